"""Weighted linear least squares, the exact engine behind every subspace separation."""
from __future__ import annotations

import numpy as np
from scipy import linalg


def lstsq(F: np.ndarray, Y: np.ndarray, weights: np.ndarray | None = None, *, rcond: float = 1e-12):
    """Solve ``min ||W^(1/2) (Y - F theta)||`` for one or many right-hand sides.

    Parameters
    ----------
    F : (n, p) array
    Y : (n,) or (n, k) array
    weights : (n,) non-negative array, optional

    Returns
    -------
    theta : (p,) or (p, k) array
    cov_unscaled : (p, p) array
        ``(F^T W F)^+``; multiply by the noise variance for the covariance of theta.
    rank : int

    Examples
    --------
    >>> import numpy as np
    >>> F = np.c_[np.ones(5), np.arange(5.0)]
    >>> theta, _, rank = lstsq(F, 2 + 3 * np.arange(5.0))
    >>> np.round(theta, 6).tolist(), rank
    ([2.0, 3.0], 2)
    """
    F = np.asarray(F, dtype=float)
    Y = np.asarray(Y, dtype=float)
    if weights is not None:
        sw = np.sqrt(np.asarray(weights, dtype=float))
        F = F * sw[:, None]
        Y = Y * (sw if Y.ndim == 1 else sw[:, None])
    # QR with column pivoting is stable for the nearly collinear bases that physics often gives.
    Q, R, piv = linalg.qr(F, mode="economic", pivoting=True)
    d = np.abs(np.diag(R))
    tol = rcond * (d[0] if d.size else 0.0) * max(F.shape)
    rank = int((d > tol).sum())
    Rr = R[:rank, :rank]
    QtY = Q[:, :rank].T @ Y
    sol = linalg.solve_triangular(Rr, QtY)
    p = F.shape[1]
    theta = np.zeros((p,) + Y.shape[1:])
    theta[piv[:rank]] = sol
    Rinv = linalg.solve_triangular(Rr, np.eye(rank))
    cov = np.zeros((p, p))
    cov[np.ix_(piv[:rank], piv[:rank])] = Rinv @ Rinv.T
    return theta, cov, rank
