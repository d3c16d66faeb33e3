"""A light default install: torch, dask and the dataset libraries are extras, imported lazily, and
their absence is one clear line naming the extra."""
from __future__ import annotations

import ast
import sys
from pathlib import Path

import tomllib
from robustness_helpers import write_csv, write_wav

from odnn_sep.cli import main

ROOT = Path(__file__).resolve().parents[2]
OPTIONAL = {"torch", "dask", "distributed", "mne", "meegkit", "pactools", "pandapower", "gymnasium", "pysindy",
            "skimage", "sklearn", "librosa", "jsonschema", "hypothesis"}
# Modules that may import an optional package at top level because they are only ever imported lazily.
LAZY_ONLY = {"odnn_sep/core/nets.py"}


def _top_level_imports(path: Path):
    tree = ast.parse(path.read_text())
    for node in tree.body:
        if isinstance(node, ast.Import):
            yield from (a.name.split(".")[0] for a in node.names)
        elif isinstance(node, ast.ImportFrom) and node.module and node.level == 0:
            yield node.module.split(".")[0]


def test_no_optional_package_is_imported_at_module_level():
    offenders = []
    for p in sorted((ROOT / "odnn_sep").rglob("*.py")):
        rel = str(p.relative_to(ROOT))
        if rel in LAZY_ONLY:
            continue
        bad = OPTIONAL & set(_top_level_imports(p))
        if bad:
            offenders.append(f"{rel}: {sorted(bad)}")
        tree = ast.parse(p.read_text())
        for node in tree.body:
            if isinstance(node, ast.ImportFrom) and node.module and any(
                    node.module.startswith(m[:-3].replace("/", ".")) for m in LAZY_ONLY):
                offenders.append(f"{rel}: imports {node.module} at module level")
    assert not offenders, offenders


def test_base_dependencies_are_light():
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    names = {d.split(">")[0].split("=")[0].split("<")[0].split("[")[0].strip().lower() for d in meta["dependencies"]}
    assert not names & {"torch", "librosa", "dask", "mne", "scikit-learn", "numba"}
    extras = meta["optional-dependencies"]
    assert {"network", "dask", "all", "test", "eeg", "grid", "robotics", "bench"} <= set(extras)
    assert any(d.startswith("torch") for d in extras["network"])
    test = " ".join(extras["test"])
    for need in ("hypothesis", "pysindy", "scikit-image", "jsonschema", "network", "dask", "eeg", "grid",
                 "robotics"):
        assert need in test, need


def test_network_solver_without_torch_names_the_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "torch", None)  # as if torch were not installed
    csv = write_csv(tmp_path / "d.csv")
    assert main(["separate", str(csv), "--basis", "x", "--solver", "network"]) == 1
    err = capsys.readouterr().err
    assert err.strip() == ('Error: --solver network needs torch, which is not installed; install it with: '
                           'pip install "odnn-sep[network]"')
    wav = write_wav(tmp_path / "a.wav", seconds=0.5)
    assert main(["denoise", str(wav), "-o", str(tmp_path / "b.wav"), "--solver", "network"]) == 1
    assert "odnn-sep[network]" in capsys.readouterr().err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["a.wav", "d.csv"]


def test_dask_missing_names_the_extra(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "distributed", None)
    (tmp_path / "in").mkdir()
    write_wav(tmp_path / "in" / "a.wav", seconds=0.5)
    assert main(["batch", "denoise", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--dask", "local"]) == 1
    assert 'pip install "odnn-sep[dask]"' in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
