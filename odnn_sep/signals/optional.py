"""Lazy imports of the heavy optional packages behind the grid and robotics datasets."""
from __future__ import annotations

import importlib

from odnn_sep.errors import MissingDependencyError

__all__ = ["require", "MissingDependencyError"]


def require(module: str, extra: str, what: str):
    """Import ``module`` or raise a one-line error that names the pip extra to install.

    Parameters
    ----------
    module : str
        The module to import, e.g. ``"pandapower.networks"``.
    extra : str
        The pip extra that installs it (``"grid"``, ``"robotics"``).
    what : str
        What needs it, for the message.

    Returns
    -------
    module

    Raises
    ------
    odnn_sep.errors.MissingDependencyError
        When the import fails.

    Examples
    --------
    >>> require("numpy", "grid", "the test").__name__
    'numpy'
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        raise MissingDependencyError(
            f"{what} needs the optional package {module.split('.')[0]!r} ({exc.__class__.__name__}: {exc}); "
            f'install it with: pip install "odnn-sep[{extra}]"'
        ) from None
