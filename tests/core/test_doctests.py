"""The examples in the engine's docstrings run (doctest over every module of odnn_sep.core and errors.py).

``python -m pytest -q`` collects them through this file, so the default run stays on tests/ and fast;
``python -m pytest --doctest-modules odnn_sep/core`` runs the same examples directly.
"""
import doctest
import importlib
import pkgutil
import subprocess
import sys
import warnings

import pytest

import odnn_sep.core

MODULES = sorted(["odnn_sep.errors"] + [m.name for m in pkgutil.iter_modules(odnn_sep.core.__path__, "odnn_sep.core.")])
NEEDS_TORCH = {"odnn_sep.core.baselines", "odnn_sep.core.nets", "odnn_sep.core.network"}
FLAGS = doctest.ELLIPSIS | doctest.NORMALIZE_WHITESPACE


@pytest.mark.parametrize("name", MODULES)
def test_docstring_examples_run(name):
    if name in NEEDS_TORCH:
        pytest.importorskip("torch", reason="the examples of this module train torch networks")
    module = importlib.import_module(name)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")        # examples show results; warnings are tested elsewhere
        result = doctest.testmod(module, optionflags=FLAGS, verbose=False, report=True)
    assert result.failed == 0, f"{result.failed} docstring example(s) of {name} failed (see the output above)"


def test_public_core_api_has_runnable_examples():
    from odnn_sep.core import linalg, solvers

    missing = []
    for obj in [getattr(odnn_sep.core, n) for n in odnn_sep.core.__all__ if n != "linalg"] + \
            [getattr(linalg, n) for n in linalg.__all__ if n not in ("Z95",)] + \
            [getattr(solvers, n) for n in solvers.__all__]:
        doc = getattr(obj, "__doc__", "") or ""
        if ">>>" not in doc and "has an example" not in doc:
            missing.append(getattr(obj, "__name__", repr(obj)))
    assert not missing, f"public objects without an example: {missing}"


def test_every_module_imports_without_torch():
    code = (
        "import importlib, importlib.abc, pkgutil, sys\n"
        "class Block(importlib.abc.MetaPathFinder):\n"
        "    def find_spec(self, name, path, target=None):\n"
        "        if name == 'torch' or name.startswith('torch.'):\n"
        "            raise ImportError('torch is not installed')\n"
        "sys.meta_path.insert(0, Block())\n"
        "import odnn_sep\n"
        "bad = []\n"
        "for m in pkgutil.walk_packages(odnn_sep.__path__, 'odnn_sep.'):\n"
        "    try:\n"
        "        importlib.import_module(m.name)\n"
        "    except Exception as exc:\n"
        "        bad.append(f'{m.name}: {exc}')\n"
        "print(bad)\n"
        "from odnn_sep.core import Basis, Even, Separator\n"
        "import numpy as np\n"
        "x = np.linspace(-1, 1, 21)\n"
        "print(Separator(Basis([lambda x: x], names=['a']), disturbance=Even()).fit(x, x).theta_)\n"
        "try:\n"
        "    Separator(Basis([lambda x: x], names=['a']), solver='network').fit(x, x)\n"
        "except Exception as exc:\n"
        "    print(type(exc).__name__, exc)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    lines = out.stdout.splitlines()
    assert lines[0] == "[]", lines[0]
    assert lines[-1].startswith("InputError the network solver needs torch: install the `network` extra")
