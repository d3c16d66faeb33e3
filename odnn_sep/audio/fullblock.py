"""The exact solver for full-length blocks: fixed-line sums through one short table, tracked-comb
Gram in closed form (see :class:`FullBlockFitter`)."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import fit as _fit
from odnn_sep.audio import gram as _gram
from odnn_sep.audio.blockplan import sin2_window
from odnn_sep.audio.lines import as_combs
from odnn_sep.audio.stretch import WHOLE_CHUNK, StretchPowers, phasor_powers
from odnn_sep.core.linalg import factor_gram

NEAR_BINS = 64.0   # lines closer than this many window bins are coupled in the Gram matrix
CHUNK = 4096       # samples per chunk of the fixed-line table (its products stay in cache)


class FullBlockFitter:
    """The exact solver for full-length blocks, without a per-block basis for the fixed lines.

    A fixed line (tone, further comb) at sample ``i0 + j c + u`` of a block (chunk ``j`` of
    ``c`` samples, offset ``u``) is ``exp(i theta(i0)) exp(i theta(j c)) exp(i theta(u))``: the same
    short table of ``c`` rows for every chunk of every block, turned by a phase per chunk. So the
    window-weighted sums of the samples against the fixed columns are one product of the samples
    (chunks as rows) with that table, combined over chunks with the chunk phasors, and the fixed
    lines' hum is the table times per-chunk coefficients: no basis the length of a block is
    evaluated or read for them. The constant and trend nuisance columns ride along (the table
    holds ``1`` and ``u``).

    The tracked comb's columns are the powers of one complex phasor per sample (kept, so the fitted
    comb is synthesised from the same powers). Its Gram block needs no sum over samples: over a
    full sin^2-weighted block its harmonics (all at least NEAR_BINS window bins from each other,
    from 0 Hz and from Nyquist) are orthogonal to ~1e-8, so it is ``sum(w) / 2`` times the
    identity; its couplings to the few fixed lines close to a harmonic are slow phasors summed on
    a coarse grid (:meth:`_near_gram`). The fixed and nuisance Gram block is computed once.
    Same least-squares problem as :func:`fit.solve_block` on :func:`fit.block_basis`, same answer
    to single-precision rounding (checked in the tests against a float64 solve).

    Fitted amplitudes of the fixed lines are in absolute time (phase at sample 0 of the input);
    the tracked comb's in the block's own reference (its centre).

    Parameters
    ----------
    L : int
        Full block length (samples).
    sr : int
        Sample rate (Hz).
    ks : sequence of int
        Tracked harmonics.
    fixed_lines : sequence
        Fixed frequencies (Hz) or ``(fundamental, harmonics)`` combs.
    w : (L,) array
        The full block's window.
    gram_step : int
        Row step of a sub-sampled Gram matrix.
    chunk : int
        Samples per chunk of the fixed-line table.

    Examples
    --------
    >>> from odnn_sep.audio.blockplan import sin2_window
    >>> sr, L = 1000, 4000; t = np.arange(L)
    >>> y = 0.8 * np.cos(2 * np.pi * 50 * (t - 2000) / sr + 0.3) + 0.2 * np.cos(2 * np.pi * 170 * t / sr)
    >>> fitter = FullBlockFitter(L, sr, [1], [170.0], sin2_window(t + 0.5, L), gram_step=1)
    >>> theta = fitter.fit(0, 2000, 50.0, 0.0, 0.0, [y[:, None]])     # h1 (cos, sin), then 170 Hz
    >>> theta.shape, theta[:3, 0].round(4).tolist()
    ((4, 1), [0.7643, -0.2364, 0.2])
    """

    def __init__(self, L: int, sr: int, ks, fixed_lines, w: np.ndarray, gram_step: int, chunk: int = CHUNK):
        self.L, self.sr, self.ks = L, sr, list(ks)
        self.fixed = list(fixed_lines)
        self.pm = 2 * len(self.ks)
        pairs = [(fc, k) for fc, kk in as_combs(self.fixed) for k in kk]
        self.fc = np.array([p[0] for p in pairs], float)
        self.kf = np.array([p[1] for p in pairs], float)
        self.nf = len(pairs)
        self.pf = 2 * self.nf
        self.gram_step = gram_step
        w = np.asarray(w, float)
        self._win = {L: (w, w.astype(np.float32), float(w.sum()))}
        self._grr, self._near = {}, {}
        self.tau_cache = {"min_n": L}
        self.phase = None      # finetrack.PhaseTrack: set to fit along the refined phase
        self.stretches = None  # stretch.StretchPowers: powers per half block (:meth:`use_stretches`)
        self._parts = None     # the last fitted block's stretches (:meth:`fit`, :meth:`block_hum`)
        self.amplitudes_given = False   # the caller replaces the tracked amplitudes (:meth:`fit`)
        # chunk table: fixed columns over one chunk (as block_basis from sample 0), then 1 and u
        c = int(max(1, min(chunk, L)))
        self.c, self.nch = c, -(-L // c)
        self.fixed_spec = _fit.BasisSpec(sr, (), tuple(self.fixed), nuisance=True)
        Rc = _fit.block_basis(self.fixed_spec, 0, c, 0, dtype=np.float32)
        Rc[:, self.pf + 1] = np.arange(c, dtype=np.float32)
        self.Rc = np.ascontiguousarray(Rc)                              # (c, pf + 2)
        self.RcT = np.ascontiguousarray(Rc[:, : self.pf].T)             # (pf, c)
        # chunk phasors exp(i theta_l(j c)) relative to the block start (the same for every block)
        self.E = np.exp(2j * np.pi * self.kf[:, None] * np.mod(np.outer(self.fc, np.arange(self.nch) * c) / sr, 1.0))
        # the tracked comb's powers: two slots, so that the next block's can be evaluated ahead
        # (:meth:`prepare`, in a worker thread) while this block's are in use
        self._Zs = [np.empty((len(self.ks), L), np.complex64) if self.pm else None, None]
        self.Z = self._Zs[0]
        self._ready = {}       # slot -> the block (i0, n, centre) whose powers it holds
        self._Yw = None
        self._bufs = {}

    def use_stretches(self, hop: int, n_frames: int):
        """Evaluate the tracked comb's powers once per half block (stretch.py) instead of once per
        block: needs the refined phase (``self.phase``) and blocks of ``2 hop`` samples centred
        at multiples of ``hop``. The same sums and hum as per block, to single-precision rounding
        of the powers (half the evaluations)."""
        if self.pm and self.phase is not None and self.L == 2 * hop:
            self.stretches = StretchPowers(self.ks, hop, n_frames, self.phase)

    def window(self, n: int):
        """``(w, w float32, sum w)``: the sin^2 fit window over ``n`` samples (the block's own for
        a full block, a Hann over the visible part of a block cut by the signal's ends)."""
        got = self._win.get(n)
        if got is None:
            w = sin2_window(np.arange(n) + 0.5, n)
            got = self._win[n] = (w, w.astype(np.float32), float(w.sum()))
        return got

    def gram_fixed(self, n: int) -> np.ndarray:
        """Gram block of the fixed and nuisance columns (block-start phase reference) under the
        window over ``n`` samples: closed form (gram.py) when every line is well inside the
        band, else summed on a sub-sampled basis."""
        G = self._grr.get(n)
        if G is None:
            margin = NEAR_BINS * self.sr / n
            f = self.kf * self.fc
            if not len(f) or (f.min() >= margin and f.max() <= self.sr / 2 - margin):
                G = _gram.fixed_gram(2 * np.pi * f / self.sr, n)
            else:
                p = self.pm + self.pf + 2
                q = self.gram_step if _fit.sub_gram(n, p, self.gram_step) else 1
                R_sub = _fit.block_basis(self.fixed_spec, 0, n, 0, step=q, dtype=np.float32)
                G = _fit.weighted_gram(R_sub, self.window(n)[0][::q], float(q)).astype(np.float64)
            self._grr[n] = G
        return G

    def weighted(self, parts, w32) -> np.ndarray:
        """The samples times the window ``w32``, channels as rows, float32 (C, nch * c), zero past
        the block's end; ``parts``: consecutive (m, C) pieces of the block."""
        C = parts[0].shape[1]
        if self._Yw is None or self._Yw.shape[0] != C:
            self._Yw = np.zeros((C, self.nch * self.c), np.float32)
        Yw = self._Yw
        a = 0
        for y in parts:
            b = a + y.shape[0]
            np.multiply(y.T, w32[a:b], out=Yw[:, a:b], dtype=np.float32)
            a = b
        Yw[:, a:] = 0.0
        return Yw

    def prepare(self, i0: int, n: int, centre: int, f0: float, rate: float, curv: float, slot: int):
        """Evaluate the tracked comb's powers for the block ``i0 .. i0 + n`` (centre ``centre``)
        into ``slot`` (0 or 1) ahead of its :meth:`fit`. Safe in a worker thread while the other
        slot is in use (every work array it touches is the slot's own)."""
        if self.stretches is not None:
            # this block's own stretch (the one before it was its predecessor's)
            self.stretches.compute(centre // self.stretches.hop)
            return
        self._ready.pop(slot, None)
        if self.pm and 16 <= n <= self.L:
            self._powers(i0, n, centre, f0, rate, curv, slot)
            self._ready[slot] = (i0, n, centre)

    def fit(self, i0: int, centre: int, f0: float, rate: float, curv: float, parts, n: int | None = None,
            slot: int = 0):
        """``theta (2 * lines, C)`` for the block whose samples ``i0 .. i0 + n`` are ``parts``
        (consecutive (m, C) pieces; ``n`` defaults to the full block, a shorter one is weighted
        by a Hann over its ``n`` samples), or None when the closed-form Gram does not hold (a
        tracked harmonic within NEAR_BINS window bins of 0 Hz, of Nyquist or of another one) or
        the basis is not well conditioned in float32: the caller then uses
        :func:`fit.solve_block`. The tracked comb's powers are kept for :meth:`block_hum`
        until the next call: those :meth:`prepare` left in ``slot`` when they are this block's,
        else evaluated into ``slot`` here (why nine parameters: the block, its track, its samples
        and the slot).

        With :attr:`amplitudes_given` set (the caller replaces the tracked comb's fitted
        amplitudes by amplitudes it already has, the amplitude paths), where no fixed line is
        coupled to a harmonic (the Gram matrix is block diagonal) the fixed lines' solution does
        not depend on the tracked sums, so they are not formed (their rows of ``theta`` are zero);
        without fixed lines the samples are not weighted at all. The fixed lines' values are the
        same either way."""
        n = self.L if n is None else int(n)
        pm = self.pm
        if n < 16 or n > self.L:
            return None
        w32 = self.window(n)[1]
        G, coupled = self._block_gram(i0, n, centre, f0, rate, curv)
        if G is None:
            return None
        known_tracked = self.amplitudes_given and not coupled
        fac = factor_gram(G)
        if fac.rcond < 1e-3:                 # not positive definite (rcond 0) or cond > 1e3: general path
            return None
        C = parts[0].shape[1]
        if pm and self.stretches is not None:
            self._parts = self.stretches.parts(i0, n, centre)
        elif pm:
            if self._ready.get(slot) != (i0, n, centre):
                self.prepare(i0, n, centre, f0, rate, curv, slot)
            self.Z = self._Zs[slot]
        if pm and known_tracked and not self.pf:
            # only the tracked comb, its amplitudes given: nothing to sum (the nuisance columns'
            # coefficients are not part of the hum)
            return np.zeros((pm, C))
        Yw = self.weighted(parts, w32)
        rhs_r = self.fixed_sums(Yw, n)
        if pm:
            rhs_m = np.zeros((pm, C)) if known_tracked else self.tracked_sums(Yw, n)
            rhs = np.vstack([rhs_m, rhs_r])
        else:
            rhs = rhs_r
        theta = fac.solve(rhs)
        pf = self.pf
        th_m, th_f = theta[:pm], theta[pm: pm + pf]
        if pf:
            # back to absolute time: (a - i b) at t = 0 of the file
            z = (th_f[0::2] - 1j * th_f[1::2]) * np.exp(-1j * self._alpha(i0))[:, None]
            th_f = np.empty_like(th_f)
            th_f[0::2], th_f[1::2] = z.real, -z.imag
        return np.vstack([th_m, th_f])

    def _block_gram(self, i0: int, n: int, centre: int, f0: float, rate: float, curv: float):
        """The block's Gram matrix and whether a fixed line is coupled to a tracked harmonic;
        ``(None, False)`` where the closed form does not hold (see :meth:`fit`)."""
        pm, sr = self.pm, self.sr
        G_rr = self.gram_fixed(n)
        if not pm:
            return G_rr, False
        kk = np.asarray(self.ks, float)
        fk = kk * f0
        margin = NEAR_BINS * sr / n
        if fk.min() < margin or fk.max() > sr / 2 - margin or (len(kk) > 1 and np.diff(fk).min() < margin):
            return None, False
        G = np.zeros((pm + G_rr.shape[0],) * 2)
        G[:pm, :pm] = np.diag(np.full(pm, 0.5 * self.window(n)[2]))
        G[pm:, pm:] = G_rr
        # couplings between a tracked harmonic and a fixed line more than NEAR_BINS window
        # bins away are below the window's sidelobes there (~1e-6): left at zero, so only
        # the few close pairs (a second comb's k-th line beside the k-th harmonic) are summed
        near = np.abs(kk[:, None] * f0 - (self.kf * self.fc)[None, :]) < margin
        if near.any():
            G[:pm, pm: pm + self.pf] = self._near_gram(i0, n, centre, f0, rate, curv, near)
            G[pm: pm + self.pf, :pm] = G[:pm, pm: pm + self.pf].T
        return G, bool(near.any())

    def fixed_sums(self, Yw, n: int) -> np.ndarray:
        """Sums of the weighted samples ``Yw`` (C, nch * c; zero past ``n``) against the fixed
        columns (block-start phase reference) and the two nuisance columns (constant, trend
        ``-1 + 2 t / (n - 1)``): (pf + 2, C), float64."""
        C = Yw.shape[0]
        S = np.dot(Yw.reshape(C * self.nch, self.c), self.Rc).astype(np.float64)
        S = S.reshape(C, self.nch, self.pf + 2)
        out = np.empty((self.pf + 2, C))
        if self.pf:
            X = S[:, :, 0: self.pf: 2] + 1j * S[:, :, 1: self.pf: 2]             # (C, nch, nf)
            Z = np.einsum("lj,cjl->lc", self.E, X)
            out[0: self.pf: 2], out[1: self.pf: 2] = Z.real, Z.imag
        out[self.pf] = S[:, :, self.pf].sum(axis=1)
        slope = 2.0 / max(n - 1, 1)
        tr0 = -1.0 + slope * self.c * np.arange(self.nch)
        out[self.pf + 1] = np.dot(S[:, :, self.pf], tr0) + slope * S[:, :, self.pf + 1].sum(axis=1)
        return out

    def _powers(self, i0, n, centre, f0, rate, curv, slot: int = 0):
        """The tracked harmonics' phasors over samples ``i0 .. i0 + n`` into slot ``slot``'s
        powers (``[:, :n]``): powers of one phasor per sample (stretch.phasor_powers)."""
        # phase in cycles; its fraction is rounded to float32 as it is written (work arrays kept
        # across blocks: fresh ones of a block's length cost more in page faults than the sums)
        if self.phase is not None:
            cyc = self.phase.cycles(i0, n, centre, scratch=slot)
        else:
            cyc = _fit.tracked_cycles(self._tau(i0, n, centre), f0, rate, curv)
        if self._Zs[slot] is None:
            self._Zs[slot] = np.empty_like(self._Zs[0])
        phasor_powers(cyc, self.ks, self._Zs[slot], self._buffer(f"r32{slot}", np.float32, self.L),
                      self._buffer(f"whole{slot}", np.float64, WHOLE_CHUNK))

    def _tau(self, i0: int, n: int, centre: int) -> np.ndarray:
        """Times (s) of samples ``i0 .. i0 + n`` from the block centre (kept for full blocks: every
        full block has the same offsets)."""
        key = (n, i0 - centre)
        kept = self.tau_cache.get("kept")          # one (key, tau) pair: read at once by either thread
        if kept is not None and kept[0] == key:
            return kept[1]
        tau = (i0 + np.arange(n) - centre) / self.sr
        if n >= self.tau_cache["min_n"]:
            self.tau_cache["kept"] = (key, tau)
        return tau

    def _buffer(self, name: str, dtype, size: int) -> np.ndarray:
        """A flat work array kept across blocks (no page faults on a fresh 1-2 MB per block)."""
        buf = self._bufs.get(name)
        if buf is None or buf.size < size or buf.dtype != dtype:
            buf = self._bufs[name] = np.zeros(size, dtype)
        return buf

    def tracked_sums(self, Yw, n) -> np.ndarray:
        """Sums of ``Yw`` against the tracked columns (cos, sin per harmonic): (pm, C), float64."""
        C = Yw.shape[0]
        # complex copy of the weighted samples (imaginary part zero) for one cgemm; block_hum
        # uses the same buffer for the synthesis afterwards, so the imaginary part is cleared
        Yc = self._buffer("yc", np.complex64, C * self.L)[: C * n].reshape(C, n)
        Yc.real = Yw[:, :n]
        Yc.imag = 0.0
        if self.stretches is not None:
            X = np.zeros((len(self.ks), C), complex)
            for P, a, m, rho in self._parts:
                Xp = np.dot(P, Yc[:, a: a + m].T)
                X += Xp if rho is None else rho[:, None] * Xp
        else:
            X = np.dot(self.Z[:, :n], Yc.T)                                          # (K, C)
        out = np.empty((self.pm, C))
        out[0::2], out[1::2] = X.real, X.imag
        return out

    def block_hum(self, i0: int, n: int, z: np.ndarray, tracked: bool, slot: int) -> np.ndarray:
        """The fitted hum over samples ``i0 .. i0 + n`` (n <= L), unwindowed, float32 (C, n):
        the fixed lines with complex amplitudes ``z[K:]`` (``a - i b``, absolute time) plus, when
        ``tracked``, the tracked comb with ``z[:K]`` (block reference) from the powers kept by the
        last :meth:`fit`. ``slot`` (0/1) picks one of two buffers: the result stays valid while
        the next block's hum is built in the other one."""
        C = z.shape[1]
        K = len(self.ks)
        nch = -(-n // self.c)
        flat = self._buffer(f"hum{slot}", np.float32, C * self.nch * self.c)
        H = flat[: C * nch * self.c].reshape(C * nch, self.c)
        if self.pf:
            # per chunk: amplitude turned to the chunk's start, as (cos, -sin) coefficients
            b = (z[K:] * np.exp(1j * self._alpha(i0))[:, None])[:, :, None] * self.E[:, None, :nch]   # (nf, C, nch)
            coef = np.empty((self.pf, C, nch), np.float32)
            coef[0::2], coef[1::2] = b.real, -b.imag
            np.dot(coef.reshape(self.pf, C * nch).T, self.RcT, out=H)
        hum = H.reshape(C, nch * self.c)[:, :n]
        if tracked and K and self.stretches is not None:
            self._stretch_hum(z[:K], hum)
        elif tracked and K:
            # (the complex samples' buffer of tracked_sums: free again once the block is solved)
            T = self._buffer("yc", np.complex64, C * self.L)[: C * n].reshape(C, n)
            np.dot(z[:K].T.astype(np.complex64), self.Z[:, :n], out=T)
            if self.pf:
                hum += T.real
            else:
                np.add(T.real, np.float32(0.0), out=hum)     # 0 + T.real without zeroing first
        elif not self.pf:
            hum[:] = 0.0
        return hum

    def _stretch_hum(self, zk: np.ndarray, hum: np.ndarray):
        """Add (or, without fixed lines, write) the tracked comb with amplitudes ``zk`` (K, C; block
        reference) into ``hum`` (C, n) from the last fitted block's stretches."""
        C = zk.shape[1]
        for P, a, m, rho in self._parts:
            coef = (zk if rho is None else zk * rho[:, None]).T.astype(np.complex64)
            T = self._buffer("yc", np.complex64, C * self.L)[: C * m].reshape(C, m)
            np.dot(coef, P, out=T)
            if self.pf:
                hum[:, a: a + m] += T.real
            else:
                np.add(T.real, np.float32(0.0), out=hum[:, a: a + m])

    def _near_gram(self, i0, n, centre, f0, rate, curv, near) -> np.ndarray:
        """Gram entries between the tracked columns and the fixed columns (pm, pf).

        With B = sum_t w e^{i (k phi - theta_l)} (difference frequency, slow) and the sum-frequency
        terms negligible (checked by the caller's margins), cos.cos = sin.sin = Re B / 2,
        cos_k.sin_l = -Im B / 2, sin_k.cos_l = Im B / 2. B is a sum over a smooth, band-limited
        summand that vanishes with its slope at both ends of the block, so the midpoint rule on a
        grid well above its bandwidth gives it to ~1e-9.
        """
        got = self._near.get(n)
        if got is None:
            # midpoint grid: spacing s samples, fine enough for every difference frequency kept
            # (< NEAR_BINS window bins)
            Jd = int(min(n, np.ceil(12 * NEAR_BINS)))
            s_d = n / Jd
            t_d = -0.5 + s_d * (np.arange(Jd) + 0.5)
            w_d = sin2_window(t_d + 0.5, n)
            E_fix = np.exp(-2j * np.pi * np.mod(np.outer(self.kf * self.fc, t_d) / self.sr, 1.0))   # (nf, Jd)
            got = self._near[n] = (s_d, t_d, w_d, E_fix)
        s_d, t_d, w_d, E_fix = got
        if self.phase is not None:
            phi = 2 * np.pi * self.phase.cycles_at(i0 + t_d, centre)
        else:
            tau = (i0 + t_d - centre) / self.sr
            phi = 2 * np.pi * tau * (f0 + tau * (rate / 2 + tau * (curv / 6)))
        kk = np.asarray(self.ks, float)
        rows = np.flatnonzero(near.any(axis=1))
        E_m = np.exp(1j * np.outer(kk[rows], phi)) * w_d[None, :]
        B = np.zeros(near.shape, complex)
        B[rows] = s_d * np.dot(E_m, E_fix.T)
        B[~near] = 0.0
        G = np.zeros((2 * len(kk), self.pf))
        G[0::2, 0::2] = 0.5 * B.real
        G[1::2, 1::2] = 0.5 * B.real
        G[0::2, 1::2] = -0.5 * B.imag
        G[1::2, 0::2] = 0.5 * B.imag
        return G

    def _alpha(self, i0: int) -> np.ndarray:
        return 2 * np.pi * self.kf * np.mod(i0 * self.fc / self.sr, 1.0)
