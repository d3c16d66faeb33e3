"""Autoregressive prewhitening of residuals: coloured noise turned into (nearly) white innovations.

A likelihood comparison of two models on coloured noise counts correlated samples as independent
and so overstates the evidence. Filtering both residuals with the same autoregressive filter,
fitted to the better model's residual, gives the Gaussian AR(p) likelihood's comparison instead.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["ar_fit", "prewhiten"]


def _autocovariance(x: np.ndarray, max_lag: int) -> np.ndarray:
    n = len(x)
    return np.array([float(x[: n - k] @ x[k:]) / n for k in range(max_lag + 1)])


def ar_fit(x: ArrayLike, max_order: int = 8) -> np.ndarray:
    """Yule-Walker AR coefficients of ``x``, the order chosen by BIC (0 for white noise).

    ``x_t = sum_k a_k x_(t-k) + e_t``; order 0 returns an empty array.

    Parameters
    ----------
    x : array_like
        Series in time order (its mean is removed).
    max_order : int, optional
        Largest order tried (also at most ``n // 10``).

    Returns
    -------
    ndarray
        ``a_1 .. a_p``.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> e = rng.normal(size=4000); x = np.zeros(4000)
    >>> for i in range(1, 4000): x[i] = 0.7 * x[i - 1] + e[i]
    >>> np.round(ar_fit(x), 2).tolist()
    [0.7]
    >>> ar_fit(rng.normal(size=500)).tolist()
    []
    """
    from scipy.linalg import solve_toeplitz  # on use: keeps the package import light

    x = np.asarray(x, float)
    x = x - x.mean()
    n = len(x)
    max_order = int(max(0, min(max_order, n // 10)))
    acov = _autocovariance(x, max_order)
    if acov[0] <= 0:
        return np.zeros(0)
    best, best_bic = np.zeros(0), n * np.log(acov[0])
    for p in range(1, max_order + 1):
        a = solve_toeplitz(acov[:p], acov[1:p + 1])
        s2 = acov[0] - float(a @ acov[1:p + 1])
        if s2 <= 0:
            break
        bic = n * np.log(s2) + p * np.log(n)
        if bic < best_bic:
            best, best_bic = a, bic
    return np.asarray(best, float)


def prewhiten(x: ArrayLike, coefs: ArrayLike) -> np.ndarray:
    """Innovations ``e_t = x_t - sum_k a_k x_(t-k)`` for ``t >= p`` (the first ``p`` are dropped).

    Parameters
    ----------
    x : array_like
        Series in time order.
    coefs : array_like
        AR coefficients from :func:`ar_fit`.

    Returns
    -------
    ndarray
        ``n - p`` innovations.

    Examples
    --------
    >>> import numpy as np
    >>> prewhiten(np.array([1.0, 2.0, 4.0, 8.0]), [2.0]).tolist()
    [0.0, 0.0, 0.0]
    """
    x = np.asarray(x, float)
    a = np.asarray(coefs, float)
    p = len(a)
    out = x[p:].copy()
    for k in range(1, p + 1):
        out -= a[k - 1] * x[p - k: len(x) - k]
    return out
