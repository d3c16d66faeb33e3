"""The numerics every front-end uses: projections, weighted solves, standard errors, variable projection.

One tested place for the algebra of ``y = F theta + g + noise``:

- :class:`Projector`, :func:`project_out`, :func:`orthonormal_basis` (subspaces; from
  :mod:`odnn_sep.core.projection`);
- :func:`solve`: weighted, complex-capable least squares (Cholesky on the normal equations with a
  conditioning check, pivoted QR as the fallback, or either on request);
- :func:`factor_gram` / :func:`solve_batched`: the same Cholesky-with-check for Gram matrices a
  front-end has summed itself (one, or a stack of small ones);
- :func:`noise_variance`, :func:`standard_errors`, :func:`stderr_from_cov`, :func:`intervals`, ``Z95``
  (from :mod:`odnn_sep.core.uncertainty`);
- :func:`varpro_residual`, :func:`varpro`: variable projection for nonlinear parameters phi (from
  :mod:`odnn_sep.core.varpro`).

Examples
--------
>>> import numpy as np
>>> from odnn_sep.core import linalg
>>> x = np.linspace(0, 1, 50)
>>> F = np.c_[np.ones_like(x), x]
>>> theta = linalg.solve(F, 1 + 2 * x)
>>> np.round(theta, 9).tolist()
[1.0, 2.0]
"""
from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike
from scipy import linalg as sla

from odnn_sep.core.projection import BaseProjector, Projector, orthonormal_basis, project_out
from odnn_sep.core.uncertainty import Z95, intervals, noise_variance, standard_errors, stderr_from_cov
from odnn_sep.core.varpro import VarproResult, varpro, varpro_residual
from odnn_sep.errors import InputError, check_option

__all__ = ["Z95", "BaseProjector", "Projector", "orthonormal_basis", "project_out", "solve", "LstsqSolution",
           "GramFactor", "factor_gram", "solve_batched", "noise_variance", "standard_errors", "stderr_from_cov",
           "intervals", "varpro", "varpro_residual", "VarproResult"]

#: Largest condition number (estimated) for which :func:`solve` trusts the normal equations.
MAX_COND = 1e8


class LstsqSolution(NamedTuple):
    """``theta``, the unscaled covariance ``(F^H W F)^+`` and the numerical rank (unpacks as a tuple).

    Examples
    --------
    >>> import numpy as np
    >>> sol = solve(np.c_[np.ones(4)], np.arange(4.0), return_cov=True)
    >>> sol.theta.tolist(), sol.cov_unscaled.tolist(), sol.rank
    ([1.5], [[0.25]], 1)
    """

    theta: np.ndarray
    cov_unscaled: np.ndarray
    rank: int


def _whiten(A, b, weights):
    if weights is None:
        return A, b
    sw = np.sqrt(np.asarray(weights, dtype=float))
    return A * sw[:, None], b * (sw if b.ndim == 1 else sw[:, None])


def _qr_solve(A, b, rcond, want_cov):
    """Pivoted QR (stable for nearly collinear columns); minimum-norm on the numerical rank."""
    Q, R, piv = sla.qr(A, mode="economic", pivoting=True)
    d = np.abs(np.diag(R))
    tol = rcond * (d[0] if d.size else 0.0) * max(A.shape)
    rank = int((d > tol).sum())
    Rr = R[:rank, :rank]
    QhB = (Q[:, :rank].conj().T if np.iscomplexobj(Q) else Q[:, :rank].T) @ b
    sol = sla.solve_triangular(Rr, QhB)
    p = A.shape[1]
    theta = np.zeros((p,) + b.shape[1:], dtype=np.result_type(A, b))
    theta[piv[:rank]] = sol
    if not want_cov:
        return theta, None, rank
    Rinv = sla.solve_triangular(Rr, np.eye(rank))
    cov = np.zeros((p, p), dtype=Rinv.dtype)
    cov[np.ix_(piv[:rank], piv[:rank])] = Rinv @ Rinv.conj().T
    return theta, cov, rank


