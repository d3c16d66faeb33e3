"""Profiles of the blend model over the opacity ``alpha`` (per-patch photo polynomials projected out).

Two criteria share the patch data (``Yp`` (p, n, C) image patches, ``Mp`` (p, n) coverage patches,
``Phi`` (n, k) the polynomial design of one patch):

* :class:`DataProfile` - residual sum of squares in the image domain, ``y ~ P (1 - a M) + b M``.
  Its share of the photo-only residual that the mark explains is the detection statistic, and it is
  the objective of the geometric registration.
* :class:`PhotoProfile` - the likelihood of the restored photo. Photo texture that a plane does not
  follow passes through the blend scaled by ``1 - a M``, so it is the *photo* that has the same
  statistics under the mark and beside it: ``(y - b M) / (1 - a M) = P + t`` with ``t`` white, and
  the change of variables adds ``sum log(1 - a M)``. The image-domain RSS lacks that term and prefers
  a large ``a`` wherever the photo is not a plane across the patch (it decouples the two sides of a
  glyph edge), which biased the opacity upwards on textured photos by several percent.

Both are, for a fixed ``alpha``, the core engine's ``Subspace`` separation (tested against it).
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import orthonormal_basis, solve_batched


def design(size: int, degree: int) -> np.ndarray:
    """(size*size, k) polynomial columns of total degree <= ``degree`` on a square patch.

    Parameters
    ----------
    size : int
        Patch side in px.
    degree : int
        Total degree, 0, 1 or 2 (1, 3 or 6 columns); coordinates run over [-1, 1].

    Returns
    -------
    np.ndarray
        (size * size, k) design matrix, pixels in row-major order.

    Examples
    --------
    >>> from odnn_sep.image.profile import design
    >>> design(3, 0).shape, design(3, 1).shape, design(8, 2).shape
    ((9, 1), (9, 3), (64, 6))
    >>> design(3, 1)[0].tolist()
    [1.0, -1.0, -1.0]
    """
    u, v = np.meshgrid(np.linspace(-1, 1, size), np.linspace(-1, 1, size))
    u, v = u.ravel(), v.ravel()
    cols = [np.ones_like(u)]
    if degree >= 1:
        cols += [u, v]
    if degree >= 2:
        cols += [u * u, u * v, v * v]
    return np.stack(cols, axis=1)


def plane_rss(Yp: np.ndarray, Q: np.ndarray) -> np.ndarray:
    """(p,) residual sum of squares of the photo-only model: each patch of ``Yp`` (p, n, C) with its
    plane (the orthonormal columns of ``Q`` (n, k)) projected out of every channel, no mark.

    Parameters
    ----------
    Yp : np.ndarray
        (p, n, C) image patches.
    Q : np.ndarray
        (n, k) orthonormal basis of the patch polynomials.

    Returns
    -------
    np.ndarray
        (p,) residual sum of squares per patch.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.profile import design, plane_rss
    >>> Q = np.linalg.qr(design(4, 1))[0]
    >>> Yp = np.zeros((2, 16, 1)); Yp[0, :, 0] = design(4, 1)[:, 1]; Yp[1, 0, 0] = 1.0
    >>> np.round(plane_rss(Yp, Q), 4).tolist()
    [0.0, 0.7125]
    """
    Yt = Yp - np.einsum("nk,pkc->pnc", Q, np.einsum("nk,pnc->pkc", Q, Yp))
    return np.sum(Yt * Yt, axis=(1, 2))


class DataProfile:
    """RSS(alpha) with the per-patch polynomials and the shared b projected out (image domain).

    Parameters
    ----------
    Yp : np.ndarray
        (p, n, C) image patches.
    Mp : np.ndarray
        (p, n) coverage patches.
    Phi : np.ndarray
        (n, k) polynomial design of one patch (:func:`design`).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import patch_grid, take_patches
    >>> from odnn_sep.image.profile import DataProfile, design
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.5 * xx, 0.3 + 0.4 * yy, 0.5 + 0.2 * xx], -1)
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None] * np.array([1.0, 1.0, 0.0])
    >>> py, px, s = patch_grid(M, 8, 1000, np.random.default_rng(0))
    >>> Yp, Mp = take_patches(y, py, px, s), take_patches(M, py, px, s)[:, :, 0]
    >>> prof = DataProfile(Yp, Mp, design(s, 1))
    >>> bool(prof(0.4) < 1e-9), bool(prof(0.2) > 1.0)
    (True, True)
    >>> np.round(prof.parts(0.4)[0], 4).tolist()
    [0.4, 0.4, 0.0]
    """

    def __init__(self, Yp, Mp, Phi, _image=None):
        self.Yp, self.Mp, self.Phi = Yp, Mp, Phi
        self.w = np.ones(len(Mp))
        self.mm = np.einsum("pn,pn->p", Mp, Mp)
        # what depends on the image patches only: shared by ``with_coverage`` (a registration tries
        # hundreds of coverages on the same patches)
        if _image is None:
            Yt = np.ascontiguousarray(np.transpose(Yp, (0, 2, 1)))  # (p, C, n): one GEMM per product below
            k = Phi.shape[1]
            _image = (Yt, np.einsum("pcn,pcn->pc", Yt, Yt),
                      (Phi[:, :, None] * Phi[:, None, :]).reshape(len(Phi), k * k))
        self._Yt, self.yy, self._pp = _image
        self._my = np.einsum("pcn,pn->pc", self._Yt, Mp)           # M^T y per patch and channel

    def with_coverage(self, Mp) -> "DataProfile":
        """The profile of the same image patches under another coverage ``Mp`` (p, n).

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.image.profile import DataProfile, design
        >>> rng = np.random.default_rng(0)
        >>> Yp, M1, M2 = rng.random((5, 16, 3)), rng.random((5, 16)), rng.random((5, 16))
        >>> a = DataProfile(Yp, M1, design(4, 1)).with_coverage(M2)
        >>> bool(np.isclose(a(0.3), DataProfile(Yp, M2, design(4, 1))(0.3)))
        True
        """
        return DataProfile(self.Yp, Mp, self.Phi, (self._Yt, self.yy, self._pp))

    def stats(self, alpha: float):
        """Per-patch (sxx (p,), sxy (p, C), syy (p,)) of M and y with the plane part removed."""
        # Gram-matrix form of the per-patch projections (3-6 columns): much faster than a batched QR.
        # With A = diag(u) Phi: A^T A = (u^2) @ (Phi_k Phi_l), A^T M = (u M) @ Phi and A^T y =
        # (u y) @ Phi, each one matrix product over all patches.
        u = 1.0 - alpha * self.Mp                                   # (p, n)
        Phi, Yt, Mp = self.Phi, self._Yt, self.Mp
        p, C, n = Yt.shape
        k = Phi.shape[1]
        G = ((u * u) @ self._pp).reshape(p, k, k) + 1e-12 * np.eye(k)[None]
        am = (u * Mp) @ Phi                                         # A^T M  (p, k)
        ay = ((Yt * u[:, None, :]).reshape(p * C, n) @ Phi).reshape(p, C, k).transpose(0, 2, 1)  # A^T y (p, k, C)
        rhs = np.concatenate([am[:, :, None], ay], axis=2)
        # well conditioned by construction (full-rank plane design, u >= 0.005, regularised): no check
        sol = solve_batched(G, rhs, check=False)                    # G^-1 [A^T M, A^T y]
        gm, gy = sol[:, :, :1], sol[:, :, 1:]
        sxx_p = self.mm - np.sum(am * gm[:, :, 0], axis=1)
        sxy_p = self._my - np.sum(am[:, :, None] * gy, axis=1)
        syy_p = self.yy - np.sum(ay * gy, axis=1)
        return sxx_p, sxy_p, syy_p

    def parts(self, alpha: float, beta=None):
        """(beta (C,), per-patch RSS (p,)); ``beta`` given: the RSS of that colour, not the best one."""
        sxx_p, sxy_p, syy_p = self.stats(alpha)
        w = self.w
        if beta is None:
            Sxx = float(np.sum(w * sxx_p))
            # the colour must be a colour: b = alpha * col with col in [0, 1]. Channels are independent
            # given alpha, so clipping each 1-D quadratic's minimiser is the constrained optimum.
            beta = np.clip((w @ sxy_p) / max(Sxx, 1e-300), 0.0, alpha)
        rss_p = np.sum(syy_p - 2 * beta[None] * sxy_p + (beta[None] ** 2) * sxx_p[:, None], axis=1)
        return beta, np.maximum(rss_p, 0.0)

    def __call__(self, alpha: float) -> float:
        _, rss_p = self.parts(alpha)
        return float(np.sum(self.w * rss_p))


class PhotoProfile:
    """Negative log-likelihood(alpha) of the restored photo (noise variance profiled out).

    Parameters
    ----------
    Yp : np.ndarray
        (p, n, C) image patches.
    Mp : np.ndarray
        (p, n) coverage patches.
    Phi : np.ndarray
        (n, k) polynomial design of one patch (:func:`design`).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import patch_grid, take_patches
    >>> from odnn_sep.image.profile import PhotoProfile, design
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.5 * xx, 0.3 + 0.4 * yy, 0.5 + 0.2 * xx], -1)
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None] * np.array([1.0, 1.0, 0.0])
    >>> py, px, s = patch_grid(M, 8, 1000, np.random.default_rng(0))
    >>> Yp, Mp = take_patches(y, py, px, s), take_patches(M, py, px, s)[:, :, 0]
    >>> prof = PhotoProfile(Yp, Mp, design(s, 1))
    >>> bool(prof(0.4) < prof(0.2)), np.round(prof.parts(0.4)[0], 4).tolist()
    (True, [0.4, 0.4, 0.0])
    """

    def __init__(self, Yp, Mp, Phi):
        self.Yp, self.Mp, self.Phi = Yp, Mp, Phi
        self.w = np.ones(len(Mp))
        self.Q = orthonormal_basis(Phi, method="qr", rtol=None)    # orthonormal plane basis (n, k)

    def parts(self, alpha: float):
        """(beta (C,), per-patch RSS of the restored photo (p,), u = 1 - alpha M (p, n))."""
        u = 1.0 - alpha * self.Mp
        Q = self.Q
        inv = 1.0 / u
        Yt = self.Yp * inv[:, :, None]                              # restored patches (p, n, C)
        Mt = self.Mp * inv                                          # (p, n)
        # sums of squares and cross products with the plane part removed (no (p, n, C) residual array)
        qy = np.matmul(Yt.transpose(0, 2, 1), Q)                    # (p, C, k)
        qm = Mt @ Q                                                 # (p, k)
        syy = np.einsum("pnc,pnc->p", Yt, Yt) - np.einsum("pck,pck->p", qy, qy)
        sxy = np.matmul(Mt[:, None, :], Yt)[:, 0, :] - np.einsum("pk,pck->pc", qm, qy)
        sxx = np.einsum("pn,pn->p", Mt, Mt) - np.einsum("pk,pk->p", qm, qm)
        w = self.w
        beta = np.clip((w @ sxy) / max(float(w @ sxx), 1e-300), 0.0, alpha)
        rss_p = syy - 2.0 * (sxy @ beta) + sxx * float(beta @ beta)
        return beta, np.maximum(rss_p, 0.0), u

    def __call__(self, alpha: float) -> float:
        _, rss_p, u = self.parts(alpha)
        C = self.Yp.shape[2]
        n_eff = float(np.sum(self.w)) * (self.Mp.shape[1] - self.Phi.shape[1]) * C
        rss = float(np.sum(self.w * rss_p))
        jac = C * float(np.sum(self.w[:, None] * np.log(u)))
        return 0.5 * n_eff * np.log(max(rss, 1e-300) / max(n_eff, 1.0)) + jac
