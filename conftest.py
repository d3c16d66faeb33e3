"""Test-run set-up shared by tests/ and the docstring examples of odnn_sep (``--doctest-modules``).

Every module of the package imports without its optional packages, so collection never fails; an
example that needs one (torch for the network solver, pysindy for the SINDy anchor, ...) is skipped
with a reason when it is not installed, as the tests do with ``pytest.importorskip``.
"""
from __future__ import annotations

import importlib.util
import re

import pytest

#: Optional packages (extras of pyproject.toml) an example may import itself.
OPTIONAL = ("torch", "mne", "meegkit", "pandapower", "gymnasium", "mujoco", "dask", "pysindy", "skimage",
            "librosa", "pactools")
#: Examples that need optional packages without importing them: doctest name prefix -> packages.
NEEDS = {
    "odnn_sep.core.nets": "torch",
    "odnn_sep.core.network": "torch",
    "odnn_sep.core.baselines.regular_dnn": "torch",
    "odnn_sep.core.baselines.pinn_penalty": "torch",
    "odnn_sep.core.baselines.sindy": "pysindy",
    "odnn_sep.core.solvers.NetworkSolver": "torch",
    "odnn_sep.audio.fit.solve_block_network": "torch",
    "odnn_sep.signals.humanoid.humanoid": "gymnasium,mujoco",
    "odnn_sep.signals.humanoid.HumanoidDataset": "gymnasium,mujoco",
    "odnn_sep.signals.humanoid.collect": "gymnasium,mujoco",
    "odnn_sep.signals.humanoid_policies.make_env": "gymnasium,mujoco",
    "odnn_sep.signals.humanoid_policies.rollout": "gymnasium,mujoco",
}
#: Example helpers that need an optional package: call -> package.
CALLS = {"three_bus_feeder(": "pandapower"}
_IMPORT = re.compile(r"^\s*(?:import|from)\s+(\w+)", re.MULTILINE)


def _needed(item) -> set[str]:
    need = {pkg for prefix, pkgs in NEEDS.items() if item.name == prefix or item.name.startswith(prefix + ".")
            for pkg in pkgs.split(",")}
    source = "\n".join(ex.source for ex in item.dtest.examples)
    need |= {pkg for call, pkg in CALLS.items() if call in source}
    return need | {m for m in _IMPORT.findall(source) if m in OPTIONAL}


def _installed(pkg: str) -> bool:
    try:
        return importlib.util.find_spec(pkg) is not None
    except (ImportError, ValueError):
        return False


def pytest_collection_modifyitems(config, items):
    from _pytest.doctest import DoctestItem

    for item in items:
        if isinstance(item, DoctestItem):
            missing = sorted(p for p in _needed(item) if not _installed(p))
            if missing:
                item.add_marker(pytest.mark.skip(reason=f"the example needs {', '.join(missing)}, "
                                                        "which is not installed"))
