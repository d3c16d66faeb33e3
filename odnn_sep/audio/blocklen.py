"""``block_s='auto'``: choose the fit block length from the demodulated hum lines alone.

Short blocks follow fast drift and amplitude changes but cut a wider notch into the content under
each line; long blocks cut a narrow notch but leave hum that changes within a block. The choice
is made on the chunk sums of pass 1 (a 100 Hz complex baseband of every hum line), where the
block fit can be emulated at a tiny fraction of the cost of running it on the samples: per
candidate length, remove the tracked phase, fit one constant complex
amplitude per line and block (window-weighted mean, the baseband image of the per-sample
least-squares fit), cross-fade the blocks and look at the residual baseband spectrum. One track
(with the longest candidate's blocks) serves every candidate's emulation: within a block the
free complex amplitude absorbs what the track does not follow.

Score (lower is better), as the line metrics of the report: mean over lines of |residual level in
+-0.5 Hz over the floor 2-10 Hz away| plus the mean depth of the deepest cut within +-1 Hz below
both the input and the floor (a hole).
"""
from __future__ import annotations

import logging

import numpy as np
from scipy import fft as sp_fft

from odnn_sep.audio import baseband as _baseband
from odnn_sep.audio import track as _track
from odnn_sep.audio.blockplan import BlockPlan, sin2_window

log = logging.getLogger(__name__)

CANDIDATES_S = (8.0, 16.0)
EXCERPT_S = 160.0      # longest stretch scored (centre of the file): bounded time on long inputs
SEG_S = 4.0            # Welch segments of the score (0.25 Hz bins, as the report's line metrics)


def choose_block(D, sr: int, n_frames: int, f_ref: float, ks, weights, *, candidates=CANDIDATES_S):
    """Return ``(block_s, track)``: the best candidate length and its track over the whole input.

    ``D``: chunk sums (J, C, K) from :func:`track.demodulate` at ``f_ref`` for harmonics ``ks``;
    ``weights`` (C, K) as for :func:`track.track_fundamental`.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums.
    sr : int
        Sample rate (Hz).
    n_frames : int
        Samples in the input.
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers.
    weights : (C, K) array
        Inverse floor PSD.
    candidates : sequence of float
        Block lengths (s), increasing.

    Returns
    -------
    block_s : float
    track : track.Track

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> x += 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> block_s, trk = choose_block(D, sr, t.size, 50.0, [1, 2], np.ones((1, 2)), candidates=(2.0, 4.0))
    >>> block_s, trk.t.tolist()
    (4.0, [0.0, 2.0, 4.0, 6.0, 8.0])
    """
    J = D.shape[0]
    j0, De, n_ex = _excerpt(D, sr, n_frames)
    whole = j0 == 0 and De.shape[0] == J
    # one track (the longest candidate's: fewest blocks) serves every emulation; the chosen
    # length's own track is computed only when it is another one
    T_ref = candidates[-1]
    trk_ref = _track.track_fundamental(De, f_ref, ks, weights, BlockPlan.from_block_s(T_ref, sr, n_ex))
    u = _baseband.derotate(De, ks, _baseband.tracked_phase(De, sr, f_ref, trk_ref)).astype(np.complex64)
    welch = _Welch(u.shape[0], sr)
    Pu = welch(u)
    scores = [_score(u, Pu, welch, BlockPlan.from_block_s(T, sr, n_ex)) for T in candidates]
    best = candidates[int(np.argmin(scores))]
    log.info("block length: %s s (score %s dB for %s s)", best, np.round(scores, 2), candidates)
    if whole and best == T_ref:
        return best, trk_ref
    return best, _track.track_fundamental(D, f_ref, ks, weights, BlockPlan.from_block_s(best, sr, n_frames))


