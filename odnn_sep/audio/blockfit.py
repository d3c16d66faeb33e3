"""Pass 2 of :func:`denoise`: per-block fits, fixed-line smoothing across blocks, overlap-add.

Each 50 %-overlapping block is fitted by weighted least squares on the tracked harmonic basis
plus the fixed lines (tones, further combs) (fit.py); the fitted hum is windowed by sin^2 (the
windows sum to one, so blocks join without clicks), subtracted and written progressively.

Fixed lines are steady by nature (a second device, another sample clock), and their per-block
amplitudes carry the noise of one block: subtracting them as fitted cuts a notch into the content
under each line as wide as a block allows. So their complex amplitudes are pooled over the
neighbouring blocks (up to ``smooth_blocks`` on each side) with a positive-part James-Stein
weight: the pooled mean where the scatter between blocks is what the local noise floor predicts,
the block's own value where the line really changes. Output is delayed by that many blocks
(memory: a few blocks). The tracked comb is not pooled: its per-block phase reference follows
the track, and its amplitude is free to follow the hum from block to block.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.audio import fit as _fit
from odnn_sep.audio import fullblock as _fullblock
from odnn_sep.audio.blockplan import BlockPlan
from odnn_sep.audio.lines import LineSet

STEADY_SCATTER = 2.0   # scatter over the noise prediction below which a line counts as steady (~1 % test)
AHEAD = True           # evaluate the next block's harmonic powers in a worker thread
STRETCHES = True       # along a refined phase: the powers once per half block (stretch.py), not per block


@dataclass(frozen=True)
class FitSettings:
    """How pass 2 fits: the solver (``'exact'`` or ``'network'``, with its seed), the Gram
    sub-sampling step (fit.solve_block), and the local noise floor PSD at each line (C per line;
    harmonics ``main_psd``, fixed lines ``fixed_psd``) for pooling amplitudes over up to
    ``smooth_blocks`` blocks on each side (None: that kind of line is not pooled).

    Examples
    --------
    >>> s = FitSettings(gram_step=4)
    >>> s.solver, s.gram_step, s.main_psd is None, s.smooth_blocks
    ('exact', 4, True, 4)
    """

    solver: str = "exact"
    random_state: object = 0
    gram_step: int = 1
    fixed_psd: np.ndarray | None = None
    main_psd: np.ndarray | None = None
    smooth_blocks: int = 4
    main_amps: np.ndarray | None = None   # (blocks, C, K) tracked-comb amplitudes to subtract (NaN: fit's own)
    envelope: object = None               # envelope.Envelope: the tracked comb's shared gain, or None


def fit_pass(source, sink, plan: BlockPlan, trk, lines: LineSet, settings: FitSettings, tick=None):
    """Fit every block, subtract, write through ``sink(piece, removed)`` (the sink writes
    ``piece - removed``; ``piece`` is what ``source.read`` returned for those samples, so an
    in-memory source's own array can take the result in place).

    Returns ``(amps, phs, valid, overall)``: (blocks, C, lines) peak amplitude and phase, which
    blocks are full length, and (C, lines) whole-input amplitudes of steady lines (NaN where a
    line is not steady or not pooled; None without pooling).

    Parameters
    ----------
    source : ArraySource or FileSource
        The input.
    sink : callable
        ``sink(piece, removed)``, in order.
    plan : BlockPlan
        The blocks.
    trk : track.Track
        The fundamental track of the blocks.
    lines : LineSet
        The lines to fit.
    settings : FitSettings
        Solver and pooling.
    tick : callable, optional
        Called with the frames of each block read.

    Returns
    -------
    amps, phs : (blocks, C, lines) arrays
    valid : (blocks,) bool array
    overall : (C, lines) array or None

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate, track_fundamental
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> hum = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> src = ArraySource(hum + 0.1 * np.random.default_rng(0).standard_normal(t.size), sr)
    >>> plan = BlockPlan.from_block_s(4.0, sr, t.size)
    >>> trk = track_fundamental(demodulate(src, 50.0, [1, 2]), 50.0, [1, 2], np.ones((1, 2)), plan)
    >>> out = []
    >>> amps, phs, valid, overall = fit_pass(src, lambda piece, removed: out.append(removed), plan, trk,
    ...                                      LineSet([1, 2]), FitSettings())
    >>> amps.shape, valid.tolist(), np.median(amps[valid], axis=0).round(2).tolist()
    ((5, 1, 2), [False, True, True, True, False], [[1.0, 0.5]])
    >>> bool(np.abs(np.concatenate(out)[:, 0] - hum).max() < 0.05)       # the hum, as removed
    True
    """
    fp = _FitPass(source, plan, trk, lines, settings)
    ahead = _Ahead(plan, fp) if _Ahead.useful(plan, fp) else None
    try:
        return _blocks(source, sink, plan, fp, tick, ahead)
    finally:
        if ahead is not None:
            ahead.close()


def _blocks(source, sink, plan: BlockPlan, fp, tick, ahead):
    """The loop of :func:`fit_pass` over the blocks (pieces from ``ahead`` when given)."""
    C, hop = source.channels, plan.hop
    prev_piece = np.zeros((0, C))
    prev_tail = np.zeros((C, 0), np.float32)
    for b in range(plan.count):
        if ahead is not None:
            ahead.ready(b)
        piece = source.read(b * hop, hop)
        parts = [p for p in (prev_piece, piece) if p.shape[0]]
        n = prev_piece.shape[0] + piece.shape[0]
        hum = fp.block(b, parts, n)                                              # (C, n) float32 or None
        npv = prev_piece.shape[0]
        if npv:
            removed = (prev_tail + hum[:, :npv] if hum is not None else prev_tail).T
            sink(prev_piece, removed)
        prev_tail = hum[:, npv:] if hum is not None else np.zeros((C, n - npv), np.float32)
        prev_piece = piece
        if tick is not None:
            tick(piece.shape[0])
    return fp.amps, fp.phs, fp.valid, fp.overall()


class _Ahead:
    """Evaluates the next block's tracked-comb powers (fullblock.FullBlockFitter.prepare, into
    the slot the current block does not use) in one worker thread while the current block is
    read, fitted and written. NumPy releases the GIL for these array operations, so on two
    cores the two parts of a block's work overlap; the arithmetic is the same as without the
    worker. The worker allocates no array of a block's length (its work arrays are kept), so
    a second malloc arena does not grow the memory."""

    def __init__(self, plan: BlockPlan, fp: "_FitPass"):
        from concurrent.futures import ThreadPoolExecutor

        self.plan, self.fp = plan, fp
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="denoise-ahead")
        self.future = self.pool.submit(self._job, 0)

    def _job(self, b: int):
        # block b: samples (b - 1) hop .. (b + 1) hop within the input, as fit_pass joins them
        hop = self.plan.hop
        i0 = max((b - 1) * hop, 0)
        n = min((b + 1) * hop, self.plan.n_frames) - i0
        trk = self.fp.trk
        self.fp.fitter.prepare(i0, n, b * hop, trk.f0[b], trk.rate[b], trk.curv[b], slot=b % 2)

    def ready(self, b: int):
        """Wait for block ``b``'s powers; start those of ``b + 1``."""
        self.future.result()
        self.future = self.pool.submit(self._job, b + 1) if b + 1 < self.plan.count else None

    def close(self):
        if self.future is not None:
            self.future.cancel()
        self.pool.shutdown(wait=True)

    @staticmethod
    def useful(plan: BlockPlan, fp: "_FitPass") -> bool:
        """Whether there is a tracked comb fitted by the exact solver over several blocks."""
        return (AHEAD and plan.count > 1 and fp.fitter is not None and fp.fitter.pm > 0
                and fp.settings.solver == "exact")


