"""Whole-input amplitude of each tracked harmonic: generalised least squares on the demodulated chunks.

Music and speech are not stationary: the content under a hum line comes and goes with the notes
and syllables. An amplitude fitted with the same weight everywhere takes the loud moments at full
weight; weighting every instant by the inverse of the local content power near the line (the
generalised least-squares estimate for noise of time-varying power) takes them at their worth.

Per line and channel, from pass 1's 10 ms chunk sums ``D`` (:func:`track.demodulate`):

1. the local content power ``p(t)`` near the line: the chunk sums with the line's slow part
   (1 s moving mean) removed, short-time power at 1.5-6 Hz from the line (1 s Hann windows);
2. per fit block: the chunks turned by the block's own tracked phase (the same cubic phase model
   as the block fit, so the line is a steady phasor within the block), averaged with weights
   ``w(t) / p(t)`` (``w`` the block's sin^2 window); the variance of that mean follows from ``p``;
3. over the full blocks: the precision-weighted mean of the blocks' moduli. Moduli, not complex amplitudes: the
   phase reference carried from block to block by the track is not accurate enough for a coherent
   mean over minutes at the higher harmonics.

A line counts as steady when its block moduli scatter no more than ``STEADY_SCATTER`` times what
the noise predicts; otherwise no whole-input value is given (the report falls back to the median
over blocks).
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import track as _track
from odnn_sep.audio.blockplan import BlockPlan, sin2_window

WINDOW_S = 1.0               # time resolution of the local power (s)
OFFSET_BAND_HZ = (1.5, 6.0)  # offsets from the line where its local content power is measured
POWER_FLOOR = 0.05           # weights capped at 1 / (this x the median power): a few quiet chunks
                             # must not carry a whole block
STEADY_SCATTER = 2.0
BATCH_CHUNKS = 1 << 16       # chunks of blocks processed at once
SEGMENT_BATCH = 1024         # local power: segments transformed at once (bounded work arrays)


def local_power(u: np.ndarray, fs: float) -> tuple[np.ndarray, np.ndarray]:
    """Expected ``|u_j - line|^2`` per chunk from the content near the line, two ways: the mean
    and the median (over ln 2, the median of an exponential variable) over the offsets.

    ``u`` (J,) complex chunk sums of one line and channel (any fixed demodulation within a few Hz
    of the line). Returns two (J,) float64 arrays, each floored at ``POWER_FLOOR`` x its median.
    The mean includes a partial of the content a few Hz away, the median does not.

    Parameters
    ----------
    u : (J,) complex array
        Chunk sums of one line and channel.
    fs : float
        Their rate (Hz; 100 for 10 ms chunks).

    Returns
    -------
    mean, median : (J,) float arrays

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> u = 5.0 + rng.standard_normal(2000) + 1j * rng.standard_normal(2000)   # a line; noise power 2
    >>> p_mean, p_med = local_power(u, 100.0)
    >>> p_mean.shape, round(float(np.median(p_mean)), 1), bool(1.5 < np.median(p_med) < 2.5)
    ((2000,), 2.0, True)
    """
    J = u.shape[0]
    n = int(min(J, max(8, round(WINDOW_S * fs))))
    # the line (and its slow drift) is the slow part: a centred n-chunk moving mean (zeros beyond
    # the ends, as np.convolve's "same"), by cumulative sums; the content a few Hz away remains
    lo, hi = n - 1 - (n - 1) // 2, (n - 1) // 2
    cs = np.concatenate([np.zeros(lo + 1, u.dtype), np.cumsum(u), np.full(hi, np.sum(u))])
    r = u - (cs[n:n + J] - cs[:J]) / n
    win = np.hanning(n + 2)[1:-1]
    f = np.abs(np.fft.fftfreq(n, 1.0 / fs))
    band = (f >= OFFSET_BAND_HZ[0]) & (f <= OFFSET_BAND_HZ[1])
    if not band.any():
        band = f > 0
    hop = max(1, n // 4)
    starts = np.arange(0, J - n + 1, hop)
    p_mean, p_med = np.empty(len(starts)), np.empty(len(starts))
    # segments a batch at a time (each row on its own, so the same values): all of them at once
    # were several times the chunk sums' size (the largest arrays of the analysis on long inputs)
    for a in range(0, len(starts), SEGMENT_BATCH):
        st = starts[a: a + SEGMENT_BATCH]
        seg = r[st[:, None] + np.arange(n)[None, :]] * win
        # per-bin power of a windowed segment of white content of variance s^2 is s^2 sum(win^2)
        P = np.abs(np.fft.fft(seg, axis=1)[:, band]) ** 2 / np.sum(win ** 2)
        p_mean[a: a + len(st)] = P.mean(axis=1)
        p_med[a: a + len(st)] = np.median(P, axis=1)
    out = []
    for p in (p_mean, p_med / np.log(2.0)):
        pj = np.interp(np.arange(J), starts + (n - 1) / 2, p)
        med = float(np.median(pj))
        out.append(np.maximum(pj, POWER_FLOOR * med) if med > 0 else np.maximum(pj, 1e-300))
    return out[0], out[1]


def steady_amplitudes(D: np.ndarray, f_ref: float, ks, trk, plan: BlockPlan) -> np.ndarray:
    """Peak amplitude (C, K) of harmonics ``ks`` (the columns of ``D``, demodulated at ``k f_ref``)
    over the whole input where steady, NaN elsewhere. ``trk``: the fundamental track of blocks
    of the blocks of ``plan``; only blocks inside the signal count.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref`` (:func:`track.demodulate`).
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    trk : track.Track
        Fundamental track of the blocks of ``plan``.
    plan : BlockPlan
        The blocks.

    Returns
    -------
    (C, K) float array
        NaN throughout when fewer than 3 blocks lie inside the signal.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate, track_fundamental
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> x += 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> plan = BlockPlan.from_block_s(4.0, sr, t.size)
    >>> trk = track_fundamental(D, 50.0, [1, 2], np.ones((1, 2)), plan)
    >>> steady_amplitudes(D, 50.0, [1, 2], trk, plan).round(2).tolist()
    [[1.0, 0.5]]
    """
    sr, hop, n_frames = plan.sr, plan.hop, plan.n_frames
    J, C, K = D.shape
    out = np.full((C, K), np.nan)
    m = _track.chunk_length(sr)
    fs = sr / m
    L = plan.length
    tj = np.arange(J) * m + (m - 1) / 2                          # chunk centres (samples)
    full = [b for b in range(len(trk.f0)) if b * hop - hop >= 0 and b * hop + hop <= n_frames]
    if len(full) < 3 or J < 8:
        return out
    # full blocks as rows of chunk indices (all the same length: a block boundary between two
    # chunk centres may drop one end chunk, where the window is ~0 anyway)
    full = np.array(full)
    j0 = np.searchsorted(tj, full * hop - hop)
    nb = int(min(np.searchsorted(tj, full * hop + hop) - j0))
    # blocks a batch at a time: the per-block arrays then take bounded memory on long inputs
    batch = max(1, BATCH_CHUNKS // nb)
    starts = range(0, len(full), batch)

    def geometry(q):
        """Chunk indices (blocks, nb), phase model in cycles and sin^2 window of the batch at ``q``."""
        b = full[q:q + batch]
        idx = j0[q:q + batch, None] + np.arange(nb)[None, :]
        c = (b * hop)[:, None]
        tau = (tj[idx] - c) / sr
        # the block fit's phase model, relative to the demodulation frequency
        ph = getattr(trk, "phase", None)
        if ph is not None and abs(ph.f_ref - f_ref) < 1e-12:
            # the refined phase, relative to the demodulation frequency
            cyc = ph.offset_cycles(tj[idx]) - ph.offset_cycles(c.astype(float))
        else:
            cyc = tau * ((trk.f0[b] - f_ref)[:, None] + tau * ((trk.rate[b] / 2)[:, None]
                                                              + tau * (trk.curv[b] / 6)[:, None]))
        return idx, cyc, sin2_window(tj[idx] - (c - hop) + 0.5, L)

    # one batch (the usual case): computed once for every line and channel
    single = geometry(0) if len(starts) == 1 else None
    for i, k in enumerate(ks):
        for ch in range(C):
            u = D[:, ch, i].astype(np.complex128)
            if not np.any(u):      # a silent channel (a flat EEG electrode): no line, and no weights
                out[ch, i] = np.nan
                continue
            # weights from the mean power: they vary as slowly as the content near the line
            # does, and weights that follow every note would modulate a partial a few Hz away
            # onto the line; the variance of the block mean from the median, the power of the
            # content that does stay under the line
            p_mean, p_med = local_power(u, fs)
            z, var = np.empty(len(full), complex), np.empty(len(full))
            for q in starts:
                idx, cyc, win = single if single is not None else geometry(q)
                w = win / p_mean[idx]
                sw = w.sum(axis=1)
                z[q:q + batch] = np.sum(w * u[idx] * np.exp(-2j * np.pi * k * cyc), axis=1) / sw
                var[q:q + batch] = np.sum(w * w * p_med[idx], axis=1) / sw ** 2
            # amplitude of a chunk sum: m A / 2
            out[ch, i] = _combine(np.abs(z) ** 2, var, m)
    return out


def _combine(z2: np.ndarray, var: np.ndarray, m: int) -> float:
    """Peak amplitude from the blocks' squared moduli ``z2`` and the variances ``var`` their weights
    imply, NaN when the moduli scatter more than those explain (the line is not steady).

    ``var`` comes from the content a few Hz from the line, which is what sets the weights; the
    content at the line itself, which is what the block mean keeps, is usually weaker (a partial
    a few Hz away averages out over a block). So ``var`` sets the relative precision of the blocks
    and a generous steadiness test, but is not subtracted as a noise bias: the moduli are averaged
    as they are (their own noise bias is second order in the small relative error of each block).
    """
    prec = 1.0 / np.maximum(var, 1e-300)
    mod = np.sqrt(np.maximum(z2, 0.0))
    mbar = float(np.sum(prec * mod) / prec.sum())
    # the modulus of a complex mean of variance v has variance ~v / 2
    scatter = float(np.sum(prec * (mod - mbar) ** 2) / (len(z2) - 1) * 2.0)
    if scatter > STEADY_SCATTER or mbar <= 0:
        return float("nan")
    return 2.0 * mbar / m
