"""The power-grid and humanoid recipes refuse draw counts and case lists that leave nothing to run.

``--seeds 0`` (or a negative count) ran no draw and, without ``--no-write``, wrote a table of nan over the
recipe's section of BENCHMARKS.md (power grid: a KeyError traceback after the table); ``--cases ,``
printed an empty table with exit 0.
"""
import importlib.util
import sys
from pathlib import Path

import pytest

RECIPES = Path(__file__).resolve().parents[2] / "recipes"


def _recipe(name):
    sys.path.insert(0, str(RECIPES))
    try:
        spec = importlib.util.spec_from_file_location(f"_recipe_{name}", RECIPES / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
    finally:
        sys.path.remove(str(RECIPES))
    return mod


@pytest.mark.parametrize("name, argv, says", [
    ("power_grid", ["--seeds", "0"], "--seeds: must be >= 1"),
    ("power_grid", ["--seeds", "-2"], "--seeds: must be >= 1"),
    ("power_grid", ["--snapshots", "0"], "--snapshots: must be >= 1"),
    ("power_grid", ["--cases", ","], "--cases ',': give one or more of case14, case33bw"),
    ("power_grid", ["--cases", "case14,case9"], "give one or more of case14, case33bw"),
    ("humanoid", ["--seeds", "0"], "--seeds: must be >= 1"),
])
def test_refused_before_any_work(name, argv, says, capsys):
    with pytest.raises(SystemExit) as exc:
        _recipe(name).main([*argv, "--no-write"])
    assert exc.value.code == 2
    assert says in capsys.readouterr().err