class _Welch:
    """Welch power (Hann, 50 % overlap, SEG_S segments) of a (J, C, K) baseband along axis 0."""

    def __init__(self, J: int, sr: int):
        m = _track.chunk_length(sr)
        nseg = int(round(SEG_S * sr / m))
        self.ok = J >= 2 * nseg
        self.f = np.fft.fftfreq(nseg, m / sr)
        self.win = np.hanning(nseg + 2)[1:-1].astype(np.float32)
        starts = np.arange(0, max(J - nseg + 1, 1), nseg // 2)
        self.idx = starts[:, None] + np.arange(nseg)[None, :]                 # (S, nseg)

    def __call__(self, x) -> np.ndarray:
        if not self.ok:
            return None
        # segments along the last axis (contiguous transforms): (C, K, S, nseg)
        xt = np.ascontiguousarray(x.transpose(1, 2, 0), dtype=np.complex64)
        seg = xt[:, :, self.idx]
        seg *= self.win
        X = sp_fft.fft(seg, axis=-1, overwrite_x=True)
        P = (X.real ** 2 + X.imag ** 2).sum(axis=2)                          # (C, K, nseg)
        return P.transpose(2, 0, 1)


def _score(u, Pu, welch, plan: BlockPlan) -> float:
    """Emulate the block fit with the blocks of ``plan`` on the tracked baseband ``u``."""
    sr, n_frames, hop = plan.sr, plan.n_frames, plan.hop
    m = _track.chunk_length(sr)
    J = u.shape[0]
    tc = (np.arange(J) * m + (m - 1) / 2) / sr
    fit = np.zeros_like(u)
    L = plan.length
    nb = plan.count
    pos = tc * sr
    for b in range(nb):
        s0 = (b - 1) * hop
        a0, a1 = max(s0, 0), min(s0 + L, n_frames)
        i0, i1 = np.searchsorted(pos, [a0, a1])
        if i1 - i0 < 2:
            continue
        p = pos[i0:i1]
        w = sin2_window(p - s0, L)                      # cross-fade window
        # fit weights: the window, or a Hann over the visible part of a block cut by an end
        wf = w if (a0 == s0 and a1 == s0 + L) else sin2_window(p - a0, max(a1 - a0, 1))
        a = (wf[:, None, None] * u[i0:i1]).sum(axis=0) / max(wf.sum(), 1e-300)
        fit[i0:i1] += w[:, None, None] * a[None]
    r = u - fit
    if Pu is None:
        return 0.0
    Pr = welch(r)
    f = welch.f
    af = np.abs(f)
    band, near, w1 = af <= 0.5, (af >= 2.0) & (af <= 10.0), af <= 1.0
    floor_u = np.median(Pu[near], axis=0)
    floor_r = np.median(Pr[near], axis=0)
    with np.errstate(divide="ignore", invalid="ignore"):
        level = 10 * np.log10(Pr[band].mean(axis=0) / np.maximum(floor_r, 1e-300))          # (C, K)
        cut = 10 * np.log10((Pr[w1] / np.maximum(np.minimum(Pu[w1], floor_u), 1e-300)).min(axis=0))
    level = np.nan_to_num(level)
    cut = np.nan_to_num(cut)
    return float(np.abs(level).mean(axis=0).mean() + np.maximum(0.0, -cut.mean(axis=0)).mean())


def _excerpt(D, sr: int, n_frames: int):
    """The central EXCERPT_S of the chunk sums ``D``: ``(j0, D[j0:...], n_ex)`` with its first chunk
    and its length in samples; the block-length choice emulates the fit there only."""
    m = _track.chunk_length(sr)
    j_ex = int(EXCERPT_S * sr / m)
    j0 = max(0, (D.shape[0] - j_ex) // 2)
    De = D[j0: j0 + j_ex]
    return j0, De, min(n_frames - j0 * m, De.shape[0] * m)


def choose_block_phase(D, psi, sr: int, n_frames: int, f_ref: float, ks, *, candidates=CANDIDATES_S) -> float:
    """As :func:`choose_block`, with the lines turned by the refined phase ``psi`` (cycles, at the
    chunk centres; finetrack.py) instead of a block track: returns the best block length.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums.
    psi : (J,) array
        Refined phase of the fundamental (cycles).
    sr, n_frames, f_ref, ks, candidates
        As in :func:`choose_block`.

    Returns
    -------
    float

    Examples
    --------
    >>> from odnn_sep.audio.finetrack import chunk_times
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> x += 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> psi = 0.1 * chunk_times(len(D), sr)                  # the 0.1 Hz offset, in cycles
    >>> choose_block_phase(D, psi, sr, t.size, 50.0, [1, 2], candidates=(2.0, 4.0))
    4.0
    """
    j0, De, n_ex = _excerpt(D, sr, n_frames)
    u = _baseband.derotate(De, ks, 2 * np.pi * (psi[j0: j0 + De.shape[0]] - psi[j0])).astype(np.complex64)
    welch = _Welch(u.shape[0], sr)
    Pu = welch(u)
    scores = [_score(u, Pu, welch, BlockPlan.from_block_s(T, sr, n_ex)) for T in candidates]
    best = candidates[int(np.argmin(scores))]
    log.info("block length: %s s (score %s dB for %s s)", best, np.round(scores, 2), candidates)
    return best
