"""Uncertainty of least-squares fits: noise variance, standard errors, normal intervals (``Z95``).

Re-exported by :mod:`odnn_sep.core.linalg`, where front-ends should import them from.
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import InputError

__all__ = ["Z95", "noise_variance", "difference_noise_variance", "stderr_from_cov", "standard_errors", "intervals"]

#: Two-sided 95 % standard-normal quantile, ``scipy.stats.norm.ppf(0.975)``.
Z95 = 1.959963984540054


def noise_variance(resid: ArrayLike, dof: int, weights: ArrayLike | None = None) -> float:
    """``sum(w r^2) / dof`` (``r @ r / dof`` without weights); NaN when ``dof <= 0``.

    Parameters
    ----------
    resid : array_like
        Residuals, (n,).
    dof : int
        Residual degrees of freedom.
    weights : array_like, optional
        Sample weights, (n,).

    Returns
    -------
    float

    Examples
    --------
    >>> noise_variance([1.0, -1.0, 2.0], 2)
    3.0
    """
    r = np.asarray(resid)
    if dof <= 0:
        return float("nan")
    if weights is None:
        return float(r @ r / dof)
    return float((np.asarray(weights) * r * r).sum() / dof)


def difference_noise_variance(x: ArrayLike, r: ArrayLike) -> float:
    """Noise variance of ``r`` from its local curvature alone (Gasser, Sroka and Jennen-Steinmetz, 1986).

    Each point is compared with the straight line through its two neighbours in x; a smooth trend
    cancels, the noise does not. It needs no fitted model, so it cannot be fooled by a fit that absorbs
    the noise (a monotone or convex class with many steps or kinks, whose residual sum of squares
    underestimated the variance by half). Triples whose outer points share an x are skipped; NaN when
    fewer than 3 triples remain.

    Parameters
    ----------
    x : array_like
        Coordinates, (n,), any order.
    r : array_like
        Values at ``x``, (n,): data, or data less a fitted part that is not smooth.

    Returns
    -------
    float

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> x = np.linspace(0, 1, 4000)
    >>> v = difference_noise_variance(x, np.exp(2 * x) + 0.1 * rng.standard_normal(x.size))
    >>> round(float(np.sqrt(v)), 2)
    0.1
    """
    x, r = np.asarray(x, dtype=float), np.asarray(r, dtype=float)
    order = np.argsort(x, kind="stable")
    x, r = x[order], r[order]
    span = x[2:] - x[:-2]
    ok = span > 0
    if ok.sum() < 3:
        return float("nan")
    span = span[ok]
    a = (x[2:][ok] - x[1:-1][ok]) / span
    b = (x[1:-1][ok] - x[:-2][ok]) / span
    e = a * r[:-2][ok] + b * r[2:][ok] - r[1:-1][ok]
    return float(np.mean(e**2 / (a**2 + b**2 + 1.0)))


def stderr_from_cov(cov_unscaled: ArrayLike, sigma2: float) -> np.ndarray:
    """Standard errors ``sqrt(diag(cov_unscaled) * sigma2)`` (negative rounding clipped to 0).

    Parameters
    ----------
    cov_unscaled : array_like
        ``(F^T F)^-1``-type covariance without the noise variance, (p, p).
    sigma2 : float
        Noise variance.

    Returns
    -------
    ndarray
        (p,) standard errors.

    Examples
    --------
    >>> stderr_from_cov(np.diag([4.0, 1.0]), 0.25).tolist()
    [1.0, 0.5]
    """
    return np.sqrt(np.maximum(np.diag(cov_unscaled).real, 0) * sigma2)


def standard_errors(J: ArrayLike, resid: ArrayLike | None = None, dof: int | None = None, *,
                    sigma2: float | None = None) -> np.ndarray:
    """Gauss–Newton standard errors ``sqrt(diag(pinv(J^T J) * s^2))`` of a least-squares fit.

    Parameters
    ----------
    J : array_like, shape (n, q)
        Jacobian of the residual (or model) with respect to the q parameters at the optimum.
    resid : array_like, shape (n,), optional
        Residual at the optimum; with ``dof`` gives ``s^2 = resid @ resid / dof``.
    dof : int, optional
        Residual degrees of freedom.
    sigma2 : float, optional
        The noise variance, instead of ``resid`` and ``dof``.

    Returns
    -------
    ndarray, shape (q,)

    Raises
    ------
    numpy.linalg.LinAlgError
        When the SVD inside ``pinv`` does not converge (non-finite J).

    Examples
    --------
    >>> import numpy as np
    >>> J = np.c_[np.ones(4)]
    >>> standard_errors(J, np.array([1.0, -1.0, 1.0, -1.0]), 3).round(6).tolist()
    [0.57735]
    """
    J = np.asarray(J)
    if sigma2 is None:
        if resid is None or dof is None:
            raise InputError("standard_errors needs resid and dof, or sigma2")
        r = np.asarray(resid)
        sigma2 = float(r @ r / dof)
    cov = np.linalg.pinv(J.T @ J) * sigma2
    return np.sqrt(np.maximum(np.diag(cov), 0))


def intervals(theta: ArrayLike, stderr: ArrayLike, level: float = 0.95, dof: float | None = None) -> np.ndarray:
    """Confidence intervals ``theta -+ q stderr``, shape (p, 2): ``q`` the normal quantile, or
    Student's t with ``dof`` degrees of freedom when the standard errors come from a noise variance
    estimated on ``dof`` residual degrees of freedom (with 4 of them the normal quantile covered
    83 % instead of 95 %).

    Parameters
    ----------
    theta : array_like
        Estimates, (p,).
    stderr : array_like
        Their standard errors, (p,).
    level : float, optional
        Coverage, strictly between 0 and 1.
    dof : float, optional
        Residual degrees of freedom of the noise variance (None or infinite: the normal quantile).

    Returns
    -------
    ndarray
        (p, 2) lower and upper bounds.

    Raises
    ------
    odnn_sep.errors.InputError
        For a level outside (0, 1).

    Examples
    --------
    >>> intervals([1.0], [0.5]).round(4).tolist()
    [[0.02, 1.98]]
    >>> intervals([1.0], [0.5], dof=4).round(4).tolist()
    [[-0.3882, 2.3882]]
    """
    if not 0 < level < 1:
        raise InputError(f"level must be strictly between 0 and 1; got {level!r}")
    if dof is not None and np.isfinite(dof) and dof > 0:
        from scipy import stats

        z = float(stats.t.ppf(0.5 + level / 2, dof))
    elif level == 0.95:
        z = Z95
    else:
        from scipy import stats

        z = float(stats.norm.ppf(0.5 + level / 2))
    theta = np.asarray(theta)
    stderr = np.asarray(stderr)
    return np.c_[theta - z * stderr, theta + z * stderr]


class SandwichErrors(NamedTuple):
    """Result of :func:`sandwich_standard_errors`.

    Attributes
    ----------
    stderr : ndarray, shape (q,)
        The largest of the classical, the block-sandwich and the AR(p) sandwich standard error.
    classical : ndarray, shape (q,)
        Gauss-Newton ``sqrt(diag(s^2 (J^T J)^-1))``.
    block : int
        Samples per block.
    n_blocks : int
        Number of blocks (the sandwich's own degrees of freedom are ``n_blocks - 1``).

    Examples
    --------
    >>> import numpy as np
    >>> r = np.repeat([1.0, -1.0], 4)                  # residual correlated in runs of four
    >>> out = sandwich_standard_errors(np.c_[np.ones(8)], r, 7, block=4)
    >>> out.block, out.n_blocks
    (4, 2)
    >>> bool((out.stderr >= out.classical).all())
    True
    """

    stderr: np.ndarray     # the largest of the classical, block-sandwich and AR(p) sandwich errors
    classical: np.ndarray  # Gauss-Newton ``sqrt(diag(s^2 (J^T J)^-1))``
    block: int             # samples per block
    n_blocks: int          # blocks (the sandwich's own degrees of freedom are n_blocks - 1)


def long_run_rho(resid: ArrayLike) -> float:
    """The AR(1) coefficient with the same low-frequency variance inflation as the residual.

    An AR(p) model (order by BIC) gives the long-run variance ``s_e^2 / (1 - sum a)^2``; the
    inflation over the variance, ``f``, is that of an AR(1) with ``rho = (f - 1) / (f + 1)``. For
    white noise plus AR(1) noise the lag-1 autocorrelation understates the persistence; this does not.
    0 when the fitted filter is not red at low frequencies.

    Parameters
    ----------
    resid : array_like
        Residual in time order.

    Returns
    -------
    float
        In [0, 1).

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.zeros(5000); e = rng.normal(size=5000)
    >>> for i in range(1, 5000): x[i] = 0.8 * x[i - 1] + e[i]
    >>> round(long_run_rho(x), 2), round(long_run_rho(x / x.std() + 2 * rng.normal(size=5000)), 2)
    (0.8, 0.33)
    """
    from odnn_sep.core.whitening import ar_fit, prewhiten

    r = np.asarray(resid, float)
    r = r - r.mean()
    var = float(r @ r) / max(len(r), 1)
    a = ar_fit(r)
    if var <= 0 or not len(a) or float(np.sum(a)) <= 0 or float(np.sum(a)) >= 1:
        return 0.0
    e = prewhiten(r, a)
    f = float(e @ e) / max(len(e), 1) / (1.0 - float(np.sum(a))) ** 2 / var
    return float(max(f - 1.0, 0.0) / (f + 1.0))


def block_length(resid: ArrayLike, *, floor_exponent: float = 1 / 3) -> int:
    """Block length for a block sandwich or bootstrap, read off the residual's autocorrelation.

    The larger of ``2 n^(1/3)`` and Andrews' (1991) AR(1) plug-in ``1.1447 (alpha n)^(1/3)``,
    ``alpha = 4 rho^2 / ((1 - rho)^2 (1 + rho)^2)`` with ``rho`` the larger of the lag-1
    autocorrelation and :func:`long_run_rho` (clipped to [0, 0.97]); at most ``n // 4``, so there are always four blocks or more. Correlated
    noise or leftover structure (large ``rho``) gives longer blocks, so that what is correlated
    within a block counts fully.

    Parameters
    ----------
    resid : array_like
        Residuals in time order, (n,).
    floor_exponent : float, optional
        Exponent of the smallest block length ``2 n**floor_exponent``.

    Returns
    -------
    int
        Between 1 and ``n // 4``.

    Examples
    --------
    >>> import numpy as np
    >>> r = np.random.default_rng(0).normal(size=1000)
    >>> block_length(r)
    20
    >>> block_length(np.sin(np.linspace(0, 20, 1000)))   # strongly correlated: longer blocks
    117
    """
    r = np.asarray(resid, float)
    n = len(r)
    r = r - r.mean()
    den = float(r @ r)
    rho = float(r[1:] @ r[:-1]) / den if den > 0 and n > 2 else 0.0
    rho = min(max(rho, long_run_rho(r), 0.0), 0.97)
    alpha = 4 * rho ** 2 / ((1 - rho) ** 2 * (1 + rho) ** 2)
    L = max(2 * n ** floor_exponent, 1.1447 * (alpha * n) ** (1 / 3))
    return int(max(1, min(round(L), n // 4)))


def sandwich_standard_errors(J: ArrayLike, resid: ArrayLike, dof: int, *, block: int | None = None) -> SandwichErrors:
    """Standard errors that hold when the noise is correlated or the model is not quite right.

    The block sandwich ``(J'J)^-1 (sum_b J_b' r_b r_b' J_b) (J'J)^-1`` over contiguous blocks of
    ``block`` samples (default :func:`block_length` of ``resid``), with the small-sample factor
    ``nb / (nb - 1) * n / dof``; the reported error is the largest of it, the classical one and the
    AR(p) sandwich (:func:`~odnn_sep.core.whitening.ar_sandwich_stderr`).

    Parameters
    ----------
    J : array_like, shape (n, q)
        Jacobian of the residual at the optimum (rows in time order).
    resid : array_like, shape (n,)
        Residual at the optimum.
    dof : int
        Residual degrees of freedom (for ``s^2`` and the small-sample factor).
    block : int, optional
        Samples per block; default from the residual's autocorrelation.

    Returns
    -------
    SandwichErrors
        ``stderr``, ``classical``, ``block``, ``n_blocks``.

    Examples
    --------
    >>> import numpy as np
    >>> J = np.c_[np.ones(8)]
    >>> out = sandwich_standard_errors(J, np.array([1.0, -1, 1, -1, 1, -1, 1, -1]), 7, block=2)
    >>> out.classical.round(4).tolist(), out.n_blocks
    ([0.378], 4)
    """
    J = np.asarray(J, float)
    r = np.asarray(resid, float)
    n = len(r)
    dof = max(int(dof), 1)
    # equilibrate the columns first: parameters of very different sizes (a stiffness of 4e-12 beside an
    # amplitude of 1 when time is in microseconds) give J'J a condition number beyond 1e16, and the
    # pseudo-inverse would then drop the small directions and report their errors as 0
    d = np.linalg.norm(J, axis=0)
    d = np.where(np.isfinite(d) & (d > 0), d, 1.0)
    J = J / d
    JtJ_inv = np.linalg.pinv(J.T @ J)
    classical = np.diag(JtJ_inv) * float(r @ r) / dof
    L = block_length(r) if block is None else int(max(1, min(block, n)))
    nb = max(n // L, 1)
    edges = np.linspace(0, n, nb + 1).astype(int)
    S = np.stack([J[a:b].T @ r[a:b] for a, b in zip(edges[:-1], edges[1:], strict=True)])
    meat = S.T @ S * (nb / max(nb - 1, 1)) * (n / dof)
    sandwich = np.diag(JtJ_inv @ meat @ JtJ_inv)
    classical = np.sqrt(np.maximum(classical, 0.0))
    # the larger of the three: the block sandwich is noisy with few long blocks (persistent noise),
    # the AR one assumes the residual is AR(p); neither is allowed to shrink the classical error
    from odnn_sep.core.whitening import ar_sandwich_stderr

    stderr = np.maximum.reduce([classical, np.sqrt(np.maximum(sandwich, 0.0)), ar_sandwich_stderr(J, r)])
    return SandwichErrors(stderr / d, classical / d, L, nb)


__all__ += ["SandwichErrors", "block_length", "long_run_rho", "sandwich_standard_errors"]
