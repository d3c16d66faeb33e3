"""Uncertainty of least-squares fits: noise variance, standard errors, normal intervals (``Z95``).

Re-exported by :mod:`odnn_sep.core.linalg`, where front-ends should import them from.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import InputError

__all__ = ["Z95", "noise_variance", "stderr_from_cov", "standard_errors", "intervals"]

#: Two-sided 95 % standard-normal quantile, ``scipy.stats.norm.ppf(0.975)``.
Z95 = 1.959963984540054


def noise_variance(resid: ArrayLike, dof: int, weights: ArrayLike | None = None) -> float:
    """``sum(w r^2) / dof`` (``r @ r / dof`` without weights); NaN when ``dof <= 0``.

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


def stderr_from_cov(cov_unscaled: ArrayLike, sigma2: float) -> np.ndarray:
    """Standard errors ``sqrt(diag(cov_unscaled) * sigma2)`` (negative rounding clipped to 0).

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


def intervals(theta: ArrayLike, stderr: ArrayLike, level: float = 0.95) -> np.ndarray:
    """Normal-approximation confidence intervals ``theta -+ z stderr``, shape (p, 2).

    Examples
    --------
    >>> intervals([1.0], [0.5]).round(4).tolist()
    [[0.02, 1.98]]
    """
    if not 0 < level < 1:
        raise InputError(f"level must be strictly between 0 and 1; got {level!r}")
    if level == 0.95:
        z = Z95
    else:
        from scipy import stats

        z = float(stats.norm.ppf(0.5 + level / 2))
    theta = np.asarray(theta)
    stderr = np.asarray(stderr)
    return np.c_[theta - z * stderr, theta + z * stderr]