class _FitPass:
    """State of pass 2 across blocks: the fitter, the pooling history, the per-block results."""

    def __init__(self, source, plan: BlockPlan, trk, lines: LineSet, settings: FitSettings):
        self.sr, self.C, self.plan, self.trk, self.lines, self.settings = source.sr, source.channels, plan, trk, lines, settings
        ks = self.ks = lines.harmonics
        L, nb = plan.length, plan.count
        self.pm = 2 * len(ks)
        nfix = lines.n_fixed
        nl = self.nl = len(ks) + nfix
        self.amps = np.zeros((nb, self.C, nl))
        self.phs = np.zeros((nb, self.C, nl))
        self.valid = np.zeros(nb, bool)
        self.col_names = [f"{nm}_{cs}" for nm in lines.names for cs in ("cos", "sin")]
        self.w_full = plan.window()
        self.fitter = _fullblock.FullBlockFitter(L, self.sr, ks, lines.fixed_lines, self.w_full,
                                                 settings.gram_step) if nl else None
        # (the fitter's float32 copy of the same window where there is one)
        self.w32_full = self.fitter.window(L)[1] if self.fitter is not None else self.w_full.astype(np.float32)
        if self.fitter is not None:
            self.fitter.phase = getattr(trk, "phase", None)
            if STRETCHES:
                self.fitter.use_stretches(plan.hop, plan.n_frames)
        pool_fixed = settings.fixed_psd is not None and nfix > 0
        self.pool_main = settings.main_psd is not None and len(ks) > 0
        self.M = settings.smooth_blocks if (pool_fixed or self.pool_main) else 0
        self.psd = np.vstack(([settings.main_psd] if self.pool_main else [])
                             + ([settings.fixed_psd] if pool_fixed else [])) if self.M else None
        rows = np.r_[np.arange(len(ks)) if self.pool_main else [], len(ks) + np.arange(nfix) if pool_fixed else []]
        self.pooled_rows = rows.astype(int)
        self.Phi = _block_phase(trk, plan.hop, self.sr) if self.pool_main else None
        self.kk = np.asarray(ks, float)
        self.basis_cache, self.sub_cache = {"min_n": L}, {"min_n": L}
        # every tracked line of every block gets its amplitude from the paths (steadypath.py): the
        # block fit's own tracked amplitudes are then never used (pooled history included)
        ma = settings.main_amps
        if self.fitter is not None:
            self.fitter.amplitudes_given = ma is not None and len(ks) > 0 and bool(np.isfinite(ma).all())
        self.zs, self.vs = [], []

    def block(self, b: int, parts, n: int):
        """The windowed fitted hum of block ``b`` (samples ``parts``, ``n`` of them), float32
        (C, n); None when there is nothing to fit."""
        hum = None
        zq = None
        if n and self.nl:
            hop, L = self.plan.hop, self.plan.length
            s0 = (b - 1) * hop
            i0 = max(s0, 0)
            z, Fm = self._fit(b, parts, i0, n)
            self.valid[b] = n == L
            if self.M:
                zq = self._pool(b, z, n)
            if self.settings.main_amps is not None:
                # amplitude paths of the tracked comb (steadypath.py) replace the block's own
                za = self.settings.main_amps[b].T
                zk = z[: len(self.ks)]
                zk[np.isfinite(za)] = za[np.isfinite(za)]
            self.amps[b] = np.abs(z).T
            self.phs[b] = np.angle(z).T
            # unwindowed hum of the block (tracked comb + fixed lines), then one window multiply
            env = self.settings.envelope if self.pm else None
            hum = self.fitter.block_hum(i0, n, z, tracked=Fm is None, slot=b % 2)
            if env is not None and Fm is None:
                # the tracked comb alone, to be scaled by the shared gain; with fixed lines the
                # buffer is reused for them, so the whole hum is copied out first
                if self.lines.n_fixed:
                    hum = hum.copy()
                    comb = hum - self.fitter.block_hum(i0, n, z, tracked=False, slot=b % 2)
                else:
                    comb = hum
            if self.pm and Fm is not None:
                th = np.empty((self.C, self.pm), Fm.dtype)
                th[:, 0::2], th[:, 1::2] = z[: len(self.ks)].real.T, -z[: len(self.ks)].imag.T
                comb = np.dot(th, Fm.T)
                hum += comb
            if env is not None:
                for c in range(self.C):
                    hum[c] += ((env.at(i0, n, c) - 1.0) * comb[c]).astype(np.float32)
            hum *= self.w32_full if n == L else self.plan.cut_window(i0 - s0, n).astype(np.float32)
        if self.M and zq is None:
            self.zs.append(None)
            self.vs.append(None)
        return hum

    def _fit(self, b: int, parts, i0: int, n: int):
        """Complex amplitudes ``a - i b`` (lines, C) of block ``b`` (tracked lines in the block's
        phase reference, fixed lines in absolute time) and the tracked-comb columns when the
        general path fitted it (else None)."""
        trk, hop = self.trk, self.plan.hop
        theta = Fm = None
        if self.settings.solver == "exact":
            # blocks cut by the signal's ends too: fitted under a Hann over their visible part
            theta = self.fitter.fit(i0, b * hop, trk.f0[b], trk.rate[b], trk.curv[b], parts, n=n, slot=b % 2)
        if theta is None:
            # fit weights: the block's window, or a Hann over the visible part of a block cut
            # by the signal's start/end (a one-sided window would leak the content onto the lines)
            w_fit = self.fitter.window(n)[0]
            blk = np.vstack(parts) if len(parts) > 1 else parts[0]
            theta, Fm = self._fit_generic(i0, n, b, blk, w_fit)
        theta = theta[: 2 * self.nl]
        return theta[0::2] - 1j * theta[1::2], Fm                                  # (nl, C)

    def _pool(self, b: int, z, n: int):
        """Pool block ``b``'s amplitudes ``z`` (in place) with its neighbours'; returns the
        block's entry of the pooling history."""
        ks = self.ks
        zq = z[self.pooled_rows].copy()
        if self.pool_main:
            # tracked lines are pooled in a common phase reference: the track's phase at each
            # block centre
            zq[: len(ks)] *= np.exp(-1j * self.kk * self.Phi[b])[:, None]
        self.zs.append(zq)
        # E|z - z0|^2 = 3 S sr / n for a sin^2-weighted fit on noise of PSD S
        self.vs.append(3.0 * np.maximum(self.psd, 1e-300) * self.sr / max(n, 1))
        zp = _pooled(self.zs, self.vs, b, self.M)
        if self.pool_main:
            zp[: len(ks)] *= np.exp(1j * self.kk * self.Phi[b])[:, None]
        z[self.pooled_rows] = zp
        return zq

    def _fit_generic(self, i0, n, b, blk, w_fit):
        """One block through the general path (edge blocks, the network solver, ill-conditioned
        blocks): ``(theta (p, C), tracked-comb columns (n, 2K))``; fixed lines in absolute time."""
        # float32 basis for the exact solver: its values come from float32 sines anyway
        # (fit.unit_phasor), and the products run at twice the speed (solve_block checks conditioning)
        trk, centre, st = self.trk, b * self.plan.hop, self.settings
        spec = _fit.BasisSpec(self.sr, self.ks, self.lines.fixed_lines, phase=getattr(trk, "phase", None))
        poly = (trk.f0[b], trk.rate[b], trk.curv[b])
        F = _fit.block_basis(spec, i0, n, centre, poly, cache=self.basis_cache,
                             dtype=np.float32 if st.solver == "exact" else np.float64)
        if st.solver == "exact":
            F_sub = None
            if _fit.sub_gram(n, F.shape[1], st.gram_step):
                F_sub = _fit.block_basis(spec, i0, n, centre, poly, cache=self.sub_cache, step=st.gram_step,
                                         dtype=np.float32)
            theta = _fit.solve_block(F, blk, w_fit, gram_step=st.gram_step, F_sub=F_sub)
        else:
            theta = _fit.solve_block_network(F, blk, w_fit, self.col_names + ["offset", "trend"],
                                             random_state=st.random_state)
        return theta, F[:, : 2 * len(self.ks)]

    def overall(self):
        return _overall(self.zs, self.vs, self.valid, self.pooled_rows, self.nl, self.C) if self.M else None


