"""Bias of the line estimates from noise in the measured voltages (errors-in-variables).

The columns of a bus equation are built from measured magnitudes and angles. Their noise is small
(PMU: ~1e-6), but on a distribution feeder the columns are differences of nearly equal voltages
multiplied by admittances of ~10^3 p.u., and least squares is attenuated towards zero:

    E[A^T A] = A0^T A0 + S,   S = sum_t J_t Sigma_u J_t^T,   so  theta_hat ~= (A^T A)^-1 (A^T A - S) theta,

with ``J_t`` the derivatives of the columns at snapshot t with respect to the measured v and delta of
the bus and its candidates, ``Sigma_u`` their noise variances (stated by the meter), and ``A`` the
columns plus the disturbance class's free part (a constant and a line in v_i). The bias
``theta_hat - (A^T A - S)^-1 A^T A theta_hat`` (corrected least squares; first order
``-(A^T A)^-1 S theta`` where ``A^T A - S`` is not safely positive definite) is used to shift the
estimates and, since it is itself estimated, to widen their intervals by it: a line whose interval still excludes zero is there whatever the bias; a coefficient
whose bias is larger than its noise is reported as limited by voltage noise rather than point-identified.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import solve


def column_jacobian(v: np.ndarray, delta: np.ndarray, i: int, others) -> np.ndarray:
    """(n, 2 len(others), m) derivatives of bus i's columns (G, B per candidate, as
    :func:`power_grid.row_columns`) with respect to m = 2 + 2 len(others) measured quantities
    (v_i, delta_i, then v_k, delta_k per candidate). ``v``, ``delta`` are (n, nb) in bus positions.

    Parameters
    ----------
    v, delta : (n, nb) ndarray
        Measured voltage magnitudes (p.u.) and angles (rad).
    i : int
        The bus of the equation.
    others : sequence of int
        Candidate neighbours, in column order.

    Returns
    -------
    (n, 2 len(others), 2 + 2 len(others)) ndarray

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.signals.power_grid import row_columns
    >>> rng = np.random.default_rng(0)
    >>> v, delta = 1 + 0.01 * rng.standard_normal((50, 3)), 0.01 * rng.standard_normal((50, 3))
    >>> F, names = row_columns(v, delta, 1, [0, 2])              # bus 1, candidates 0 and 2
    >>> J = column_jacobian(v, delta, 1, [0, 2])
    >>> J.shape
    (50, 4, 6)
    >>> v2 = v.copy()
    >>> v2[:, 0] += 1e-7                                             # nudge v_0, the first candidate
    >>> bool(np.allclose((row_columns(v2, delta, 1, [0, 2])[0] - F) / 1e-7, J[:, :, 2], atol=1e-5))
    True
    """
    n = v.shape[0]
    J = np.zeros((n, 2 * len(others), 2 + 2 * len(others)))
    vi, di = v[:, i], delta[:, i]
    for j, k in enumerate(others):
        vk = v[:, k]
        c, s = np.cos(di - delta[:, k]), np.sin(di - delta[:, k])
        g, b, uk = 2 * j, 2 * j + 1, 2 + 2 * j  # column rows and the candidate's (v_k, delta_k) positions
        J[:, g, 0], J[:, g, 1], J[:, g, uk], J[:, g, uk + 1] = -(vk * c - 2 * vi), vi * vk * s, -vi * c, -vi * vk * s
        J[:, b, 0], J[:, b, 1], J[:, b, uk], J[:, b, uk + 1] = -vk * s, -vi * vk * c, -vi * s, vi * vk * c
    return J


def regressor_noise_bias(F: np.ndarray, x: np.ndarray, J: np.ndarray, sigma_v: float, sigma_delta: float,
                         theta: np.ndarray, *, free_part: bool) -> np.ndarray:
    """First-order bias of the coefficients of ``F`` from noise in the measured voltages.

    Parameters
    ----------
    F : (n, p) ndarray
        Columns of the bus equation, evaluated on the measured voltages.
    x : (n,) ndarray
        Measured v_i (the class's free line; its own noise is counted).
    J : (n, p, m) ndarray
        :func:`column_jacobian`.
    sigma_v, sigma_delta : float
        Noise standard deviations of magnitudes (p.u.) and angles (rad).
    theta : (p,) ndarray
        Coefficients at which the bias is evaluated (the estimates).
    free_part : bool
        Whether the disturbance class has a free constant and line in v_i (Convex) or nothing.

    Returns
    -------
    (p,) ndarray
        ``E[theta_hat] - theta`` to first order in the noise variances.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.signals.power_grid import row_columns
    >>> rng = np.random.default_rng(0)
    >>> v, delta = 1 + 0.01 * rng.standard_normal((50, 3)), 0.01 * rng.standard_normal((50, 3))
    >>> F, names = row_columns(v, delta, 1, [0, 2])              # bus 1, candidates 0 and 2
    >>> J = column_jacobian(v, delta, 1, [0, 2])
    >>> theta = np.array([-4.0, 12.0, -5.0, 15.0])
    >>> b = regressor_noise_bias(F, v[:, 1], J, 1e-3, 1e-3, theta, free_part=False)
    >>> b.round(3).tolist()
    [0.035, -0.089, 0.053, -0.155]
    >>> bool((np.sign(b) == -np.sign(theta)).all())                # attenuated towards zero
    True
    """
    n, p, m = J.shape
    var = np.tile([sigma_v**2, sigma_delta**2], m // 2)
    if free_part:
        A = np.c_[F, np.ones(n), x]
        Ja = np.concatenate([J, np.zeros((n, 2, m))], axis=1)
        Ja[:, p + 1, 0] = 1.0  # d(v_i)/d(v_i)
        th = np.r_[theta, 0.0, 0.0]  # the class's affine part is small next to line admittances
    else:
        A, Ja, th = F, J, np.asarray(theta, dtype=float)
    S = np.einsum("tpm,m,tqm->pq", Ja, var, Ja)
    gram = A.T @ A
    corrected = corrected_normal_equations(gram, S, gram @ th)
    if corrected is None:  # the noise is not small against the column spread: first order only
        return -(solve(A, np.zeros(n), return_cov=True).cov_unscaled @ (S @ th))[:p]
    return (th - corrected)[:p]


#: Largest share of the column spread (generalised eigenvalue of S against A^T A) that the voltage
#: noise may make up for the corrected normal equations; beyond it the correction's own variance grows
#: like 1 / (1 - share) (five-fold at 0.8) and only the first-order bias is used.
MAX_NOISE_SHARE = 0.8


def corrected_normal_equations(gram: np.ndarray, S: np.ndarray, rhs: np.ndarray,
                               max_share: float = MAX_NOISE_SHARE) -> np.ndarray | None:
    """Solve ``(A^T A - S) t = rhs`` (least squares corrected for known regressor noise, Fuller 1987).

    None when the noise makes up more than ``max_share`` of the column spread in some direction
    (largest generalised eigenvalue of ``S`` against ``A^T A``): the correction would then be unstable.

    Parameters
    ----------
    gram : (p, p) ndarray
        ``A^T A`` of the measured columns.
    S : (p, p) ndarray
        Expected contribution of the regressor noise to ``gram``.
    rhs : (p,) ndarray
        Right-hand side, ``A^T y``.
    max_share : float, optional
        Largest share of the column spread the noise may make up.

    Returns
    -------
    (p,) ndarray or None

    Examples
    --------
    >>> import numpy as np
    >>> gram = np.array([[4.0, 1.0], [1.0, 2.0]])
    >>> corrected_normal_equations(gram, 0.1 * np.eye(2), np.ones(2)).round(4).tolist()
    [0.1404, 0.4524]
    >>> corrected_normal_equations(gram, 3 * np.eye(2), np.ones(2)) is None     # noise dominates
    True
    """
    from scipy.linalg import eigh

    d = np.sqrt(np.maximum(np.diag(gram), 1e-300))
    Gs, Ss = gram / np.outer(d, d), S / np.outer(d, d)
    try:
        share = eigh(0.5 * (Ss + Ss.T), 0.5 * (Gs + Gs.T), eigvals_only=True).max()
    except np.linalg.LinAlgError:
        return None
    if not share < max_share:
        return None
    return np.linalg.solve(Gs - Ss, rhs / d) / d
