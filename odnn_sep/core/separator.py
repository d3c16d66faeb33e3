"""The ODNN separator: y = F(phi) theta + g + noise with g confined to a disturbance class."""
from __future__ import annotations

import inspect
import logging
from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.core.base import Disturbance, Problem
from odnn_sep.core.basis import Basis
from odnn_sep.core.checks import check_basis_matrix, check_xy
from odnn_sep.core.disturbance import Orthogonal
from odnn_sep.core.linalg import orthonormal_basis
from odnn_sep.core.phi import fit_phi
from odnn_sep.core.result import Result
from odnn_sep.core.solvers import Solver, get_solver
from odnn_sep.errors import (
    InputError,
    NotFittedError,
    NotIdentifiableError,
    as_float_array,
    check_option,
    check_type,
)

log = logging.getLogger(__name__)


class Separator:
    """Separate known physics from a disturbance confined to a class that cannot imitate it.

    Parameters
    ----------
    basis : Basis or ParametricBasis
        The physics columns (and nonlinear parameters phi).
    disturbance : Disturbance, default ``Orthogonal()``
        The class g is confined to: a shipped class or a subclass of
        :class:`~odnn_sep.core.base.Disturbance`.
    solver : str or Solver
        ``"exact"``: closed-form projection (subspace classes) or shape-constrained least squares
        (cones). ``"network"``: the paper's constrained network trained by gradient descent (torch);
        it must agree with the exact solver where both apply. Any name registered with
        :func:`~odnn_sep.core.solvers.register_solver`, or a :class:`~odnn_sep.core.solvers.Solver`.
    random_state : int, optional
        Seed for the network solver, the cone bootstrap and the multi-start search; None means 0, so
        the same data and options always give the same result.
    n_starts : int
        Random starts for nonlinear parameters without a grid.
    epochs : int
        Network-solver Adam iterations (followed by L-BFGS polishing).
    lr : float
        Network-solver Adam step size.

    Attributes
    ----------
    result_ : Result
        Everything the fit found (set by :meth:`fit`).
    theta_ : ndarray
        Linear coefficients, ``result_.theta``.
    phi_ : dict
        Nonlinear parameters (empty for a linear basis).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-2, 2, 401)
    >>> y = 0.5 * x**2 * np.sin(5 * x) + np.cos(x)      # physics odd, disturbance even
    >>> r = Separator(Basis([lambda x: x**2 * np.sin(5 * x)], names=["a"]), disturbance=Even()).fit(x, y).result_
    >>> round(float(r.theta[0]), 6)
    0.5
    """

    def __init__(self, basis: Basis, disturbance: Disturbance | None = None, solver: str | Solver = "exact", *,
                 random_state: int | None = None, n_starts: int = 8, epochs: int = 1500, lr: float = 1e-2):
        self.basis = basis
        self.disturbance = disturbance
        self.solver = solver
        self.random_state = random_state
        self.n_starts = n_starts
        self.epochs = epochs
        self.lr = lr

    # -- scikit-learn estimator protocol --------------------------------------------------------
    @classmethod
    def _param_names(cls) -> list[str]:
        sig = inspect.signature(cls.__init__)
        return [n for n, p in sig.parameters.items() if n != "self" and p.kind is not p.VAR_KEYWORD]

    def get_params(self, deep: bool = True) -> dict:
        """The constructor parameters (scikit-learn protocol, so ``sklearn.base.clone`` works).

        Parameters
        ----------
        deep : bool
            Also return ``name__sub`` entries for parameters that have ``get_params`` themselves.

        Examples
        --------
        >>> from odnn_sep.core import Basis, Separator
        >>> Separator(Basis([abs], names=["a"]), epochs=10).get_params()["epochs"]
        10
        """
        out = {}
        for name in self._param_names():
            value = getattr(self, name)
            if deep and hasattr(value, "get_params") and not isinstance(value, type):
                out.update({f"{name}__{k}": v for k, v in value.get_params().items()})
            out[name] = value
        return out

    def set_params(self, **params: Any) -> "Separator":
        """Set constructor parameters (``name__sub`` reaches into a parameter with ``set_params``); returns self.

        Examples
        --------
        >>> from odnn_sep.core import Basis, Even, Separator
        >>> Separator(Basis([abs], names=["a"])).set_params(disturbance=Even(), n_starts=2).n_starts
        2
        """
        valid = self._param_names()
        nested: dict = {}
        for key, value in params.items():
            name, _, sub = key.partition("__")
            check_option("parameter", name, valid)
            if sub:
                nested.setdefault(name, {})[sub] = value
            else:
                setattr(self, name, value)
        for name, sub_params in nested.items():
            target = getattr(self, name)
            if not hasattr(target, "set_params"):
                raise InputError(f"{name} ({type(target).__name__}) has no parameters to set; got {sorted(sub_params)}")
            target.set_params(**sub_params)
        return self

    def __repr__(self) -> str:
        args = ", ".join(f"{k}={v!r}" for k, v in self.get_params(deep=False).items())
        return f"{type(self).__name__}({args})"

    def predict(self, x: ArrayLike) -> np.ndarray:
        """The fitted physics ``F(x; phi_) @ theta_`` at sample points ``x`` (new or the fitted ones).

        Parameters
        ----------
        x : array_like, shape (m,) or (m, d)
            Sample points, with the dimensionality used in :meth:`fit`.

        Returns
        -------
        ndarray, shape (m,)

        Raises
        ------
        NotFittedError
            Before :meth:`fit`.
        NotIdentifiableError
            When theta is only set-identified (cone classes): there is no single physics curve.

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.core import Basis, Even, Separator
        >>> x = np.linspace(-1, 1, 51)
        >>> sep = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, 3 * x + np.cos(4 * x))
        >>> sep.predict(np.array([2.0])).round(9).tolist()
        [6.0]
        """
        if not hasattr(self, "result_"):
            raise NotFittedError(f"this {type(self).__name__} is not fitted yet; call fit(x, y) before predict")
        if self.result_.identified != "point":
            raise NotIdentifiableError(
                f"theta is only set-identified with the {self.result_.disturbance_class} disturbance class, so the "
                "physics at new x is not one curve; evaluate basis.evaluate(x, phi_) @ theta for thetas inside "
                "result_.interval instead")
        x = as_float_array("x", x, ndim=(1, 2))
        d = 1 if x.ndim == 1 else x.shape[1]
        if d != self.n_features_in_:
            raise InputError(f"x has {d} coordinate(s) per sample but the separator was fitted with "
                             f"{self.n_features_in_}; pass x of the same dimensionality")
        return self.basis.evaluate(x, self.phi_) @ self.theta_

    # ------------------------------------------------------------------------------------------
    def _validate(self) -> tuple[Disturbance, Solver]:
        check_type("basis", self.basis, Basis, "an odnn_sep.core.Basis")
        dist = Orthogonal() if self.disturbance is None else self.disturbance
        check_type("disturbance", dist, Disturbance,
                   "a Disturbance instance (Orthogonal(), Even(), Periodic(T), Band(lo, hi), Subspace(G), "
                   "Convex(), Monotone() or a subclass of odnn_sep.core.base.Disturbance)")
        for name, low in (("n_starts", 1), ("epochs", 0)):
            value = getattr(self, name)
            check_type(name, value, (int, np.integer), "an integer")
            if value < low:
                raise InputError(f"{name} must be >= {low}; got {value!r}")
        check_type("lr", self.lr, (int, float, np.floating), "a number")
        if not (np.isfinite(self.lr) and self.lr > 0):
            raise InputError(f"lr must be a finite number > 0; got {self.lr!r}")
        solver = get_solver(self.solver, epochs=self.epochs, lr=self.lr)
        if not solver.supports(dist):
            raise InputError(f"solver {solver.name!r} does not handle the {dist.describe()} disturbance class; "
                             "use solver='exact' or another solver")
        return dist, solver

    def fit(self, x: ArrayLike, y: ArrayLike, weights: ArrayLike | None = None) -> "Separator":
        """Fit theta (and phi) to ``y`` sampled at ``x``.

        Parameters
        ----------
        x : array_like, shape (n,) or (n, d)
            Sample points.
        y : array_like, shape (n,)
            Observations.
        weights : array_like, shape (n,), optional
            Non-negative least-squares weights (only for classes that support them: ``Orthogonal``).

        Returns
        -------
        self
        """
        dist, solver = self._validate()
        x, y, weights = check_xy(x, y, weights)
        dist.check_inputs(x, weights)
        names = self.basis.names
        prepared = dist.prepare(x)
        check_basis_matrix(self.basis.evaluate(x), names, n_extra=len(self.basis.phi_names))

        phi, phi_info = {}, {}
        if self.basis.is_parametric:
            phi, phi_info = fit_phi(self.basis, dist, x, y, weights, prepared, n_starts=self.n_starts,
                                    random_state=self.random_state)
        F = self.basis.evaluate(x, phi)
        check_basis_matrix(F, names)
        problem = Problem(F=F, x=x, y=y, weights=weights, names=names, disturbance=dist, prepared=prepared,
                          random_state=self.random_state)
        out = solver.solve(problem)
        if "cov" in phi_info:
            out = self._with_phi_uncertainty(out, problem, phi, phi_info)
        self.result_ = self._result(problem, out, solver, phi, phi_info)
        self.theta_ = self.result_.theta
        self.phi_ = phi
        self.n_features_in_ = 1 if x.ndim == 1 else x.shape[1]
        return self

    def _with_phi_uncertainty(self, out: dict, problem: Problem, phi: dict, phi_info: dict) -> dict:
        """``out`` with theta's errors and intervals widened by the uncertainty of the fitted phi
        (:func:`odnn_sep.core.phi.theta_stderr_with_phi`); theta itself is unchanged."""
        import warnings
        from dataclasses import replace

        from odnn_sep.core.linalg import intervals
        from odnn_sep.core.phi import theta_stderr_with_phi
        from odnn_sep.core.solvers import ExactSolver

        keys = self.basis.phi_names

        def theta_at(v):
            F = self.basis.evaluate(problem.x, dict(zip(keys, v)))
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")       # the fit itself has said what there is to say
                return ExactSolver().solve(replace(problem, F=F))["theta"]

        stderr = theta_stderr_with_phi(theta_at, np.array([phi[k] for k in keys]), phi_info["cov"], out["stderr"])
        # t on the degrees of freedom left after phi as well
        return {**out, "stderr": stderr, "interval": intervals(out["theta"], stderr, dof=phi_info["dof"])}

    def _result(self, problem: Problem, out: dict, solver: Solver, phi: dict, phi_info: dict) -> Result:
        F, y = problem.F, problem.y
        diag = dict(out.get("diagnostics", {}))
        diag.update(phi_info.get("diagnostics", {}))
        g = out["disturbance"]
        g_norm = float(np.linalg.norm(g))
        if g_norm > 0:
            # how much of the estimated disturbance lies in span(F): that part would have gone into theta
            Q = orthonormal_basis(F, method="qr", rtol=None)
            diag["disturbance_in_basis_span"] = float(np.linalg.norm(Q.T @ g)) / g_norm
        return Result(
            theta=out["theta"], names=problem.names, stderr=out["stderr"], interval=out["interval"],
            physics=F @ out["theta"], disturbance=g, residual=y - F @ out["theta"] - g,
            solver=solver.name, disturbance_class=problem.disturbance.describe(),
            identified=problem.disturbance.identification,
            phi=phi, phi_stderr=phi_info.get("stderr", {}),
            loss_history=tuple(out.get("loss_history", ())), converged=bool(out.get("converged", True)),
            diagnostics=diag,
        )
