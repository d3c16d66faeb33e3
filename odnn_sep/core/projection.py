"""Orthogonal projectors onto subspaces, applied without forming the n x n matrix.

:class:`BaseProjector` is the interface every disturbance-class projector implements (``rank``,
:meth:`~BaseProjector.project`, :meth:`~BaseProjector.project_out`); :class:`Projector` is the one
built from explicit columns (SVD or QR), optionally in a weighted inner product. Re-exported by
:mod:`odnn_sep.core.linalg`.
"""
from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import InputError, check_option

__all__ = ["BaseProjector", "Projector", "orthonormal_basis", "project_out"]


class BaseProjector:
    """An orthogonal projector P onto a subspace of R^n (or C^n).

    Subclasses implement :meth:`project` (and, for the network solver, :meth:`project_torch`) and set
    ``rank``, the dimension of the subspace. ``apply`` and ``apply_torch`` are the historical names.

    Examples
    --------
    >>> import numpy as np
    >>> class Mean(BaseProjector):          # projector onto the constants
    ...     rank = 1
    ...     def project(self, v):
    ...         return np.full_like(v, v.mean())
    >>> Mean().project_out(np.array([1.0, 2.0, 3.0])).tolist()
    [-1.0, 0.0, 1.0]
    """

    rank: int

    def project(self, v: np.ndarray) -> np.ndarray:  # pragma: no cover - interface
        """``P v`` for a vector (n,) or for every column of a matrix (n, k)."""
        raise NotImplementedError

    def project_out(self, v: np.ndarray) -> np.ndarray:
        """``(I - P) v``: what the subspace cannot express."""
        return v - self.project(v)

    def project_torch(self, v: Any) -> Any:  # pragma: no cover - interface
        """``P v`` for a torch tensor (used by the network solver's projection layer)."""
        raise NotImplementedError

    def apply(self, v: np.ndarray) -> np.ndarray:
        """Same as :meth:`project` (the name the disturbance classes have always used)."""
        return self.project(v)

    def apply_torch(self, v: Any) -> Any:
        """Same as :meth:`project_torch`."""
        return self.project_torch(v)


def orthonormal_basis(A: ArrayLike, *, method: str = "svd", rtol: float | None = 1e-10, min_scale: float = 0.0) -> np.ndarray:
    """Orthonormal columns spanning the numerical range of ``A`` (n, k), real or complex.

    Parameters
    ----------
    A : array_like, shape (n, k)
        Columns spanning the subspace (1-D: one column).
    method : {"svd", "qr"}
        ``"svd"``: left singular vectors with singular value ``> rtol * s_max`` (rank revealing;
        what the disturbance classes use). ``"qr"``: the Q columns of an unpivoted QR whose
        ``|R_jj| > rtol * max(min_scale, max |R_jj|)``; cheaper, and the rule
        ``odnn_sep.mismatch`` has used (``min_scale=1.0`` there).
    rtol : float or None
        Relative tolerance below which a direction counts as numerically absent; None keeps every
        column of the factorisation (for a basis known to have full column rank).
    min_scale : float
        Floor on the scale the QR tolerance is relative to (ignored by ``"svd"``).

    Returns
    -------
    Q : ndarray, shape (n, r)
        ``Q^H Q = I``; r is the numerical rank.

    Examples
    --------
    >>> import numpy as np
    >>> A = np.c_[np.ones(4), np.arange(4.0), np.arange(4.0) + 1]   # third column is dependent
    >>> orthonormal_basis(A).shape
    (4, 2)
    """
    check_option("method", method, ("svd", "qr"))
    A = np.asarray(A)
    if A.ndim == 1:
        A = A[:, None]
    if A.ndim != 2:
        raise InputError(f"A must be a 2-D (n, k) array of columns; got shape {A.shape}")
    if method == "svd":
        U, s, _ = np.linalg.svd(A, full_matrices=False)
        if rtol is None:
            return U
        keep = s > rtol * (s[0] if s.size else 0)
        return U[:, keep]
    q, r = np.linalg.qr(A)
    if rtol is None:
        return q
    dr = np.abs(np.diag(r))
    keep = dr > rtol * max(min_scale, dr.max(initial=0.0))
    return q[:, keep]


