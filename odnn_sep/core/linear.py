"""Weighted linear least squares by pivoted QR (kept for existing callers; see :mod:`odnn_sep.core.linalg`)."""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import LstsqSolution, solve


def lstsq(F: np.ndarray, Y: np.ndarray, weights: np.ndarray | None = None, *, rcond: float = 1e-12) -> LstsqSolution:
    """Solve ``min ||W^(1/2) (Y - F theta)||`` for one or many right-hand sides by pivoted QR.

    The same as ``linalg.solve(F, Y, weights=weights, rcond=rcond, method="qr", return_cov=True)``.

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
    return solve(np.asarray(F, dtype=float), np.asarray(Y, dtype=float), weights=weights, rcond=rcond,
                 method="qr", return_cov=True)