def solve(A: ArrayLike, b: ArrayLike, *, weights: ArrayLike | None = None, rcond: float = 1e-12, method: str = "auto",
          max_cond: float = MAX_COND, return_cov: bool = False) -> np.ndarray | LstsqSolution:
    """Weighted least squares ``min ||W^(1/2) (b - A theta)||``, real or complex, one or many right-hand sides.

    Parameters
    ----------
    A : array_like, shape (n, p)
        Design matrix (physics columns).
    b : array_like, shape (n,) or (n, k)
        Observations.
    weights : array_like, shape (n,), optional
        Non-negative weights.
    rcond : float
        Relative pivot size below which QR treats a column as dependent (numerical rank).
    method : {"auto", "cholesky", "qr", "lstsq"}
        ``"auto"``: Cholesky on the Jacobi-scaled normal equations when the estimated condition
        number is below ``max_cond`` (fast for tall, well-conditioned bases), otherwise pivoted QR.
        ``"cholesky"`` is the same. ``"qr"``: always pivoted QR (rank-revealing; the separator's
        solver). ``"lstsq"``: :func:`numpy.linalg.lstsq` with ``rcond=None`` (SVD, minimum norm).
    max_cond : float
        Largest estimated condition number of the scaled Gram matrix accepted by Cholesky.
    return_cov : bool
        Also return ``(A^H W A)^+`` (multiply by the noise variance for the covariance of theta)
        and the rank, as an :class:`LstsqSolution`.

    Returns
    -------
    theta : ndarray, shape (p,) or (p, k)
        Or an :class:`LstsqSolution` ``(theta, cov_unscaled, rank)`` with ``return_cov=True``.

    Examples
    --------
    >>> import numpy as np
    >>> F = np.c_[np.ones(5), np.arange(5.0)]
    >>> theta, cov, rank = solve(F, 2 + 3 * np.arange(5.0), method="qr", return_cov=True)
    >>> np.round(theta, 6).tolist(), rank
    ([2.0, 3.0], 2)
    >>> z = solve(F.astype(complex), (1 + 2j) * np.arange(5.0))   # complex amplitudes
    >>> np.round(z, 9).tolist()
    [0j, (1+2j)]
    """
    check_option("method", method, ("auto", "cholesky", "qr", "lstsq"))
    A, b = _design_and_data(A, b)
    Aw, bw = _whiten(A, b, weights)
    if method == "lstsq":
        theta, _, rank, _ = np.linalg.lstsq(Aw, bw, rcond=None)
        return LstsqSolution(theta, np.linalg.pinv(Aw.conj().T @ Aw), int(rank)) if return_cov else theta
    if method in ("auto", "cholesky"):
        AH = Aw.conj().T
        fac = factor_gram(AH @ Aw)
        if fac.rcond >= 1.0 / max_cond:
            theta = fac.solve(AH @ bw)
            if not return_cov:
                return theta
            return LstsqSolution(theta, fac.solve(np.eye(A.shape[1])), A.shape[1])
    theta, cov, rank = _qr_solve(Aw, bw, rcond, return_cov)
    return LstsqSolution(theta, cov, rank) if return_cov else theta


def _design_and_data(A, b) -> tuple[np.ndarray, np.ndarray]:
    """``A`` (n, p) and ``b`` (n,) or (n, k) as float or complex arrays with the same n, else InputError."""
    A = np.asarray(A)
    b = np.asarray(b)
    if A.dtype.kind not in "fc":
        A = A.astype(float)
    if b.dtype.kind not in "fc":
        b = b.astype(float)
    if A.ndim != 2 or b.ndim not in (1, 2) or b.shape[0] != A.shape[0]:
        raise InputError(f"solve needs A (n, p) and b (n,) or (n, k) with the same n; got {A.shape} and {b.shape}")
    return A, b


class GramFactor:
    """Cholesky factor of a Jacobi-scaled Gram matrix ``G / (d d^T)``, ``d = sqrt(diag G)``.

    ``rcond`` is ``(min diag L / max diag L)^2``, a cheap estimate of 1 / cond of the scaled
    matrix (0 when ``G`` is not numerically positive definite); compare it with ``1 / max_cond``
    before trusting :meth:`solve`. Build it with :func:`factor_gram`.

    Examples
    --------
    >>> import numpy as np
    >>> fac = factor_gram(np.array([[4.0, 2.0], [2.0, 2.0]]))
    >>> fac.ok, round(fac.rcond, 6), fac.solve(np.array([6.0, 4.0])).round(12).tolist()
    (True, 0.5, [1.0, 1.0])
    >>> factor_gram(np.array([[1.0, 1.0], [1.0, 1.0]])).rcond     # singular: 0, solve by QR instead
    0.0
    """

    def __init__(self, factor: tuple[np.ndarray, bool] | None, scale: np.ndarray, rcond: float):
        self.factor, self.scale, self.rcond = factor, scale, rcond

    @property
    def ok(self) -> bool:
        """Whether the factorisation succeeded (``rcond > 0``)."""
        return self.factor is not None

    def solve(self, rhs: ArrayLike) -> np.ndarray:
        """``G^-1 rhs`` for rhs (p,) or (p, k)."""
        if self.factor is None:
            raise InputError("the Gram matrix is not positive definite; solve by QR instead (solve(..., method='qr'))")
        d = self.scale if np.ndim(rhs) == 1 else self.scale[:, None]
        return sla.cho_solve(self.factor, rhs / d, check_finite=False) / d


