"""Closed-form Gram matrix of fixed-frequency columns under a sin^2 window.

Over ``t = 0 .. n - 1`` with weights ``w_t = sin^2(pi (t + 1/2) / n)`` (the blocks' window, and the
Hann over the visible part of a block cut by the signal's ends), every weighted sum of products of
``cos(omega t)``, ``sin(omega t)``, a constant and a linear trend is a Dirichlet kernel and its
derivative, evaluated at the sum and difference frequencies. Exact (no sub-sampling), float64,
and independent of the block length's cost.
"""
from __future__ import annotations

import numpy as np


def _dirichlet(x: np.ndarray, n: int):
    """``D(x) = sum_{u} exp(i x u)`` over ``u = -(n - 1)/2 .. (n - 1)/2`` (real) and its derivative."""
    h = 0.5 * x
    s, c = np.sin(h), np.cos(h)
    sn, cn = np.sin(n * h), np.cos(n * h)
    small = np.abs(s) < 1e-9
    s_safe = np.where(small, 1.0, s)
    D = np.where(small, n * cn / np.where(small, c, 1.0), sn / s_safe)
    dD = np.where(small, 0.0, (0.5 * n * cn * s - 0.5 * sn * c) / s_safe ** 2)
    return D, dD


def _hann_kernel(x: np.ndarray, n: int):
    """``K(x) = sum_u w_u exp(i x u)`` for the centred sin^2 window (real, even) and ``K'(x)``."""
    d = 2 * np.pi / n
    D0, dD0 = _dirichlet(x, n)
    Dm, dDm = _dirichlet(x - d, n)
    Dp, dDp = _dirichlet(x + d, n)
    return 0.5 * D0 + 0.25 * (Dm + Dp), 0.5 * dD0 + 0.25 * (dDm + dDp)


def fixed_gram(omega: np.ndarray, n: int) -> np.ndarray:
    """``F^T diag(w) F`` for the columns ``cos(omega_l t), sin(omega_l t)`` (pairs, in order), then a
    constant and the trend ``-1 + 2 t / (n - 1)``, with the sin^2 weights above; (2 m + 2) square.

    The trend's own entries with the fixed columns use the kernel's derivative, which loses
    precision for frequencies within a few window bins of 0 or of Nyquist: callers use this only
    when every line is well inside the band.

    Parameters
    ----------
    omega : (m,) array
        Line frequencies (rad per sample).
    n : int
        Samples in the block.

    Returns
    -------
    (2 m + 2, 2 m + 2) float64 array

    Examples
    --------
    >>> from odnn_sep.audio.blockplan import sin2_window
    >>> n, omega = 2000, 2 * np.pi * 0.17; t = np.arange(n)
    >>> F = np.stack([np.cos(omega * t), np.sin(omega * t), np.ones(n), -1 + 2 * t / (n - 1)], axis=1)
    >>> G = fixed_gram(np.array([omega]), n)
    >>> G.shape, np.allclose(G, (F * sin2_window(t + 0.5, n)[:, None]).T @ F)
    ((4, 4), True)
    """
    omega = np.asarray(omega, float)
    m = len(omega)
    c = (n - 1) / 2
    G = np.zeros((2 * m + 2, 2 * m + 2))
    if m:
        # sum_t w e^{i x t} = e^{i x c} K(x)
        dif = omega[:, None] - omega[None, :]
        tot = omega[:, None] + omega[None, :]
        Kd, _ = _hann_kernel(dif, n)
        Kt, _ = _hann_kernel(tot, n)
        Sd = np.exp(1j * dif * c) * Kd
        St = np.exp(1j * tot * c) * Kt
        G[0:2 * m:2, 0:2 * m:2] = 0.5 * (Sd + St).real
        G[1:2 * m:2, 1:2 * m:2] = 0.5 * (Sd - St).real
        G[0:2 * m:2, 1:2 * m:2] = 0.5 * (St - Sd).imag
        G[1:2 * m:2, 0:2 * m:2] = 0.5 * (St + Sd).imag
        K1, dK1 = _hann_kernel(omega, n)
        ph = np.exp(1j * omega * c)
        S1 = ph * K1                                     # with the constant
        St1 = (2.0 / max(n - 1, 1)) * ph * (-1j) * dK1   # with the trend: sum w (2u / (n - 1)) e^{i x t}
        G[0:2 * m:2, 2 * m], G[1:2 * m:2, 2 * m] = S1.real, S1.imag
        G[0:2 * m:2, 2 * m + 1], G[1:2 * m:2, 2 * m + 1] = St1.real, St1.imag
        G[2 * m, : 2 * m] = G[: 2 * m, 2 * m]
        G[2 * m + 1, : 2 * m] = G[: 2 * m, 2 * m + 1]
    u = np.arange(n) - c
    w = 0.5 + 0.5 * np.cos(2 * np.pi * u / n)
    G[2 * m, 2 * m] = w.sum()
    G[2 * m + 1, 2 * m + 1] = float(np.dot(w, u * u)) * (2.0 / max(n - 1, 1)) ** 2
    return G
