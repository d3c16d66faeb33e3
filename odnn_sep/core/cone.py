"""Shape-constrained least squares for cone disturbance classes (convex, monotone) in 1-D.

A cone cannot exclude the physics the way a subspace does: ``x^2 + c sin 5x`` stays convex for
small |c|, so every theta in an interval fits the data equally well. We therefore compute

* the least-squares fit over theta and g in the cone (NNLS after projecting out the free terms),
* the identified interval of each theta_j: the profile-RSS set
  ``{t : min RSS with theta_j = t  <=  RSS_min + chi2_1(0.95) * sigma^2}`` (plus a tiny numerical
  tolerance), found by bracketing and bisection,
* a point estimate at the interval's centre (minimax error over the identified set).
"""
from __future__ import annotations

from typing import TYPE_CHECKING, Callable, Sequence

import numpy as np

from odnn_sep.core.linalg import Projector, solve
from odnn_sep.core.uncertainty import difference_noise_variance
from odnn_sep.errors import check_type

if TYPE_CHECKING:
    from odnn_sep.core.base import ConeDisturbance

CHI2_1_95 = 3.841458820694124


MAX_KNOTS = 400


def thin_knots(inner: np.ndarray) -> np.ndarray:
    """At most ``MAX_KNOTS`` of the candidate knots ``inner``, evenly spread.

    NNLS cost grows ~ cubically with the knot count; beyond MAX_KNOTS we keep an evenly spread
    subset, i.e. an inner approximation of the cone (reported in the diagnostics).

    Parameters
    ----------
    inner : ndarray
        Candidate knots, sorted.

    Returns
    -------
    ndarray
        ``inner`` itself, or an evenly spread subset of ``MAX_KNOTS`` of them.

    Examples
    --------
    >>> import numpy as np
    >>> thin_knots(np.arange(1000.0)).size
    400
    """
    if inner.size <= MAX_KNOTS:
        return inner
    return inner[np.unique(np.linspace(0, inner.size - 1, MAX_KNOTS).round().astype(int))]


def cone_generators(x: np.ndarray, disturbance: ConeDisturbance) -> tuple[np.ndarray, np.ndarray]:
    """Return (A, H): g = A u + H d with u free and d >= 0 spans the cone on the samples.

    ``x`` must be sorted increasing; the class's own ``generators`` (see
    :class:`~odnn_sep.core.base.ConeDisturbance`).

    Parameters
    ----------
    x : ndarray
        Sample coordinates, sorted increasing.
    disturbance : ConeDisturbance
        ``Convex()``, ``Monotone()``, ...

    Returns
    -------
    A : (n, a) ndarray
        Free generators (e.g. a constant and a line).
    H : (n, h) ndarray
        Non-negative generators.

    Raises
    ------
    odnn_sep.errors.InputError
        When ``disturbance`` is not a cone class.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Monotone
    >>> [a.shape for a in cone_generators(np.arange(5.0), Monotone())]
    [(5, 1), (5, 4)]
    """
    from odnn_sep.core.base import ConeDisturbance

    check_type("disturbance", disturbance, ConeDisturbance, "a cone class (Convex(), Monotone(), ...)")
    return disturbance.generators(x)


class _ConeLS:
    """min ||y - A u - H d||^2 over free u and d >= 0, for many y with the same A and H.

    The free part is projected out once (QR), leaving a plain NNLS per right-hand side.
    """

    def __init__(self, A: np.ndarray, H: np.ndarray):
        self.A, self.H = A, H
        self.free = Projector(A, method="qr", rtol=None)
        self.Hp = self.free.project_out(H)
        # unit columns for the solve of u: lstsq's cut-off is relative to the largest singular value, and
        # x in epoch seconds (1.7e9) next to a constant column fell under it (theta off, a zero-width set)
        norms = np.linalg.norm(A, axis=0)
        self._norms = np.where(norms > 0, norms, 1.0)

    def __call__(self, y: np.ndarray):
        yp = self.free.project_out(y)
        from scipy import optimize  # (here: scipy.optimize is a tenth of a second of every start-up)

        d, rnorm = optimize.nnls(self.Hp, yp, maxiter=50 * self.H.shape[1])
        u = solve(self.A / self._norms, y - self.H @ d, method="lstsq") / self._norms
        return u, d, float(rnorm) ** 2


def _active(d: np.ndarray) -> int:
    return int((d > 1e-12 * max(1.0, np.abs(d).max(initial=0))).sum())