class Projector(BaseProjector):
    """Orthogonal projector onto span(A), optionally in the weighted inner product ``<a, b> = sum w a b``.

    Parameters
    ----------
    A : array_like, shape (n, k)
        Columns spanning the subspace, real or complex; dependent columns are allowed.
    weights : array_like, shape (n,), optional
        Non-negative weights of the inner product. With weights, ``project(v)`` is ``A beta`` for the
        weighted least-squares ``beta`` (so rows of weight 0 get the fitted value, not their own).
    method, rtol, min_scale
        How the orthonormal basis is found, see :func:`orthonormal_basis`.

    Attributes
    ----------
    Q : ndarray, shape (n, r)
        Orthonormal basis (of ``sqrt(w) A`` when weighted).
    rank : int

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1, 1, 5)
    >>> P = Projector(np.c_[np.ones(5), x])
    >>> P.rank, np.allclose(P.project(3 + 2 * x), 3 + 2 * x), np.allclose(P.project_out(x**2).sum(), 0)
    (2, True, True)
    """

    def __init__(self, A: ArrayLike, *, weights: ArrayLike | None = None, method: str = "svd", rtol: float | None = 1e-10,
                 min_scale: float = 0.0):
        A = np.asarray(A)
        if A.ndim == 1:
            A = A[:, None]
        self._sw = None
        self._B = None
        if weights is None:
            self.Q = orthonormal_basis(A, method=method, rtol=rtol, min_scale=min_scale)
        else:
            w = np.asarray(weights, dtype=float)
            if w.shape != (A.shape[0],) or (w < 0).any() or not np.isfinite(w).all():
                raise InputError(f"weights must be {A.shape[0]} finite non-negative numbers; got shape {w.shape}")
            self._sw = np.sqrt(w)
            Aw = A * self._sw[:, None]
            self.Q = orthonormal_basis(Aw, method=method, rtol=rtol, min_scale=min_scale)
            # A beta for the weighted least-squares beta: A pinv(sqrt(w) A) Q Q^H sqrt(w) v
            self._B = A @ (np.linalg.pinv(Aw, rcond=1e-15 if rtol is None else rtol) @ self.Q)
        self.rank = int(self.Q.shape[1])
        self._QH = self.Q.conj().T if np.iscomplexobj(self.Q) else self.Q.T

    def project(self, v: np.ndarray) -> np.ndarray:
        if self._sw is None:
            return self.Q @ (self._QH @ v)
        sw = self._sw if np.ndim(v) == 1 else self._sw[:, None]
        return self._B @ (self._QH @ (sw * v))

    def project_torch(self, v: Any) -> Any:
        import torch

        if self._sw is not None:
            raise InputError("the torch projection layer supports unweighted projectors only")
        Q = torch.as_tensor(self.Q, dtype=v.dtype)
        return Q @ (Q.T @ v)


def project_out(F: ArrayLike, G: ArrayLike, weights: ArrayLike | None = None) -> np.ndarray:
    """Remove from the columns of ``F`` their (weighted) projection onto span(G): ``(I - P_G) F``.

    Parameters
    ----------
    F : array_like, shape (n,) or (n, p)
    G : array_like, shape (n, k)
        Columns spanning the subspace to remove (dependent columns allowed).
    weights : array_like, shape (n,), optional
        Inner-product weights, see :class:`Projector`.

    Returns
    -------
    ndarray, same shape as ``F``

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1, 1, 5)
    >>> np.round(project_out(x + 1, np.ones(5)), 12).tolist()
    [-1.0, -0.5, 0.0, 0.5, 1.0]
    """
    return Projector(G, weights=weights).project_out(np.asarray(F))