def factor_gram(G: ArrayLike) -> GramFactor:
    """Jacobi-scaled Cholesky of a Hermitian positive semi-definite Gram matrix ``G`` (p, p).

    Scaling by ``sqrt(diag G)`` first makes the pivot ratio a scale-free conditioning check;
    the audio block solver's acceptance tests (``rcond >= 1 / 1e8`` in float64, ``>= 1e-3`` for
    float32 sums) are comparisons of :attr:`GramFactor.rcond`.

    Parameters
    ----------
    G : array_like, shape (p, p)
        Hermitian positive semi-definite Gram matrix (real or complex).

    Returns
    -------
    GramFactor
        With ``solve`` and the reciprocal pivot ratio ``rcond``.

    Examples
    --------
    >>> import numpy as np
    >>> F = np.c_[np.ones(100), np.linspace(0, 1, 100)]
    >>> fac = factor_gram(F.T @ F)
    >>> fac.rcond > 1e-3, np.round(fac.solve(F.T @ (1 - F[:, 1])), 9).tolist()
    (True, [1.0, -1.0])
    """
    G = np.asarray(G)
    diag = np.diag(G).real if np.iscomplexobj(G) else np.diag(G)
    d = np.sqrt(np.maximum(diag, 1e-300))
    try:
        c, low = sla.cho_factor(G / np.outer(d, d), check_finite=False)
    except sla.LinAlgError:
        return GramFactor(None, d, 0.0)
    dc = np.abs(np.diag(c))
    rc = dc.min() / dc.max()
    if not np.isfinite(rc):
        return GramFactor(None, d, 0.0)
    return GramFactor((c, low), d, float(rc ** 2))


def solve_batched(G: ArrayLike, r: ArrayLike, *, max_cond: float = MAX_COND, check: bool = True) -> np.ndarray:
    """Solve ``G x = r`` for a Gram matrix or a stack of them, Cholesky with a per-system fallback.

    Parameters
    ----------
    G : array_like, shape (..., p, p)
        Hermitian positive semi-definite Gram matrices (``F^H W F``).
    r : array_like, shape (..., p) or (..., p, k)
        Right-hand sides (``F^H W y``); numpy's rule: a 1-D ``r`` is one vector, otherwise the
        last two axes are a matrix.
    max_cond : float
        Systems whose estimated condition number (see :class:`GramFactor`) exceeds this, or that
        are not positive definite, are solved one by one with :func:`numpy.linalg.lstsq` on the
        Gram matrix (minimum-norm: ``pinv(G) r``).
    check : bool
        False: the caller vouches that every system is well conditioned (e.g. the Gram matrices of
        a fixed full-rank design under positive weights, regularised), and the stack is solved at
        once with :func:`numpy.linalg.solve`, without the conditioning check (a hot loop's fast path).

    Returns
    -------
    ndarray, shape of ``r`` broadcast against the stack.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.stack([np.eye(2) * 2, np.array([[1.0, 1.0], [1.0, 1.0]])])   # second is singular
    >>> solve_batched(G, np.ones((2, 2, 1)))[..., 0].round(12).tolist()
    [[0.5, 0.5], [0.5, 0.5]]
    """
    G = np.asarray(G)
    r = np.asarray(r)
    if G.ndim < 2 or G.shape[-1] != G.shape[-2]:
        raise InputError(f"G must be a (..., p, p) stack of square matrices; got shape {G.shape}")
    if not check:
        return np.linalg.solve(G, r[..., None])[..., 0] if r.ndim == 1 else np.linalg.solve(G, r)
    if G.ndim == 2:
        fac = factor_gram(G)
        if fac.rcond >= 1.0 / max_cond:
            return fac.solve(r)
        return np.linalg.lstsq(G, r, rcond=None)[0]
    vec = r.ndim == 1
    rm = r[..., None] if vec else r
    batch = np.broadcast_shapes(G.shape[:-2], rm.shape[:-2])
    Gb = np.broadcast_to(G, batch + G.shape[-2:]).reshape((-1,) + G.shape[-2:])
    rb = np.broadcast_to(rm, batch + rm.shape[-2:]).reshape((-1,) + rm.shape[-2:])
    diag = np.diagonal(Gb, axis1=1, axis2=2)
    d = np.sqrt(np.maximum(diag.real, 1e-300))
    Gs = Gb / (d[:, :, None] * d[:, None, :])
    good = _cholesky_ok(Gs, max_cond)
    out = np.empty(rb.shape, dtype=np.result_type(Gb, rb))
    if good.any():
        out[good] = np.linalg.solve(Gs[good], rb[good] / d[good][:, :, None]) / d[good][:, :, None]
    for i in np.flatnonzero(~good):
        out[i] = np.linalg.lstsq(Gb[i], rb[i], rcond=None)[0]
    out = out.reshape(batch + rm.shape[-2:])
    return out[..., 0] if vec else out


def _cholesky_ok(Gs: np.ndarray, max_cond: float) -> np.ndarray:
    """Per scaled Gram matrix of the stack: positive definite with pivot ratio^2 >= 1 / max_cond."""
    try:
        L = np.linalg.cholesky(Gs)
        dl = np.abs(np.diagonal(L, axis1=1, axis2=2))
        return (dl.min(axis=1) / dl.max(axis=1)) ** 2 >= 1.0 / max_cond
    except np.linalg.LinAlgError:
        return np.array([factor_gram(g).rcond >= 1.0 / max_cond for g in Gs], dtype=bool)
