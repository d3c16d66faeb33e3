"""Nonlinear parameters phi of a ParametricBasis: starting points, the variable-projection search, errors.

The search itself is :func:`odnn_sep.core.linalg.varpro`; the residual it minimises comes from the
disturbance class (:meth:`~odnn_sep.core.base.Disturbance.reduced_residual`), so theta and the
class's part are solved exactly inside for every phi.
"""
from __future__ import annotations

import itertools
import warnings
from typing import TYPE_CHECKING, Callable

import numpy as np

from odnn_sep.core.linalg import standard_errors, varpro
from odnn_sep.errors import IdentifiabilityWarning, InputError

if TYPE_CHECKING:
    from odnn_sep.core.base import Disturbance
    from odnn_sep.core.basis import Basis

__all__ = ["MAX_GRID_POINTS", "phi_starts", "fit_phi"]

#: Largest phi grid searched point by point.
MAX_GRID_POINTS = 5000


def phi_starts(basis: Basis, cost: Callable[[np.ndarray], float] | None, *, n_starts: int,
               random_state: int | None = None) -> list[np.ndarray]:
    """Starting points for the phi search: phi0, then the 3 best grid points (when the basis has a
    grid) or ``n_starts - 1`` uniform draws inside finite bounds.

    Parameters
    ----------
    basis : ParametricBasis
        With ``phi0``, ``bounds`` and optionally a ``grid``.
    cost : callable or None
        ``phi -> cost``, used to rank the grid points (needed only with a grid).
    n_starts : int
        Number of starts without a grid.
    random_state : int, optional
        Seed of the uniform draws (0 when None).

    Returns
    -------
    list of ndarray

    Raises
    ------
    odnn_sep.errors.InputError
        For a grid of more than ``MAX_GRID_POINTS`` points.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import ParametricBasis
    >>> pb = ParametricBasis(lambda x, xp=np, f=1.0: xp.sin(f * x), {"f": 1.0}, names=["a"], bounds={"f": (0, 2)})
    >>> len(phi_starts(pb, cost=None, n_starts=4, random_state=0))
    4
    """
    keys = basis.phi_names
    lo = np.array([basis.bounds[k][0] for k in keys], dtype=float)
    hi = np.array([basis.bounds[k][1] for k in keys], dtype=float)
    starts = [np.array([basis.phi0[k] for k in keys])]
    grid = basis.grid
    if grid:
        axes = [np.asarray(grid.get(k, [basis.phi0[k]]), dtype=float) for k in keys]
        cand = list(itertools.product(*axes))
        if len(cand) > MAX_GRID_POINTS:
            raise InputError(f"the phi grid has {len(cand)} points; keep it under {MAX_GRID_POINTS} "
                             "(coarsen the grid)")
        costs = [cost(np.array(c)) for c in cand]
        starts += [np.array(cand[i]) for i in np.argsort(costs)[:3]]
    elif np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and n_starts > 1:
        rng = np.random.default_rng(0 if random_state is None else random_state)   # reproducible by default
        starts += [lo + (hi - lo) * rng.random(len(keys)) for _ in range(n_starts - 1)]
    return starts


