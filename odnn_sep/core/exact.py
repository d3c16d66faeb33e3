"""Exact solutions of one separation problem: projection for linear classes, cone fits for shape classes.

Called by the disturbance families (:class:`~odnn_sep.core.base.SubspaceDisturbance`,
``Orthogonal``, :class:`~odnn_sep.core.base.ConeDisturbance`) through
:class:`~odnn_sep.core.solvers.ExactSolver`. Each returns the solver dict the separator turns into a
:class:`~odnn_sep.core.result.Result`: ``theta``, ``stderr``, ``interval``, ``disturbance``,
``diagnostics`` (and ``cov`` for linear classes).
"""
from __future__ import annotations

import warnings
from typing import TYPE_CHECKING

import numpy as np

from odnn_sep.core import cone
from odnn_sep.core.checks import check_outside_class, require_outside_class
from odnn_sep.core.linalg import Z95, Projector, intervals, noise_variance, solve, stderr_from_cov
from odnn_sep.errors import IdentifiabilityWarning, NotIdentifiableError

if TYPE_CHECKING:  # the families import this module on use
    from odnn_sep.core.base import Problem
    from odnn_sep.core.projection import BaseProjector

__all__ = ["fit_linear_class", "fit_cone_class"]


def fit_linear_class(problem: Problem, projector: BaseProjector | None = None) -> dict:
    """Theta by least squares of ``(I - P) y`` on ``(I - P) F``; ``projector=None`` is explicit orthogonality.

    With explicit orthogonality g absorbs everything outside span(F) (``g = y - F theta``) and the
    noise level comes from the fit residual, which treats g as noise (conservative when g is not
    exactly orthogonal). With a subspace class, g is the class's part of ``y - F theta`` and the
    degrees of freedom also lose the class's rank.

    Parameters
    ----------
    problem : Problem
        Basis matrix, data, weights, names and the disturbance class.
    projector : BaseProjector, optional
        Projector onto the class's subspace; None for explicit orthogonality.

    Returns
    -------
    dict
        ``theta``, ``stderr``, ``interval`` (p, 2), ``disturbance`` (n,), ``diagnostics`` (noise level,
        degrees of freedom, class rank, outside-class report) and ``cov`` (p, p).

    Raises
    ------
    odnn_sep.errors.NotIdentifiableError
        When a basis column lies (nearly) inside the class.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Even, Problem
    >>> x = np.linspace(-1, 1, 21)
    >>> problem = Problem(np.c_[x], x, 2 * x + x**2, None, ("a",), Even())
    >>> out = fit_linear_class(problem, Even().projector(x))
    >>> round(float(out["theta"][0]), 9), out["diagnostics"]["disturbance_rank"]
    (2.0, 11)
    """
    F, y, weights, names = problem.F, problem.y, problem.weights, problem.names
    desc = problem.disturbance.describe()
    n = F.shape[0]
    if projector is None:
        Fp, yp, rank_g = F, y, 0
    else:
        Fp, yp, rank_g = projector.project_out(F), projector.project_out(y), projector.rank
    diag = check_outside_class(F, Fp, names, desc)
    theta, cov_u, rank = solve(Fp, yp, weights=weights, method="qr", return_cov=True)
    if rank < Fp.shape[1]:
        theta, cov_u, rank = _solve_scaled(Fp, yp, weights, names)
    r = yp - Fp @ theta
    if projector is None:
        dof = n - rank
        sigma2 = noise_variance(r, dof, np.ones(n) if weights is None else weights)
        disturbance = y - F @ theta
    else:
        dof = n - rank_g - rank
        sigma2 = noise_variance(r, dof)
        disturbance = projector.project(y - F @ theta)
    stderr = stderr_from_cov(cov_u, sigma2)
    diag.update({"sigma": float(np.sqrt(sigma2)) if np.isfinite(sigma2) else None, "dof": int(dof),
                 "disturbance_rank": int(rank_g)})
    return {"theta": theta, "stderr": stderr, "interval": intervals(theta, stderr, dof=dof),
            "disturbance": disturbance, "diagnostics": diag, "cov": cov_u * sigma2}