def _overall(zs, vs, valid, rows, nl: int, C: int):
    """One amplitude per line and channel for the whole input: the modulus of the precision-weighted
    mean of the full blocks' complex amplitudes (common phase reference) where the lines are
    steady (scatter between blocks within twice what the floor predicts), NaN elsewhere (the
    caller then reports the median over blocks)."""
    idx = [j for j in range(len(zs)) if zs[j] is not None and valid[j]]
    out = np.full((C, nl), np.nan)
    if len(idx) < 3:
        return out
    # blocks overlap by half: neighbours share a sixth of their noise, so the scatter about the
    # mean is compared with (n - 1) independent-block units
    zbar, r = _mean_scatter(zs, vs, idx)
    steady = r <= STEADY_SCATTER
    out[:, rows] = np.where(steady, np.abs(zbar), np.nan).T
    return out


def _mean_scatter(zs, vs, idx):
    """Precision-weighted mean of the complex amplitudes ``zs[j]`` (lines, C) over blocks ``idx``
    (noise variances ``vs[j]``), and the scatter about it over what the noise predicts (~1 for a
    steady line)."""
    Z = np.stack([zs[j] for j in idx])              # (nw, lines, C)
    W = 1.0 / np.stack([vs[j] for j in idx])
    zbar = (W * Z).sum(axis=0) / W.sum(axis=0)
    r = (W * np.abs(Z - zbar) ** 2).sum(axis=0) / (len(idx) - 1)
    return zbar, r


