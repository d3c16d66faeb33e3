"""Variable projection: fit nonlinear parameters phi with the linear theta solved exactly inside.

For ``y = F(phi) theta + g + noise`` with g in a subspace class, the reduced residual
``r(phi) = (I - P) y - (I - P) F(phi) theta_hat(phi)`` depends on phi only; minimising it over
phi gives the joint least-squares optimum (Golub & Pereyra 1973), with half the parameters and
a better-conditioned problem. Re-exported by :mod:`odnn_sep.core.linalg`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, Sequence

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["varpro_residual", "varpro", "VarproResult"]

#: scipy.optimize.least_squares options of the separator's phi search.
LEAST_SQUARES_OPTIONS = {"x_scale": "jac", "xtol": 1e-12, "ftol": 1e-12, "gtol": 1e-12, "max_nfev": 2000}


def varpro_residual(design: Callable[[np.ndarray], np.ndarray], y: ArrayLike, *,
                    project_out: Callable[[np.ndarray], np.ndarray] | None = None,
                    weights: ArrayLike | None = None) -> Callable[[np.ndarray], np.ndarray]:
    """The reduced residual ``phi -> sqrt(w) * ((I - P) y - (I - P) F(phi) theta_hat(phi))``.

    Parameters
    ----------
    design : callable
        ``design(phi_vector) -> F`` (n, p), the physics columns at phi.
    y : array_like, shape (n,)
        Observations.
    project_out : callable, optional
        ``v -> (I - P) v`` for the disturbance subspace (e.g. ``Projector.project_out``); None
        for the explicit-orthogonality class.
    weights : array_like, shape (n,), optional
        Least-squares weights (the returned residual is whitened: its squared norm is the
        weighted RSS).

    Returns
    -------
    callable
        ``resid(phi_vector) -> (n,)``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 30)
    >>> resid = varpro_residual(lambda v: np.exp(-v[0] * t)[:, None], 2 * np.exp(-3 * t))
    >>> float(np.abs(resid(np.array([3.0]))).max()) < 1e-12
    True
    """
    from odnn_sep.core.linalg import solve

    y = np.asarray(y, dtype=float)
    sw = None if weights is None else np.sqrt(weights)
    yp = y if project_out is None else project_out(y)

    def resid(v):
        F = design(v)
        Fp = F if project_out is None else project_out(F)
        theta = solve(Fp, yp, weights=weights, method="qr")
        r = yp - Fp @ theta
        return r if sw is None else r * sw

    return resid


@dataclass(frozen=True)
class VarproResult:
    """Best of a multi-start search: ``phi`` (q,), its ``cost`` (sum of squared residuals), the
    optimizer's result (``.jac`` is the residual Jacobian for least-squares searches) and the
    number of starts tried.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 40)
    >>> resid = varpro_residual(lambda v: np.exp(-v[0] * t)[:, None], 2 * np.exp(-3 * t))
    >>> fit = varpro(resid, [np.array([1.0]), np.array([5.0])], (np.array([0.0]), np.array([10.0])))
    >>> round(float(fit.phi[0]), 6), bool(fit.cost < 1e-20), fit.n_starts
    (3.0, True, 2)
    """

    phi: np.ndarray
    cost: float
    result: object
    n_starts: int

    @property
    def jac(self) -> np.ndarray | None:
        """Jacobian of the reduced residual at phi (None for a scalar search)."""
        return getattr(self.result, "jac", None)


def varpro(residual: Callable[[np.ndarray], np.ndarray], starts: Sequence, bounds: tuple[ArrayLike, ArrayLike], *,
           scalar: bool = False,
           **options: Any) -> VarproResult:
    """Minimise ``sum(residual(phi)^2)`` over phi inside ``bounds`` from several starts; keep the best.

    Parameters
    ----------
    residual : callable
        ``phi -> (n,)``, e.g. from :func:`varpro_residual`.
    starts : sequence of array_like, each shape (q,)
        Starting points; each is clipped into the bounds.
    bounds : (lo, hi)
        Arrays of shape (q,) (``-inf`` / ``inf`` for none).
    scalar : bool
        False: :func:`scipy.optimize.least_squares` (trust region, gives a Jacobian for standard
        errors). True: a derivative-free scalar search (Powell for one parameter, Nelder–Mead
        otherwise) for residuals that are not smooth in phi (cone classes).
    **options
        Passed to ``least_squares`` (default :data:`LEAST_SQUARES_OPTIONS`) or ``minimize``.

    Returns
    -------
    VarproResult

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 1, 40)
    >>> resid = varpro_residual(lambda v: np.exp(-v[0] * t)[:, None], 2 * np.exp(-3 * t))
    >>> fit = varpro(resid, [np.array([1.0])], (np.array([0.0]), np.array([10.0])))
    >>> round(float(fit.phi[0]), 6)
    3.0
    """
    from scipy import optimize

    lo, hi = (np.asarray(b, dtype=float) for b in bounds)
    cost = lambda v: float(np.sum(residual(v) ** 2))  # noqa: E731
    best = None
    for s in starts:
        s = np.clip(s, lo, hi)
        if scalar:
            sol = optimize.minimize(cost, s, method="Nelder-Mead" if len(lo) > 1 else "Powell",
                                    bounds=list(zip(lo, hi)), **options)
            val, v = sol.fun, sol.x
        else:
            sol = optimize.least_squares(residual, s, bounds=(lo, hi), **{**LEAST_SQUARES_OPTIONS, **options})
            val, v = 2 * sol.cost, sol.x
        if best is None or val < best[0]:
            best = (val, v, sol)
    val, v, sol = best
    return VarproResult(phi=v, cost=val, result=sol, n_starts=len(starts))