def fit_phi(basis: Basis, dist: Disturbance, x: np.ndarray, y: np.ndarray, weights: np.ndarray | None,
            prepared: object, *, n_starts: int, random_state: int | None = None) -> tuple[dict, dict]:
    """Best phi by variable projection; returns ``(phi, {"stderr": ..., "diagnostics": ...})``.

    Standard errors come from the Jacobian of the reduced residual (point-identified classes only;
    the projected-out theta is accounted for by variable projection). Warns when phi ends on a bound.

    Parameters
    ----------
    basis : ParametricBasis
    dist : Disturbance
        The disturbance class.
    x, y : ndarray
        Coordinates and data.
    weights : ndarray or None
    prepared : object
        The class prepared for ``x`` (its projector), or None.
    n_starts : int
        Starts of the local search (see :func:`phi_starts`).
    random_state : int, optional

    Returns
    -------
    phi : dict
        Name -> value.
    info : dict
        ``stderr`` of phi and ``diagnostics``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Orthogonal, ParametricBasis
    >>> t = np.linspace(0, 1, 50)
    >>> pb = ParametricBasis(lambda t, xp=np, k=1.0: xp.exp(-k * t), {"k": 1.0}, names=["a"], bounds={"k": (0, 10)})
    >>> phi, info = fit_phi(pb, Orthogonal(), t, 2 * np.exp(-3 * t), None, None, n_starts=1)
    >>> round(phi["k"], 6)
    3.0
    """
    keys = basis.phi_names
    lo = np.array([basis.bounds[k][0] for k in keys], dtype=float)
    hi = np.array([basis.bounds[k][1] for k in keys], dtype=float)
    design = lambda v: basis.evaluate(x, dict(zip(keys, v)))  # noqa: E731
    resid, scalar = dist.reduced_residual(design, x, y, weights, prepared)
    cost = lambda v: float(np.sum(resid(v) ** 2))  # noqa: E731
    starts = phi_starts(basis, cost, n_starts=n_starts, random_state=random_state)
    best = varpro(resid, starts, (lo, hi), scalar=scalar)
    v = best.phi
    phi = dict(zip(keys, (float(t) for t in v)))
    at_bound = [k for k, t, a, b in zip(keys, v, lo, hi) if np.isclose(t, a) or np.isclose(t, b)]
    if at_bound:
        warnings.warn(f"nonlinear parameter(s) {at_bound} ended on their bounds; widen the bounds",
                      IdentifiabilityWarning, stacklevel=4)
    stderr, cov = {}, None
    if dist.identification == "point" and best.jac is not None:
        r = resid(v)
        dof = r.size - len(keys) - basis.n_columns - dist.nuisance_rank(prepared)
        if dof > 0:
            try:
                stderr = dict(zip(keys, standard_errors(best.jac, r, dof).tolist()))
                # the whole covariance, for theta's errors (theta moves with phi: theta_stderr_with_phi)
                cov = np.linalg.pinv(best.jac.T @ best.jac) * float(r @ r / dof)
            except np.linalg.LinAlgError:
                stderr, cov = {}, None
    info = {"stderr": stderr, "diagnostics": {"phi_starts": len(starts), "phi_cost": float(best.cost)}}
    if stderr and cov is not None and np.isfinite(cov).all():
        info["cov"], info["dof"] = cov, dof
    return phi, info


def theta_stderr_with_phi(theta_at: Callable[[np.ndarray], np.ndarray], phi: np.ndarray, phi_cov: np.ndarray,
                          stderr: np.ndarray) -> np.ndarray:
    """Standard errors of theta that include the uncertainty of the fitted phi.

    ``stderr`` holds theta's errors with phi fixed at its estimate. Theta is solved exactly for each
    phi, ``theta(phi)``; to first order its error is the one at fixed phi plus ``D (phi_hat - phi)``
    with ``D = d theta / d phi``, and the two parts are uncorrelated (phi's variable-projection
    residual is orthogonal to the basis columns), so ``Var = stderr**2 + diag(D cov(phi) D^T)``.
    Leaving the second part out gave N0 of ``N0 exp(mu t)`` intervals that held the truth in 20 % of
    draws instead of 95 %.

    Parameters
    ----------
    theta_at : callable
        ``phi vector -> theta`` solved with phi fixed.
    phi : (q,) ndarray
        The fitted phi.
    phi_cov : (q, q) ndarray
        Its covariance.
    stderr : (p,) ndarray
        Theta's standard errors at fixed phi.

    Returns
    -------
    (p,) ndarray

    Examples
    --------
    >>> import numpy as np
    >>> theta_at = lambda v: np.array([2.0 * v[0]])            # theta moves twice as fast as phi
    >>> theta_stderr_with_phi(theta_at, np.array([1.0]), np.array([[0.09]]), np.array([0.4])).round(6).tolist()
    [0.72111]
    """
    phi = np.asarray(phi, dtype=float)
    D = np.empty((np.size(stderr), phi.size))
    for k in range(phi.size):
        # a step well inside phi's own uncertainty, where theta(phi) is close to linear
        h = 1e-3 * float(np.sqrt(phi_cov[k, k])) or 1e-7 * (1.0 + abs(phi[k]))
        e = np.zeros_like(phi)
        e[k] = h
        D[:, k] = (np.asarray(theta_at(phi + e)) - np.asarray(theta_at(phi - e))) / (2 * h)
    extra = np.einsum("ik,kl,il->i", D, phi_cov, D)
    return np.sqrt(np.asarray(stderr, dtype=float) ** 2 + np.maximum(extra, 0.0))
