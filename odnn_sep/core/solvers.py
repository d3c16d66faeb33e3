"""Solvers as objects, and the registry through which a front-end plugs in a specialised one.

A solver turns a :class:`~odnn_sep.core.base.Problem` (physics columns, data, disturbance class)
into theta with uncertainty and the disturbance estimate. :class:`ExactSolver` asks the class for
its exact solution; :class:`NetworkSolver` trains the paper's constrained network (torch, imported
only when it runs) and takes its uncertainty from the exact analysis of the same problem.
``Separator(solver=...)`` accepts a :class:`Solver` instance or a registered name.

Examples
--------
>>> from odnn_sep.core.solvers import ExactSolver, get_solver, register_solver, registered_solvers
>>> class LoudExact(ExactSolver):
...     name = "loud-exact"
>>> register_solver("loud-exact", LoudExact)
>>> type(get_solver("loud-exact")).__name__, "exact" in registered_solvers()
('LoudExact', True)
>>> unregister_solver("loud-exact")
"""
from __future__ import annotations

import abc
import inspect
from typing import Any, Callable, ClassVar

from odnn_sep.core.base import Disturbance, Problem
from odnn_sep.core.linalg import intervals
from odnn_sep.errors import InputError, check_option, check_type

__all__ = ["Solver", "ExactSolver", "NetworkSolver", "register_solver", "unregister_solver", "get_solver",
           "registered_solvers"]


class Solver(abc.ABC):
    """Interface of a separation solver.

    ``solve`` returns a dict with ``theta`` (p,), ``stderr`` (p,), ``interval`` (p, 2),
    ``disturbance`` (n,), ``diagnostics`` (dict) and optionally ``loss_history`` and ``converged``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Orthogonal, Separator
    >>> class OrdinaryLeastSquares(Solver):        # a specialised solver for the Orthogonal class
    ...     name = "ols"
    ...     def supports(self, disturbance):
    ...         return isinstance(disturbance, Orthogonal)
    ...     def solve(self, problem):
    ...         theta = np.linalg.lstsq(problem.F, problem.y, rcond=None)[0]
    ...         zeros = np.zeros_like(theta)
    ...         return {"theta": theta, "stderr": zeros, "interval": np.c_[theta, theta],
    ...                 "disturbance": problem.y - problem.F @ theta, "diagnostics": {}}
    >>> x = np.linspace(0, 1, 10)
    >>> Separator(Basis([lambda x: x], names=["a"]), solver=OrdinaryLeastSquares()).fit(x, 4 * x).theta_.round(9)
    array([4.])
    """

    #: Name recorded in :attr:`Result.solver <odnn_sep.core.result.Result>`.
    name: ClassVar[str] = "solver"

    def supports(self, disturbance: Disturbance) -> bool:
        """Whether this solver can handle the class (a specialised solver may refuse some)."""
        return True

    @abc.abstractmethod
    def solve(self, problem: Problem) -> dict:
        """Solve one separation problem."""


class ExactSolver(Solver):
    """Closed-form projection for linear classes, shape-constrained least squares for cones.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 21)
    >>> sep = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even(), solver=ExactSolver())
    >>> round(float(sep.fit(x, 2 * x + x**2).theta_[0]), 9)
    2.0
    """

    name: ClassVar[str] = "exact"

    def solve(self, problem: Problem) -> dict:
        return problem.disturbance.fit_exact(problem)


class NetworkSolver(Solver):
    """The paper's constrained network trained jointly with theta (Adam, then L-BFGS), in torch.

    Parameters
    ----------
    epochs : int
        Adam iterations before the L-BFGS polish.
    lr : float
        Adam step size for theta (the network's is 0.3 times it).
    hidden, depth : int
        Width and number of hidden layers of the disturbance network.
    progress : bool
        Show a progress bar of the training epochs on stderr.

    Its theta must agree with the exact solver's where both apply; its standard errors and
    identified sets come from the exact analysis of the same problem.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 41)
    >>> sep = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even(), solver=NetworkSolver(epochs=20))
    >>> round(float(sep.fit(x, 2 * x + x**2).theta_[0]), 4)
    2.0
    """

    name: ClassVar[str] = "network"

    def __init__(self, epochs: int = 1500, lr: float = 1e-2, hidden: int = 32, depth: int = 3,
                 progress: bool = False):
        self.epochs, self.lr, self.hidden, self.depth = epochs, lr, hidden, depth
        self.progress = progress

    def solve(self, problem: Problem) -> dict:
        from odnn_sep.core.nets import require_torch
        from odnn_sep.core.network import fit_network

        require_torch()

        out = fit_network(problem.F, problem.x, problem.y, problem.disturbance, problem.prepared,
                          weights=problem.weights, random_state=problem.random_state, epochs=self.epochs,
                          lr=self.lr, hidden=self.hidden, depth=self.depth, progress=self.progress)
        exact = ExactSolver().solve(problem)
        out["stderr"], out["interval_exact"] = exact["stderr"], exact["interval"]
        out["diagnostics"] = {**exact["diagnostics"], **out.get("diagnostics", {}),
                              "exact_theta": exact["theta"].tolist()}
        if problem.disturbance.identification == "set":
            out["interval"] = exact["interval"]
        else:
            out["interval"] = intervals(out["theta"], exact["stderr"])
        return out