def _block_phase(trk, hop: int, sr: int) -> np.ndarray:
    """Phase of the tracked fundamental at each block centre (rad, from the first centre): the
    integral of the track between centres by the Hermite (corrected trapezoid) rule. The blocks'
    own cubic terms are left out: they come from second differences of the track and are the
    noisiest part of it."""
    ph = getattr(trk, "phase", None)
    if ph is not None:
        # the refined phase itself: f_ref t + psi(t) at the block centres, from the first one
        c = np.arange(len(trk.f0)) * hop
        cyc = c * (ph.f_ref / ph.sr) + ph.offset_cycles(c.astype(float))
        return 2 * np.pi * np.mod(cyc - cyc[0], 1.0)
    h = hop / sr
    f, r = trk.f0, trk.rate
    cyc = h * (f[:-1] + f[1:]) / 2 + h ** 2 * (r[:-1] - r[1:]) / 12
    step = 2 * np.pi * np.mod(cyc, 1.0)
    return np.concatenate([[0.0], np.cumsum(step)])


def _pooled(zs, vs, f: int, M: int) -> np.ndarray:
    """Positive-part James-Stein pooling of block ``f``'s amplitudes towards the precision-weighted
    mean of blocks ``f - M .. f`` (causal: the output is not delayed)."""
    idx = [j for j in range(f - M, f + 1) if 0 <= j < len(zs) and zs[j] is not None]
    z_f = zs[f]
    if len(idx) < 3:
        return z_f.copy()
    zbar, r = _mean_scatter(zs, vs, idx)
    lam = np.clip(1.0 - 1.0 / np.maximum(r, 1e-12), 0.0, 1.0)
    return zbar + lam * (z_f - zbar)
