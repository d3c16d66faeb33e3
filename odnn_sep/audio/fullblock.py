"""The exact solver for full-length blocks: fixed-line columns evaluated once, tracked-comb Gram in
closed form (see :class:`FullBlockFitter`)."""
from __future__ import annotations

import numpy as np
from scipy import linalg

from odnn_sep.audio import fit as _fit

NEAR_BINS = 64.0   # lines closer than this many window bins are coupled in the Gram matrix


class FullBlockFitter:
    """The exact solver for full-length blocks, with the fixed-frequency columns evaluated once.

    A fixed line (tone, further comb) over a block starting at sample ``i0`` is the same column
    pair as over a block starting at 0, turned by the phase ``k * 2 pi * i0 * f / sr``: a change
    of coordinates of its (cos, sin) pair. So the fixed and nuisance columns and their Gram block
    are computed once (at ``i0 = 0``), and each block computes only the tracked comb's columns;
    the fitted coefficients are turned back to the absolute-time phase convention of
    :func:`block_basis`.

    The tracked comb's Gram block needs no sum over samples: over a full sin^2-weighted block its
    harmonics (all at least NEAR_BINS window bins from each other, from 0 Hz and from Nyquist)
    are orthogonal to ~1e-8, so it is ``sum(w) / 2`` times the identity; its couplings to the few
    fixed lines close to a harmonic are slow phasors summed on a coarse grid (:meth:`_near_gram`).
    Same least-squares problem, same answer to single-precision rounding (checked in the tests
    against a float64 solve).
    """

    def __init__(self, L: int, sr: int, ks, fixed_lines, w: np.ndarray, gram_step: int):
        self.L, self.sr, self.ks = L, sr, list(ks)
        self.fixed = list(fixed_lines)
        self.w = np.asarray(w, float)
        self.pm = 2 * len(self.ks)
        pairs = [(fc, k) for fc, kk in _fit._as_combs(self.fixed) for k in kk]
        self.fc = np.array([p[0] for p in pairs], float)
        self.kf = np.array([p[1] for p in pairs], float)
        self.pf = 2 * len(pairs)
        self.R = _fit.block_basis(0, L, 0, sr, 0.0, 0.0, 0.0, [], self.fixed, nuisance=True, dtype=np.float32)
        p = self.pm + self.R.shape[1]
        self.q = gram_step if gram_step > 1 and L // gram_step >= 8 * p else 1
        wq = self.w[:: self.q]
        self.G_rr = _fit._weighted_gram(np.asfortranarray(self.R[:: self.q]), wq, float(self.q)).astype(np.float64)
        self.w32 = self.w.astype(np.float32)
        self.wsum = float(self.w.sum())
        self.cache = {"min_n": L}
        # midpoint grid for the tracked-comb Gram entries (see _near_gram): spacing s samples,
        # fine enough for every difference frequency kept (< NEAR_BINS window bins)
        rate_d = 12 * NEAR_BINS * sr / L
        Jd = int(min(L, np.ceil(L * rate_d / sr)))
        self.s_d = L / Jd
        self.t_d = -0.5 + self.s_d * (np.arange(Jd) + 0.5)
        self.w_d = np.sin(np.pi * (self.t_d + 0.5) / L) ** 2
        self.E_fix = np.exp(-2j * np.pi * np.mod(np.outer(self.kf * self.fc, self.t_d) / sr, 1.0))   # (nf, Jd)

    def fit(self, i0: int, centre: int, f0: float, rate: float, curv: float, Y: np.ndarray):
        """``(theta (2 * lines, C), tracked-comb columns (L, 2K))`` for the block starting at ``i0``
        (fixed lines in absolute time: see :meth:`fixed_hum`; the columns are overwritten by the
        next call), or None when the
        block's basis is not well conditioned in float32 or a harmonic lies within NEAR_BINS window
        bins of 0 Hz or Nyquist (the caller then uses :func:`solve_block`)."""
        L, sr = self.L, self.sr
        pm = self.pm
        if pm:
            fk = np.asarray(self.ks, float) * f0
            margin = NEAR_BINS * sr / L
            if fk.min() < margin or fk.max() > sr / 2 - margin:
                return None
            M = _fit.block_basis(i0, L, centre, sr, f0, rate, curv, self.ks, [], nuisance=False, cache=self.cache,
                            dtype=np.float32)
            G = np.zeros((pm + self.R.shape[1],) * 2)
            G[:pm, :pm] = np.diag(np.full(pm, 0.5 * self.wsum))
            G[pm:, pm:] = self.G_rr
            # couplings between a tracked harmonic and a fixed line more than NEAR_BINS window
            # bins away are below the window's sidelobes there (~1e-6): left at zero, so only
            # the few close pairs (a second comb's k-th line beside the k-th harmonic) are summed
            near = np.abs(np.asarray(self.ks, float)[:, None] * f0 - (self.kf * self.fc)[None, :]) < margin
            if near.any():
                G[:pm, pm: pm + self.pf] = self._near_gram(i0, centre, f0, rate, curv, near)
                G[pm: pm + self.pf, :pm] = G[:pm, pm: pm + self.pf].T
        else:
            G = self.G_rr
        Yw = np.multiply(Y, self.w32[:, None], dtype=np.float32)
        rhs_r = np.dot(self.R.T, Yw)
        rhs = np.vstack([np.dot(M.T, Yw), rhs_r]) if pm else rhs_r
        rhs = rhs.astype(np.float64)
        d = np.sqrt(np.maximum(np.diag(G), 1e-300))
        try:
            c, low = linalg.cho_factor(G / np.outer(d, d), check_finite=False)
            rc = np.diag(c).min() / np.diag(c).max()
        except linalg.LinAlgError:
            return None
        if rc ** 2 < 1e-3:
            return None
        theta = linalg.cho_solve((c, low), rhs / d[:, None], check_finite=False) / d[:, None]
        pf = self.pf
        th_m, th_f = theta[:pm], theta[pm: pm + pf]
        if pf:
            # back to absolute time: (a - i b) at t = 0 of the file
            z = (th_f[0::2] - 1j * th_f[1::2]) * np.exp(-1j * self._alpha(i0))[:, None]
            th_f = np.empty_like(th_f)
            th_f[0::2], th_f[1::2] = z.real, -z.imag
        return np.vstack([th_m, th_f]), (M if pm else np.zeros((L, 0), np.float32))

    def _near_gram(self, i0, centre, f0, rate, curv, near) -> np.ndarray:
        """Gram entries between the tracked columns and the fixed columns (pm, pf).

        With B = sum_t w e^{i (k phi - theta_l)} (difference frequency, slow) and the sum-frequency
        terms negligible (checked by the caller's margins), cos.cos = sin.sin = Re B / 2,
        cos_k.sin_l = -Im B / 2, sin_k.cos_l = Im B / 2. B is a sum over a smooth, band-limited
        summand that vanishes with its slope at both ends of the block, so the midpoint rule on a
        grid well above its bandwidth gives it to ~1e-9.
        """
        tau = (i0 + self.t_d - centre) / self.sr
        phi = 2 * np.pi * tau * (f0 + tau * (rate / 2 + tau * (curv / 6)))
        kk = np.asarray(self.ks, float)
        rows = np.flatnonzero(near.any(axis=1))
        E_m = np.exp(1j * np.outer(kk[rows], phi)) * self.w_d[None, :]
        B = np.zeros(near.shape, complex)
        B[rows] = self.s_d * np.dot(E_m, self.E_fix.T)
        B[~near] = 0.0
        G = np.zeros((2 * len(kk), self.pf))
        G[0::2, 0::2] = 0.5 * B.real
        G[1::2, 1::2] = 0.5 * B.real
        G[0::2, 1::2] = -0.5 * B.imag
        G[1::2, 0::2] = 0.5 * B.imag
        return G

    def _alpha(self, i0: int) -> np.ndarray:
        return 2 * np.pi * self.kf * np.mod(i0 * self.fc / self.sr, 1.0)

    def fixed_hum(self, i0: int, n: int, z: np.ndarray) -> np.ndarray:
        """The fixed lines over samples ``i0 .. i0 + n`` (n <= L) with complex amplitudes ``z``
        (lines, C; ``a - i b`` in absolute time), unwindowed, float32 (n, C)."""
        zr = z * np.exp(1j * self._alpha(i0))[:, None]
        th = np.empty((self.pf, z.shape[1]), np.float32)
        th[0::2], th[1::2] = zr.real, -zr.imag
        return np.dot(self.R[:n, : self.pf], th)
