"""Amplitude paths of the tracked harmonics: each line's complex amplitude along the shared tracked
phase, smoothed over as many blocks as the line's own data allow.

A block fit gives every 8-16 s block its own amplitude and phase per line; on a steady line most
of that freedom fits the content under the line instead (noise, a note partial), and the block
fit's pooling (blockfit.py) only looks back a few blocks. Here, from pass 1's chunk sums:

1. per block and line, the generalised least-squares mean of the tracked baseband over the
   block's sin^2 window, every chunk weighted by the inverse content power right beside the line
   (:func:`odnn_sep.audio.nearpower.near_power`, a note partial 0.5 Hz away included): the loud
   moments of music and speech count for what they are worth, the hum is read in the rests;
2. per line, the block amplitudes smoothed by a Hann kernel over ``H`` blocks (or all of them:
   one steady amplitude), ``H`` chosen by cross-validation: each block predicted from the blocks
   that share none of its samples. A steady line takes the whole input; a line whose amplitude or
   phase against the track moves (amplitude modulation, a track error at a high harmonic) takes a
   shorter span. The block fit's own amplitudes stay where even the shortest span is best while
   the blocks scatter more than their noise, or where the path's miss exceeds the block fit's own
   error (measured per block, see :func:`_weighted_means`; medians over the blocks, so that one
   block held by a loud partial does not decide). (The held-out error is compared between spans
   only: its size against the blocks' own noise says little, that noise being measured beside
   the line, not under it.)

The block fit (blockfit.py) then subtracts these amplitudes for the tracked comb, in each block's
own phase reference.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import track as _track
from odnn_sep.audio.amplitude import local_power
from odnn_sep.audio.blockplan import BlockPlan, sin2_window
from odnn_sep.audio.nearpower import near_power

SPANS = (None, 16, 8, 4, 3)  # Hann half-widths tried (blocks); None: one amplitude for the whole input;
                             # when the last (only the blocks next but one) wins and the blocks scatter
                             # more than their noise, the block fit stays
MIN_BLOCKS = 6              # fewer blocks: the block fit's own amplitudes are kept
SHORTER_MARGIN = 0.02       # a shorter span must predict held-out blocks this much better to be chosen
EXCLUDE = 1                 # blocks this close share samples with the one predicted (50 % overlap)
BATCH_BLOCKS = 64           # blocks whose chunk tables are made at once (bounded work arrays)


def block_means(D: np.ndarray, sr: int, ks, psi: np.ndarray, plan: BlockPlan, *, keep_power: bool = False):
    """Per block the weighted mean tracked baseband of each line, as a peak amplitude in the common
    reference (``A`` of ``Re(A exp(2 pi i k (f_ref t + psi(t))))``), and its variance.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref`` (:func:`track.demodulate`).
    sr : int
        Sample rate (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    psi : (J,) array
        Tracked phase of the fundamental (cycles, relative to ``f_ref t``) at the chunk centres.
    plan : BlockPlan
        The fit blocks.
    keep_power : bool, default False
        Also return the content power beside each line at every chunk (envelope.py weighs the
        lines with it).

    Returns
    -------
    A : (blocks, C, K) complex array
    var : (blocks, C, K) float array
        ``inf`` for a block with no chunk.
    var_eq : (blocks, C, K) float array
        The error variance of the equal-weight mean over the same window (the block fit's), as
        measured (see :func:`_weighted_means`).
    var_noise : (blocks, C, K) float array
        The variance of ``A`` from the content 1.5-6 Hz from the line alone (``var`` also counts
        the content right beside it).
    near : (J, C, K) float32 array
        Only with ``keep_power``: :func:`nearpower.near_power` of each line and channel.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(40 * sr) / sr
    >>> x = 0.5 * np.cos(2 * np.pi * 50.0 * t + 1.0) + 0.01 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = _track.demodulate(ArraySource(x, sr), 50.0, [1])
    >>> A, var, _, _ = block_means(D, sr, [1], np.zeros(len(D)), BlockPlan.from_block_s(8.0, sr, t.size))
    >>> A.shape, bool(np.allclose(A[2:-2, 0, 0], 0.5 * np.exp(1j), atol=0.01))
    ((11, 1, 1), True)
    """
    J, C, K = D.shape
    m = _track.chunk_length(sr)
    fs = sr / m
    tj = np.arange(J) * m + (m - 1) / 2
    nb, hop = plan.count, plan.hop
    lo = np.searchsorted(tj, np.arange(nb) * hop - hop)
    hi = np.searchsorted(tj, np.arange(nb) * hop + hop)
    A = np.zeros((nb, C, K), complex)
    var, var_eq, var_n = (np.full((nb, C, K), np.inf) for _ in range(3))
    near = np.empty((J, C, K), np.float32) if keep_power else None
    for i, k in enumerate(ks):
        rot = np.exp(-2j * np.pi * np.mod(k * psi, 1.0))
        for c in range(C):
            u = D[:, c, i].astype(np.complex128) * rot
            A[:, c, i], var[:, c, i], var_eq[:, c, i], var_n[:, c, i], p_w = _line_means(u, fs, tj, lo, hi, plan, m)
            if near is not None:
                near[:, c, i] = p_w
    return (A, var, var_eq, var_n, near) if keep_power else (A, var, var_eq, var_n)


def _line_means(u, fs: float, tj, lo, hi, plan: BlockPlan, m: int):
    """:func:`block_means` of one line and channel (tracked baseband ``u``; the blocks' chunks
    ``lo[b]:hi[b]`` of centres ``tj``)."""
    nb, hop = plan.count, plan.hop
    A = np.zeros(nb, complex)
    var, var_eq, var_n = (np.full(nb, np.inf) for _ in range(3))
    # weights: the content right beside the line (a note partial 0.5 Hz away included); variance
    # for the blocks' relative precision: the larger of that and the content 1.5-6 Hz away, so a
    # block held by a partial throughout is not trusted; for the path-or-block-fit decision the
    # latter alone (the near power also holds the line's own fast changes, which are not noise)
    p_w, p_med = near_power(u, fs), local_power(u, fs)[1]
    p_var = np.maximum(p_med, p_w)
    blocks = np.flatnonzero(hi > lo)
    # the blocks in batches, each a (blocks, chunks) table of its chunks (masked past its end):
    # one Python step per block cost more than the sums themselves on long inputs
    width = int((hi - lo).max()) if len(blocks) else 0
    for i in range(0, len(blocks), BATCH_BLOCKS):
        bs = blocks[i: i + BATCH_BLOCKS]
        idx = lo[bs, None] + np.arange(width)[None, :]
        inside = idx < hi[bs, None]
        idx = np.minimum(idx, len(u) - 1)
        win = np.where(inside, sin2_window(tj[idx] - (bs * hop - hop)[:, None], plan.length), 0.0)
        A[bs], var[bs], _ = _weighted_means(u[idx], win, p_w[idx], p_var[idx], m)
        _, var_n[bs], var_eq[bs] = _weighted_means(u[idx], win, p_w[idx], p_med[idx], m)
    return A, var, var_eq, var_n, p_w


def _weighted_means(u, win, p_w, p_var, m: int):
    """Per row (block) of ``(blocks, chunks)`` tables: the weighted mean of the chunk sums ``u`` as
    a peak amplitude (weights ``win / p_w``), its variance (from ``p_var``), and the error variance
    of the equal-weight mean, the block fit's (``0, inf, inf`` without weight).

    The latter is measured, not modelled: the weighted mean being the generalised least-squares
    one, the equal-weight mean differs from it by a term uncorrelated with it, so its variance is
    ``E|a_eq - a_w|^2 + var(a_w)``; a partial that leaks into the block fit shows in that difference
    whatever its offset from the line."""
    w = win / p_w
    sw = w.sum(axis=1)
    ok = sw > 0
    sw_ = np.where(ok, sw, 1.0)
    a_w = (2.0 / m) * np.sum(w * u, axis=1) / sw_
    var_w = (2.0 / m) ** 2 * np.sum(w * w * p_var, axis=1) / sw_ ** 2
    a_eq = (2.0 / m) * np.sum(win * u, axis=1) / np.where(ok, win.sum(axis=1), 1.0)
    var_eq = np.abs(a_eq - a_w) ** 2 + var_w
    return np.where(ok, a_w, 0.0), np.where(ok, var_w, np.inf), np.where(ok, var_eq, np.inf)


def _kernel(nb: int, span) -> np.ndarray:
    d = np.abs(np.arange(nb)[:, None] - np.arange(nb)[None, :]).astype(float)
    if span is None:
        return np.ones((nb, nb))
    return np.where(d < span, np.cos(np.pi * d / (2 * span)) ** 2, 0.0)


def smooth_path(A: np.ndarray, var: np.ndarray, var_fit: np.ndarray | None = None,
                var_noise: np.ndarray | None = None):
    """One line's block amplitudes ``A`` (blocks,) smoothed over the span that predicts held-out
    blocks best (see the module text); None where the shortest span wins (the line moves faster
    than a smoothed path follows), or where the path is expected to miss the line by more than
    ``var_fit``, the noise of the block fit's own amplitudes (a strong line that moves is better
    followed block by block). The path's miss, from the held-out predictions ``pred``: about
    ``|A - pred|^2 - var_noise``, ``var_noise`` being the held-out blocks' own noise; medians over
    the blocks. The shortest span winning while that miss is not positive (the blocks scatter no
    more than their noise) is chance, and the path is kept.

    Parameters
    ----------
    A : (blocks,) complex array
    var : (blocks,) float array
        Variances of ``A`` (the blocks' relative precision).
    var_fit : (blocks,) float array, optional
    var_noise : (blocks,) float array, optional
        Variances of ``A`` for the miss (default ``var``).

    Returns
    -------
    (blocks,) complex array or None

    Examples
    --------
    >>> rng = np.random.default_rng(1)
    >>> A = 1.0 + 0.1 * (rng.standard_normal(12) + 1j * rng.standard_normal(12))   # steady, noisy
    >>> out = smooth_path(A, np.full(12, 0.02))
    >>> bool(np.abs(out - 1.0).max() < 0.06), bool(np.ptp(out.real) < 0.05)
    (True, True)
    >>> am = 1.0 + 0.3 * np.sin(2 * np.pi * np.arange(16) / 10)                 # fast modulation, no noise
    >>> smooth_path(am.astype(complex), np.full(16, 1e-6)) is None
    True
    >>> slow = 1.0 + 0.3 * np.sin(2 * np.pi * np.arange(16) / 40)               # slow, but the block fit is exact
    >>> smooth_path(slow.astype(complex), np.full(16, 1e-6), np.full(16, 1e-6)) is None
    True
    """
    nb = len(A)
    prec = np.where(np.isfinite(var), 1.0 / np.maximum(var, 1e-300), 0.0)
    if nb < MIN_BLOCKS or (prec > 0).sum() < MIN_BLOCKS:
        return None
    best, best_err, miss, fit_miss = _best_span(A, prec, var if var_noise is None else var_noise, var_fit)
    # the shortest span winning means the line moves, unless the blocks scatter no more than
    # their own noise (then the spans differ by chance)
    if best_err == np.inf or (best == SPANS[-1] and miss > 0) or miss > fit_miss:
        return None
    kw = _kernel(nb, best) * prec[None, :]
    return (kw @ A) / np.maximum(kw.sum(axis=1), 1e-300)


def _best_span(A, prec, var_noise, var_fit):
    """The span of :data:`SPANS` that predicts held-out blocks best (a shorter one only when better
    by ``SHORTER_MARGIN``), its precision-weighted held-out error, the path's miss there and the
    block fit's error (medians over the blocks: one block held by a loud partial must not decide
    for all)."""
    nb = len(A)
    near = np.abs(np.arange(nb)[:, None] - np.arange(nb)[None, :]) <= EXCLUDE
    best, best_err, miss, fit_miss = None, np.inf, np.inf, np.inf
    for span in SPANS:
        kw = np.where(near, 0.0, _kernel(nb, span)) * prec[None, :]
        ok = (kw.sum(axis=1) > 0) & (prec > 0)
        if ok.sum() < MIN_BLOCKS // 2:
            continue
        pred = (kw @ A)[ok] / kw.sum(axis=1)[ok]
        err = float(np.sum(prec[ok] * np.abs(A[ok] - pred) ** 2) / ok.sum())
        if err < best_err * (1.0 - SHORTER_MARGIN):
            best, best_err = span, err
            miss = float(np.median(np.abs(A[ok] - pred) ** 2 - var_noise[ok]))
            fit_miss = float(np.median(var_fit[ok])) if var_fit is not None else np.inf
    return best, best_err, miss, fit_miss


def comb_block_amplitudes(D: np.ndarray, sr: int, f_ref: float, ks, psi: np.ndarray, plan: BlockPlan,
                          means=None, jumps=()):
    """Complex amplitudes ``z`` (blocks, C, K) of the tracked harmonics in each block's own phase
    reference (the block fit's: ``hum = Re(z exp(2 pi i k (phase(t) - phase(centre))))``), NaN
    where the block fit's own amplitude is kept; None when no line has a smoothed path.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref``.
    sr : int
        Sample rate (Hz).
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    psi : (J,) array
        Tracked phase (cycles, relative to ``f_ref t``) at the chunk centres.
    plan : BlockPlan
        The fit blocks.
    means : tuple, optional
        :func:`block_means` of the same arguments, when the caller has it (its first four parts).
    jumps : sequence of (int, float), optional
        Steps of ``psi`` placed to the sample (finetrack.PhaseTrack): the block fit's phase has
        them, so the block references here must too (a block centred within 10 ms of a step
        would otherwise be turned by part of it).

    Returns
    -------
    (blocks, C, K) complex array or None

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(40 * sr) / sr
    >>> x = 0.5 * np.cos(2 * np.pi * 50.1 * t) + 0.05 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = _track.demodulate(ArraySource(x, sr), 50.0, [1])
    >>> psi = 0.1 * (np.arange(len(D)) * 10 + 4.5) / sr
    >>> z = comb_block_amplitudes(D, sr, 50.0, [1], psi, BlockPlan.from_block_s(8.0, sr, t.size))
    >>> z.shape, bool(np.allclose(np.abs(z), 0.5, atol=0.005))
    ((11, 1, 1), True)
    """
    from odnn_sep.audio.finetrack import PhaseTrack

    A, var, var_eq, var_n = means[:4] if means is not None else block_means(D, sr, ks, psi, plan)
    nb, C, K = A.shape
    out = np.full((nb, C, K), np.nan, complex)
    centres = np.arange(nb) * float(plan.hop)
    ph = PhaseTrack(psi, sr, f_ref, jumps)
    cyc = np.mod(centres * (f_ref / sr), 1.0) + ph.offset_cycles(centres)
    any_path = False
    for i, k in enumerate(ks):
        for c in range(C):
            path = smooth_path(A[:, c, i], var[:, c, i], var_eq[:, c, i], var_n[:, c, i])
            if path is not None:
                out[:, c, i] = path * np.exp(2j * np.pi * np.mod(k * cyc, 1.0))
                any_path = True
    return out if any_path else None