def _solve_scaled(Fp: np.ndarray, yp: np.ndarray, weights, names):
    """:func:`solve` on unit-norm columns, for columns of far different sizes.

    The pivoted QR drops a column whose pivot is below 1e-12 of the largest times n: beside x**10 on
    [0, 10] (norm 1e11) it dropped sin(3x) and reported its coefficient as 0 +- 0. The columns passed
    the collinearity check on unit-norm columns, so they are independent once scaled.
    """
    s = np.linalg.norm(Fp, axis=0)
    theta, cov_u, rank = solve(Fp / s, yp, weights=weights, method="qr", return_cov=True)
    if rank < Fp.shape[1]:
        raise NotIdentifiableError(f"the basis columns {list(names)} are numerically dependent once the class is "
                                   "projected out; theta is not identifiable: drop a column or change the class")
    return theta / s, cov_u / np.outer(s, s), rank


def fit_cone_class(problem: Problem) -> dict:
    """Identified intervals and their centre for a cone class (see :mod:`odnn_sep.core.cone`).

    Warns (IdentifiabilityWarning) when an interval is wider than 5 % of its centre.

    Parameters
    ----------
    problem : Problem
        With a cone class (``Convex`` or ``Monotone``) as its disturbance.

    Returns
    -------
    dict
        ``theta`` (interval centres), ``stderr`` (half-widths / 1.96), ``interval`` (p, 2),
        ``disturbance`` (n,) and ``diagnostics`` (least-squares theta, minimal RSS, noise level, cone
        generators, relative widths).

    Examples
    --------
    >>> import warnings
    >>> import numpy as np
    >>> from odnn_sep.core import Monotone, Problem
    >>> x = np.linspace(0, 1, 30)
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore")
    ...     out = fit_cone_class(Problem(np.c_[np.sin(9 * x)], x, x + np.sin(9 * x), None, ("s",), Monotone(), None, 0))
    >>> bool(out["interval"][0, 0] <= 1 <= out["interval"][0, 1])
    True
    """
    dist, names = problem.disturbance, problem.names
    # a column inside the class's free part (a line for Convex, a constant for Monotone), or a dependent
    # set of columns, leaves theta free in both directions: refused as for a linear class
    order = np.argsort(problem.x, kind="stable")
    A_free, _ = dist.generators(problem.x[order])
    F_sorted = problem.F[order]
    require_outside_class(F_sorted, Projector(A_free, method="qr", rtol=None).project_out(F_sorted), names,
                          dist.describe())
    c = cone.fit_cone(problem.F, problem.x, problem.y, dist, random_state=problem.random_state)
    _refuse_open_sides(c["interval"], names, dist.describe())
    width = c["interval"][:, 1] - c["interval"][:, 0]
    rel = width / np.maximum(np.abs(c["theta_mid"]), 1e-300)
    if np.any(rel > 0.05):
        # 7 significant digits: rounding to 6 decimals wrote a set of coefficients near 1e-10 as [0.0, 0.0]
        shown = dict(zip(names, [[float(f"{v:.7g}") for v in row] for row in c["interval"]]))
        warnings.warn(
            f"theta is only set-identified with the {dist.describe()} disturbance class: identified "
            f"intervals {shown} (relative widths "
            f"{np.round(rel, 3).tolist()}); the point estimate is the interval centre",
            IdentifiabilityWarning, stacklevel=5,
        )
    if c["noise_dof"] <= MIN_CONE_NOISE_DOF:
        exact = c["rss_min"] <= 1e-20 * max(float(problem.y @ problem.y), 1e-300)
        warnings.warn(few_noise_dof_message(dist.describe(), problem.y.size, c["active"], c["noise_dof"], exact,
                                            from_differences=c["noise_from"] == "differences"),
                      IdentifiabilityWarning, stacklevel=5)
    return {"theta": c["theta_mid"], "stderr": width / (2 * Z95), "interval": c["interval"],
            "disturbance": c["g"],
            "diagnostics": {"theta_least_squares": c["theta_ls"].tolist(), "rss_min": c["rss_min"],
                            "sigma": float(np.sqrt(c["sigma2"])), "sigma_from": c["noise_from"],
                            "active_cone_generators": c["active"],
                            "cone_generators": c["generators"], "exact_cone": c["exact_cone"],
                            "interval_relative_width": rel.tolist()}}


