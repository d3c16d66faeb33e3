"""The public API has runnable examples, and every module imports without torch.

The examples themselves run in the default test command (``--doctest-modules`` over odnn_sep,
configured in pyproject.toml; conftest.py skips those whose optional package is missing).
"""
import subprocess
import sys

import odnn_sep
import odnn_sep.core
import odnn_sep.errors


def test_public_api_has_runnable_examples():
    from odnn_sep.core import linalg, solvers

    public = [getattr(odnn_sep.core, n) for n in odnn_sep.core.__all__ if n != "linalg"]
    public += [getattr(linalg, n) for n in linalg.__all__ if n != "Z95"]
    public += [getattr(solvers, n) for n in solvers.__all__]
    public += [getattr(odnn_sep.errors, n) for n in dir(odnn_sep.errors)
               if getattr(getattr(odnn_sep.errors, n), "__module__", "") == "odnn_sep.errors"]
    public += [getattr(odnn_sep, n) for n in dir(odnn_sep) if not n.startswith("_") and isinstance(getattr(odnn_sep, n), type)]
    missing = sorted({getattr(obj, "__name__", repr(obj)) for obj in public if ">>>" not in (obj.__doc__ or "")})
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


def test_every_public_function_and_class_has_an_example():
    """Module-level public functions and classes of every public module carry a runnable example."""
    import ast
    from pathlib import Path

    root = Path(odnn_sep.__file__).parent
    missing = []
    for path in sorted(root.rglob("*.py")):
        rel = path.relative_to(root)
        if any(part.startswith("_") and part != "__init__.py" for part in rel.parts):
            continue
        for node in ast.parse(path.read_text()).body:
            if isinstance(node, (ast.FunctionDef, ast.ClassDef)) and not node.name.startswith("_"):
                if ">>>" not in (ast.get_docstring(node) or ""):
                    missing.append(f"{rel}:{node.lineno} {node.name}")
    assert not missing, f"public functions/classes without an example: {missing}"