def _cp(sol, sigma2: float) -> float:
    """Mallows' Cp / SURE of a cone fit: RSS + 2 sigma^2 * (active generators).

    A cone absorbs more noise where the fitted shape is far from the cone's faces (a steep monotone
    g can follow noise, a flat one cannot), so the raw profile RSS is not flat across the identified
    set under noise. The number of active generators is the cone projection's degrees of freedom
    (Meyer & Woodroofe 2000); adding it back makes the criterion comparable across theta.
    """
    return sol[2] + 2.0 * sigma2 * _active(sol[1])


def cone_lstsq(A: np.ndarray, H: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """min ||y - A u - H d||^2 with d >= 0. Returns (u, d, rss).

    Parameters
    ----------
    A : (n, a) ndarray
        Free columns.
    H : (n, h) ndarray
        Columns with non-negative coefficients.
    y : (n,) ndarray

    Returns
    -------
    u : (a,) ndarray
    d : (h,) ndarray
        Non-negative.
    rss : float

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(6.0)
    >>> u, d, rss = cone_lstsq(np.ones((6, 1)), (x[:, None] >= x[None, 1:]).astype(float), np.sqrt(x))
    >>> rss < 1e-20, bool((d >= 0).all())          # sqrt(x) is non-decreasing: it lies in the cone
    (True, True)
    """
    return _ConeLS(A, H)(y)


def open_sides(F: np.ndarray, x_sorted: np.ndarray, disturbance: ConeDisturbance, *, rtol: float = 1e-6
               ) -> np.ndarray:
    """Which ends of each coefficient's identified set are unbounded: ``(p, 2)`` bools, lower then upper.

    Lowering theta_j by ``t`` adds ``t F_j`` to the disturbance, so the set has no lower end when
    ``F_j``, less some combination of the other columns, lies in the class (and no upper end when
    ``-F_j`` does): every value on that side then fits as well as the best. The profile search
    cannot see this (its criterion is flat there up to the rounding of ever larger numbers, which
    it read as an edge near 1e10). The class is tested on at most ``MAX_KNOTS + 2`` evenly spread
    samples, where its generators describe it exactly (more samples only thin the cone).

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns, rows sorted as ``x_sorted``.
    x_sorted : (n,) ndarray
        Sample coordinates, increasing.
    disturbance : ConeDisturbance
    rtol : float, optional
        Largest share of ``|F_j|`` left outside the class for the column to count as inside it.

    Returns
    -------
    (p, 2) ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Convex
    >>> x = np.linspace(-1, 1, 41)
    >>> open_sides(np.c_[x**2], x, Convex()).tolist()           # x**2 is convex: no lower end
    [[True, False]]
    >>> open_sides(np.c_[np.sin(5 * x)], x, Convex()).tolist()  # the class bounds sin 5x on both sides
    [[False, False]]
    """
    n, p = F.shape
    rows = np.unique(np.linspace(0, n - 1, min(n, MAX_KNOTS + 2)).round().astype(int))
    A0, H = disturbance.generators(x_sorted[rows])
    Fr = F[rows]
    out = np.zeros((p, 2), dtype=bool)
    for j in range(p):
        fit = _ConeLS(np.hstack([np.delete(Fr, j, axis=1), A0]), H)
        size = np.linalg.norm(Fr[:, j])
        out[j] = [np.sqrt(fit(sign * Fr[:, j])[2]) <= rtol * size for sign in (1.0, -1.0)]
    return out


def profile_edge(profile: Callable[[float], float], t0: float, thresh: float, sgn: float) -> float:
    """Edge of ``{t : profile(t) <= thresh}`` on one side (``sgn`` -1 or +1) of ``t0``, which is inside.

    Doubles the step until the profile exceeds the threshold (looking a little further first, since
    Cp jumps with the active set and one exceedance may be a local bump), then bisects; returns
    ``sgn * inf`` when no edge is found within 60 doublings.

    Parameters
    ----------
    profile : callable
        ``t -> criterion`` (e.g. the profile Cp of one coefficient).
    t0 : float
        A point inside the set.
    thresh : float
        Largest criterion inside the set.
    sgn : float
        -1 for the lower edge, +1 for the upper.

    Returns
    -------
    float

    Examples
    --------
    >>> round(profile_edge(lambda t: t * t, 0.0, 4.0, 1.0), 5)
    2.0
    """
    step0 = max(abs(t0), 1.0) * 1e-3
    inside, step = t0, step0
    out = t0 + sgn * step
    it = 0
    while it < 60:
        if profile(out) > thresh:
            ahead = [t0 + sgn * step * f for f in (1.25, 1.5, 2.0)]
            back_in = [a for a in ahead if profile(a) <= thresh]
            if not back_in:
                break
            out = back_in[-1]
        inside, step = out, abs(out - t0) * 2
        out = t0 + sgn * step
        it += 1
    if it >= 60:
        return sgn * np.inf
    for _ in range(40):  # bisection to ~1e-12 of the bracket
        mid = 0.5 * (inside + out)
        if profile(mid) <= thresh:
            inside = mid
        else:
            out = mid
        if abs(out - inside) <= 1e-7 * max(1.0, abs(t0)):
            break
    return inside


def bootstrap_excess(design: tuple[np.ndarray, np.ndarray], fit: tuple[np.ndarray, np.ndarray], Fs: np.ndarray,
                     theta_ls: np.ndarray, sigma2: float, profile_solvers: Sequence[Callable], *, n_boot: int,
                     random_state: int | None = None) -> np.ndarray:
    """95 % quantile, per coefficient, of the profile-Cp excess at the true theta over replicates
    drawn around the fitted model ``A u + H d`` (``design = (A, H)``, ``fit = (u, d)``) with noise
    variance ``sigma2``.

    ``profile_solvers[j]`` fits the cone model without column j. The replicates use the seed
    ``random_state`` (0 when None, so a fit is reproducible).

    Parameters
    ----------
    design : tuple of ndarray
        ``(A, H)``: free columns (basis first) and cone generators, rows sorted by x.
    fit : tuple of ndarray
        ``(u, d)`` of the fit of ``y`` on them.
    Fs : (n, p) ndarray
        The basis columns, rows in the same order.
    theta_ls : (p,) ndarray
        Least-squares theta (the truth of the replicates).
    sigma2 : float
        Noise variance of the replicates.
    profile_solvers : sequence of callable
        One cone solver per coefficient, without its column.
    n_boot : int
        Number of replicates.
    random_state : int, optional

    Returns
    -------
    (p,) ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Convex
    >>> x = np.linspace(-1, 1, 41); F = np.c_[np.sin(5 * x)]
    >>> A0, H = cone_generators(x, Convex()); A = np.hstack([F, A0])
    >>> y = x**2 + np.sin(5 * x) + 0.01 * np.random.default_rng(1).standard_normal(41)
    >>> u, d, rss = cone_lstsq(A, H, y)
    >>> e = bootstrap_excess((A, H), (u, d), F, u[:1], rss / 30, [_ConeLS(A0, H)], n_boot=5)
    >>> e.shape, bool(e[0] >= 0)
    ((1,), True)
    """
    (A, H), (u, d) = design, fit
    p = len(profile_solvers)
    rng = np.random.default_rng(0 if random_state is None else random_state)
    full = _ConeLS(A, H)
    mu = A @ u + H @ d
    T = np.empty((n_boot, p))
    for b in range(n_boot):
        yb = mu + np.sqrt(sigma2) * rng.standard_normal(mu.size)
        ref_b = _cp(full(yb), sigma2)
        T[b] = [_cp(profile_solvers[j](yb - theta_ls[j] * Fs[:, j]), sigma2) - ref_b for j in range(p)]
    return np.quantile(T, 0.95, axis=0)


def coefficient_scales(F: np.ndarray, y: np.ndarray, spread: float = 1e3) -> np.ndarray | None:
    """Factors ``k`` that bring each coefficient of ``y ~ F theta`` to order one (``F * k``), or None when
    every coefficient's natural size ``rms(y) / rms(F_j)`` is already within ``[1/spread, spread]``.

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns (none all zero).
    y : (n,) ndarray
    spread : float, optional

    Returns
    -------
    (p,) ndarray or None

    Examples
    --------
    >>> x = np.linspace(-1, 1, 50)
    >>> coefficient_scales(np.c_[np.sin(5 * x)], 2 * np.sin(5 * x)) is None
    True
    >>> coefficient_scales(np.c_[np.sin(5 * x)], 2e-9 * np.sin(5 * x)).round(12).tolist()
    [2e-09]
    """
    rms_y = float(np.sqrt(np.mean(np.square(y)))) or 1.0
    rms_f = np.sqrt(np.mean(np.square(F), axis=0))
    if not (rms_f > 0).all():
        return None
    k = rms_y / rms_f
    return None if ((k >= 1 / spread) & (k <= spread)).all() else k


def fit_cone(F: np.ndarray, x: np.ndarray, y: np.ndarray, disturbance: ConeDisturbance, *, level_chi2: float = CHI2_1_95,
             n_boot: int = 40, random_state: int | None = None) -> dict:
    """Least-squares fit and identified intervals; see module docstring.

    The profile-RSS excess of a shape-constrained fit is not chi-square distributed (the active set
    moves with theta), so the 95 % threshold is calibrated by a parametric bootstrap around the
    fitted model (``n_boot`` replicates, drawn with seed ``random_state``, 0 when None, so a fit is
    reproducible); it is never below the chi-square(1) threshold.

    Returns a dict with theta_ls, interval (p, 2), theta_mid, g (at theta_mid), rss_min, sigma2,
    active (number of active cone generators), noise_from ("residual": RSS over the residual degrees
    of freedom; "differences": the larger, difference-based estimate of the data less the physics).

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns.
    x : (n,) ndarray
        Coordinates (any order).
    y : (n,) ndarray
    disturbance : ConeDisturbance
    level_chi2 : float, optional
        Lowest threshold, in units of the noise variance (chi-square(1) 95 % quantile).
    n_boot : int, optional
        Bootstrap replicates calibrating the threshold (0: chi-square only).
    random_state : int, optional

    Returns
    -------
    dict

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Convex
    >>> x = np.linspace(-1, 1, 41)
    >>> c = fit_cone(np.c_[np.sin(5 * x)], x, x**2 + np.sin(5 * x), Convex(), n_boot=0)
    >>> bool(c["interval"][0, 0] < 1 < c["interval"][0, 1])    # theta = 1 lies in the identified set
    True
    """
    k = coefficient_scales(F, y)
    if k is not None:
        # the interval search steps and stops at absolute sizes (1e-3, 1e-7 of max(|theta|, 1)): a
        # coefficient of 2e-9 (data in small units) got the zero-width set [2.01953e-09, 2.01953e-09].
        # Columns scaled so that each coefficient is of order one; the fit itself is the same
        c = fit_cone(F * k, x, y, disturbance, level_chi2=level_chi2, n_boot=n_boot, random_state=random_state)
        return {**c, "theta_ls": c["theta_ls"] * k, "interval": c["interval"] * k[:, None],
                "theta_mid": c["theta_mid"] * k}
    order = np.argsort(x, kind="stable")
    xs, ys, Fs = x[order], y[order], F[order]
    A0, H = cone_generators(xs, disturbance)
    p = F.shape[1]
    A = np.hstack([Fs, A0])
    u, d, rss_min = cone_lstsq(A, H, ys)
    theta_ls = u[:p]
    n_active = _active(d)
    dof = max(1, xs.size - A.shape[1] - n_active)
    # The residual of a cone fit is shrunk: its steps and kinks follow the noise, so RSS / dof was
    # about half the noise variance (median on simulated monotone records of 100-400 points; 0 at 40
    # points), and sets missed the truth in 1 of 10 fits. The difference-based estimate of the data
    # less the physics (the cone part is smooth or monotone, so it cancels) sets a floor under it.
    # (Also where the residual is at rounding level: 20 noisy points often fit a convex or monotone
    # class exactly. Noise-free smooth data get a floor at their curvature's level: a slightly wider set.)
    scale = float(ys @ ys) or 1.0
    diff2 = difference_noise_variance(xs, ys - Fs @ theta_ls)
    floored = bool(np.isfinite(diff2) and diff2 > rss_min / dof)
    sigma2 = diff2 if floored else rss_min / dof
    solvers = [_ConeLS(np.hstack([Fs[:, [k for k in range(p) if k != j]], A0]), H) for j in range(p)]
    excess = np.full(p, level_chi2 * sigma2)
    if n_boot and sigma2 > 1e-20 * scale / xs.size:
        excess = np.maximum(excess, bootstrap_excess((A, H), (u, d), Fs, theta_ls, sigma2, solvers,
                                                     n_boot=n_boot, random_state=random_state))

    cp_min = _cp((u, d, rss_min), sigma2)
    interval = np.empty((p, 2))
    unbounded = open_sides(Fs, xs, disturbance)
    for j in range(p):
        thresh = cp_min + excess[j] + 1e-10 * scale
        profile = lambda t, j=j: _cp(solvers[j](ys - t * Fs[:, j]), sigma2)  # noqa: E731
        interval[j] = [sgn * np.inf if unbounded[j, k] else profile_edge(profile, theta_ls[j], thresh, sgn)
                       for k, sgn in enumerate((-1.0, 1.0))]
    theta_mid = np.where(np.isfinite(interval).all(axis=1), interval.mean(axis=1), theta_ls)
    # the disturbance at the reported point: best cone fit to what the physics leaves
    ug, dg, _ = cone_lstsq(A0, H, ys - Fs @ theta_mid)
    g_sorted = A0 @ ug + H @ dg
    g = np.empty_like(g_sorted)
    g[order] = g_sorted
    return {
        "theta_ls": theta_ls, "interval": interval, "theta_mid": theta_mid, "g": g,
        "rss_min": rss_min, "sigma2": sigma2, "active": n_active, "threshold_excess": excess, "generators": H.shape[1],
        "noise_dof": int(xs.size - A.shape[1] - n_active),
        "noise_from": "differences" if floored else "residual",
        "exact_cone": H.shape[1] >= disturbance.full_generator_count(xs.size),
    }