_REGISTRY: dict[str, Callable[..., Solver]] = {"exact": ExactSolver, "network": NetworkSolver}


def register_solver(name: str, factory: Callable[..., Solver], *, replace: bool = False) -> None:
    """Make ``Separator(solver=name)`` build its solver with ``factory(**options)``.

    ``factory`` is a Solver subclass or any callable returning a :class:`Solver`; it receives the
    separator options it names among ``epochs`` and ``lr``. The built-in names cannot be replaced.

    Parameters
    ----------
    name : str
        The name ``Separator(solver=...)`` will accept.
    factory : callable
        A :class:`Solver` subclass, or a callable returning a Solver.
    replace : bool, optional
        Allow replacing a solver registered earlier under ``name`` (never a built-in).

    Raises
    ------
    odnn_sep.errors.InputError
        For a name taken (without ``replace``) or built in, or a factory that is not callable.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, ExactSolver, Orthogonal, Separator
    >>> class TracedExact(ExactSolver):          # e.g. a front-end's fast path for its own problems
    ...     name = "traced-exact"
    >>> register_solver("traced-exact", TracedExact, replace=True)
    >>> x = np.linspace(0, 1, 50)
    >>> sep = Separator(Basis([lambda x: x], names=["a"]), disturbance=Orthogonal(), solver="traced-exact")
    >>> round(float(sep.fit(x, 3 * x).theta_[0]), 9)
    3.0
    >>> unregister_solver("traced-exact")
    >>> register_solver("exact", TracedExact)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: a solver named 'exact' is already registered; pick another name
    """
    check_type("name", name, str)
    if name in ("exact", "network") or (name in _REGISTRY and not replace):
        raise InputError(f"a solver named {name!r} is already registered; pick another name"
                         + ("" if name in ("exact", "network") else " or pass replace=True"))
    if not callable(factory):
        raise InputError(f"factory must be callable (a Solver subclass); got {factory!r}")
    _REGISTRY[name] = factory


def unregister_solver(name: str) -> None:
    """Remove a solver added with :func:`register_solver` (the built-in ``exact`` and ``network`` stay).

    Parameters
    ----------
    name : str
        A name added with :func:`register_solver`.

    Raises
    ------
    odnn_sep.errors.InputError
        For a built-in or unknown name.

    Examples
    --------
    >>> register_solver("scratch", ExactSolver)
    >>> unregister_solver("scratch")
    >>> "scratch" in registered_solvers()
    False
    """
    if name in ("exact", "network"):
        raise InputError(f"the built-in solver {name!r} cannot be removed")
    check_option("name", name, tuple(n for n in _REGISTRY if n not in ("exact", "network")))
    del _REGISTRY[name]


def registered_solvers() -> tuple[str, ...]:
    """Names ``Separator(solver=...)`` accepts.

    Examples
    --------
    >>> registered_solvers()[:2]
    ('exact', 'network')
    """
    return tuple(_REGISTRY)


def get_solver(spec: str | Solver, **options: Any) -> Solver:
    """The solver for ``spec``: a :class:`Solver` instance is returned as is; a name is built from the
    registry with the ``options`` its factory accepts (``epochs``, ``lr`` for the network solver).

    Parameters
    ----------
    spec : str or Solver
        A registered name (``"exact"``, ``"network"``, ...) or a ready solver.
    **options
        Separator options (``epochs``, ``lr``); each is passed only if the factory accepts it.

    Returns
    -------
    Solver

    Raises
    ------
    odnn_sep.errors.InputError
        For an unknown name, or a factory that does not return a Solver.

    Examples
    --------
    >>> get_solver("network", epochs=10, lr=0.1).epochs
    10
    """
    if isinstance(spec, Solver):
        return spec
    check_type("solver", spec, str, "a registered name or a Solver instance")
    check_option("solver", spec, tuple(_REGISTRY))
    factory = _REGISTRY[spec]
    try:
        params = inspect.signature(factory).parameters
    except (TypeError, ValueError):  # pragma: no cover - builtins without a signature
        params = {}
    takes_all = any(p.kind is p.VAR_KEYWORD for p in params.values())
    solver = factory(**{k: v for k, v in options.items() if takes_all or k in params})
    if not isinstance(solver, Solver):
        raise InputError(f"the factory registered as {spec!r} returned {type(solver).__name__}, not a Solver")
    return solver
