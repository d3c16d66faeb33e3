"""Autoregressive prewhitening of residuals: coloured noise turned into (nearly) white innovations.

A likelihood comparison of two models on coloured noise counts correlated samples as independent
and so overstates the evidence. Filtering both residuals with the same autoregressive filter,
fitted to the better model's residual, gives the Gaussian AR(p) likelihood's comparison instead.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

__all__ = ["ar_autocovariance", "ar_fit", "ar_sandwich_stderr", "prewhiten"]


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


def ar_autocovariance(resid: ArrayLike, max_lag: int) -> np.ndarray:
    """Autocovariance at lags ``0..max_lag`` of the AR(p) model fitted to ``resid`` (order by BIC).

    The model's own autocovariance, not the sample one: it decays smoothly and stays positive
    definite, so a sandwich built on it never gives a negative variance. Zeros beyond lag 0 when no
    red filter is chosen (white noise, or a filter whose coefficients sum to zero or less).

    Parameters
    ----------
    resid : array_like
        Residual in time order.
    max_lag : int
        Largest lag returned.

    Returns
    -------
    ndarray, shape (max_lag + 1,)

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> x = np.zeros(5000); e = rng.normal(size=5000)
    >>> for i in range(1, 5000): x[i] = 0.6 * x[i - 1] + e[i]
    >>> g = ar_autocovariance(x, 3); np.round(g[1:] / g[0], 2).tolist()
    [0.6, 0.36, 0.21]
    """
    r = np.asarray(resid, float)
    r = r - r.mean()
    var = float(r @ r) / max(len(r), 1)
    out = np.zeros(max_lag + 1)
    out[0] = var
    a = ar_fit(r)
    if var <= 0 or not len(a) or float(np.sum(a)) <= 0:
        return out
    e = prewhiten(r, a)
    s2 = float(e @ e) / max(len(e), 1)
    # impulse response of 1 / (1 - sum a_k z^k): psi_j, then gamma_h = s2 sum_j psi_j psi_(j+h)
    n_psi = max_lag + 400
    psi = np.zeros(n_psi)
    psi[0] = 1.0
    for j in range(1, n_psi):
        k = min(len(a), j)
        psi[j] = float(a[:k] @ psi[j - k:j][::-1])
    for h in range(max_lag + 1):
        out[h] = s2 * float(psi[: n_psi - h] @ psi[h:])
    return out


def ar_sandwich_stderr(J: ArrayLike, resid: ArrayLike, *, tol: float = 1e-3, max_lag: int = 400) -> np.ndarray:
    """Standard errors of least squares under AR(p) noise fitted to the residual.

    ``(J'J)^-1 J' Sigma J (J'J)^-1`` with ``Sigma`` the Toeplitz autocovariance of the fitted AR
    model (:func:`ar_autocovariance`), summed over lags until it falls below ``tol`` of the
    variance. Where the noise is strongly persistent, a block sandwich with few long blocks is
    itself noisy; this one uses the AR model instead, so it does not need long blocks.

    Parameters
    ----------
    J : array_like, shape (n, q)
        Jacobian of the residual (rows in time order).
    resid : array_like, shape (n,)
        Residual.
    tol : float, optional
        Lags whose autocovariance is below ``tol`` times the variance are left out.
    max_lag : int, optional
        Most lags summed.

    Returns
    -------
    ndarray, shape (q,)

    Examples
    --------
    >>> import numpy as np
    >>> J = np.c_[np.ones(400)]
    >>> r = np.random.default_rng(0).normal(size=400)          # white: the classical error
    >>> round(float(ar_sandwich_stderr(J, r)[0] / (r.std() / 20)), 2)
    1.0
    """
    J = np.asarray(J, float)
    r = np.asarray(resid, float)
    n = len(r)
    g = ar_autocovariance(r, min(max_lag, n - 1))
    keep = np.flatnonzero(np.abs(g) >= tol * g[0]) if g[0] > 0 else np.array([0])
    L = int(keep.max()) if len(keep) else 0
    meat = g[0] * (J.T @ J)
    for h in range(1, L + 1):
        C = J[:-h].T @ J[h:]
        meat += g[h] * (C + C.T)
    JtJ_inv = np.linalg.pinv(J.T @ J)
    return np.sqrt(np.maximum(np.diag(JtJ_inv @ meat @ JtJ_inv), 0.0))