#: Residual degrees of freedom of a cone fit at or below which its noise level is not trusted: on
#: simulated convex/monotone records of 20-200 points the identified set held the truth in 77-84 % of
#: fits with at most 2 left and 71-91 % with 3-5, against 82-100 % above (noise from the residual
#: alone; the difference-based floor of ``cone.fit_cone`` now takes over there, and the warning says so).
MIN_CONE_NOISE_DOF = 5


def few_noise_dof_message(desc: str, n: int, active: int, dof: int, exact: bool = False, *,
                          from_differences: bool = False) -> str:
    """The warning for a cone fit that leaves too few points to estimate the noise.

    Parameters
    ----------
    desc : str
        The class, as its ``describe()`` says it.
    n, active, dof : int
        Points, active cone generators and the residual degrees of freedom left.
    exact : bool, optional
        The fit's residual is at rounding level (noise-free data, or noise the class absorbed whole).
    from_differences : bool, optional
        The noise level was taken from the data's point-to-point differences (larger than what the
        residual gave), so the set is not too narrow for that reason.

    Returns
    -------
    str

    Examples
    --------
    >>> few_noise_dof_message("convex", 20, 15, 2)[:74]
    'the convex fit uses 15 kinks or steps on 20 points and leaves 2 degree(s) '
    """
    if exact and from_differences:
        return (f"the data lie exactly in the {desc} class with the basis (residual at rounding level): the noise "
                "level is taken from the differences between neighbouring points instead, which assumes the "
                "disturbance changes little from one point to the next; if the data are noise-free, the exact "
                "identified set is narrower than the one given")
    if exact:
        return (f"the data lie exactly in the {desc} class with the basis (residual at rounding level): the "
                "identified set is exact if they are noise-free; if they hold noise, the class absorbed it "
                f"({active} kinks or steps on {n} points) and the set is too narrow (it may miss the truth)")
    if from_differences:
        return (f"the {desc} fit uses {active} kinks or steps on {n} points and leaves {max(dof, 0)} degree(s) of "
                "freedom to estimate the noise: the noise level is taken from the differences between neighbouring "
                "points instead, which assumes the disturbance changes little from one point to the next (a "
                "disturbance with jumps widens the set); use more points for a narrower set")
    return (f"the {desc} fit uses {active} kinks or steps on {n} points and leaves {max(dof, 0)} degree(s) of "
            "freedom to estimate the noise: unless the data are noise-free, the noise is underestimated and the "
            "identified set is too narrow (it may miss the truth); use more points")


def _refuse_open_sides(interval: np.ndarray, names, desc: str) -> None:
    """NotIdentifiableError for a coefficient whose identified set is a half-line (see ``cone.open_sides``)."""
    mixed = " (with some combination of the other columns)" if len(names) > 1 else ""
    for name, (lo, hi) in zip(names, interval):
        if np.isinf(lo) or np.isinf(hi):
            bound = f"<= {hi:.6g}" if np.isinf(lo) else f">= {lo:.6g}"
            raise NotIdentifiableError(
                f"basis column {name!r}{mixed} lies inside the {desc} "
                f"disturbance class on one side: every coefficient {bound} fits the data equally well, so it is "
                "not identified; remove the column or choose a disturbance class that excludes it")
