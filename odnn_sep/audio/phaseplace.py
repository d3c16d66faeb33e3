"""Each step of the hum's phase placed to the sample where it happens.

The phase is known at chunk centres (10 ms apart) and read between them by linear interpolation
(finetrack.PhaseTrack), which spreads a step over the 10 ms between two centres and leaves the
hum there nearly whole: at half a cycle the lines' full level for 5 ms, about -35 dB of a 30 s
recording, most of what a splice leaves once its jump is followed (phasejumps.py). Here every
step the final phase holds is found between two centres, placed to the sample by least squares
on the input whitened by an AR model of what the hum leaves, and returned for PhaseTrack, which
keeps it sharp. Cost: 0.2 s of the input is read around each step.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio.phasejumps import MAX_JUMPS

SHARP_MIN = 0.005      # cycles: a change of the phase between two chunk centres this far from its
                       # neighbours' is a step (a smooth phase's changes differ by < 1e-5)
SHARP_SPAN = 50        # chunks on either side whose mean is the hum just before and after a step
WHITEN_CHUNKS = 10     # chunks on either side of a step whose residual fits the whitening AR model
AR_ORDER = 16          # its order


def to_the_sample(source, D, psi: np.ndarray, ks, f_ref: float) -> tuple[np.ndarray, list[tuple[int, float]]]:
    """The steps of ``psi`` (kept whole by phasejumps.follow and the fine track), each placed to
    the sample where it happens: ``(first sample after it, step in cycles)``.

    A step shows in ``psi`` as a change between two neighbouring centres at least ``SHARP_MIN``
    away from the mean of the changes on either side. The hum just before and after it (each
    harmonic's mean turned amplitude over ``SHARP_SPAN`` chunks on that side) is drawn at the
    samples around the two centres, and the first sample after the step is where the input agrees
    with the hum before it up to there and with the hum after it from there (least squares;
    chunk sums cannot tell, as part of a chunk keeps the image of each line at minus its
    frequency).

    Parameters
    ----------
    source : ArraySource or FileSource
        The input (the samples between the two centres around each step are read).
    D : (J, C, K) complex array
        Chunk sums of the harmonics ``ks`` at ``f_ref`` (track.demodulate).
    psi : (J,) array
        The phase (cycles, relative to ``f_ref t``, at the chunk centres).
    ks : (K,) array
        Harmonic numbers.
    f_ref : float
        Reference fundamental of ``D`` (Hz).

    Returns
    -------
    psi : (J,) array
        ``psi`` with each step moved to the chunk centres on either side of its sample (the
        sample is searched from one centre before the step's interval to one after it: the 10 ms
        chunk it was placed at can be the neighbour of the right one under a loud host).
    list of (int, float)
        For ``finetrack.PhaseTrack(jumps=...)``.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 2000; t = np.arange(20 * sr) / sr
    >>> ph = 2 * np.pi * 50 * t + np.pi * (np.arange(t.size) >= 20013)     # half a cycle at sample 20013
    >>> x = sum(np.cos(k * ph) for k in (1, 2, 3))
    >>> src = ArraySource(x, sr); D = demodulate(src, 50.0, [1, 2, 3])
    >>> psi = 0.5 * (np.arange(len(D)) >= 1001)                # the fine track's step, between centres
    >>> to_the_sample(src, D, psi, np.array([1.0, 2, 3]), 50.0)[1]
    [(20013, 0.5)]
    >>> psi2, jumps = to_the_sample(src, D, 0.5 * (np.arange(len(D)) >= 1002), np.array([1.0, 2, 3]), 50.0)
    >>> jumps, bool(np.array_equal(psi2, psi))              # a chunk late: moved back
    ([(20013, 0.5)], True)
    """
    from odnn_sep.audio import finetrack as _ft
    from odnn_sep.audio import track as _track

    psi = np.asarray(psi, dtype=np.float64)
    J = len(psi)
    if J < 8:
        return psi, []
    sr = source.sr
    ks = np.asarray(ks, dtype=np.float64)
    d = np.diff(psi)
    dev = np.zeros_like(d)
    dev[1:-1] = d[1:-1] - 0.5 * (d[:-2] + d[2:])                  # a step between centres i and i + 1
    mag = np.abs(dev)
    peak = (mag > SHARP_MIN) & (mag >= np.roll(mag, 1)) & (mag >= np.roll(mag, -1))
    m = _track.chunk_length(sr)
    x0 = (m - 1) / 2
    out = []
    fixed = psi.copy()
    for i in np.flatnonzero(peak)[:MAX_JUMPS]:
        delta = float(dev[i])
        lo, hi = max(i - SHARP_SPAN, 0), min(i + 2 + SHARP_SPAN, J)
        if i - lo < 2 * WHITEN_CHUNKS or hi - (i + 2) < 2 * WHITEN_CHUNKS:
            continue
        smooth = psi[lo:hi].copy()
        smooth[i + 1 - lo:] -= delta
        turn = np.stack([_ft.phase_turn(smooth, k) for k in ks], axis=1)           # (n, K)
        Dt = D[lo:hi].astype(np.complex128) * turn[:, None, :]
        # per-sample complex amplitudes of the lines (a chunk sum is m / 2 times the amplitude)
        cb, ca = 2 * Dt[: i - lo].mean(axis=0) / m, 2 * Dt[i + 2 - lo:].mean(axis=0) / m   # (C, K)
        first = np.arange(int(np.ceil(x0 + (i - 1) * m)), int(np.floor(x0 + (i + 2) * m)) + 1)
        at = _place(source, first, i, m, x0, smooth[i - lo - WHITEN_CHUNKS: i + 2 - lo + WHITEN_CHUNKS],
                    ks, f_ref, cb, ca)
        if at is not None:
            out.append((at, delta))
            near = np.arange(i - 1, i + 3)
            fixed[near] = psi[near] - delta * (near >= i + 1) + delta * (x0 + m * near >= at)
    return fixed, out


def _place(source, first, i, m, x0, psi_near, ks, f_ref, cb, ca):
    """The first sample after the step among ``first``: the least-squares boundary between the
    hum before (``cb``) and after (``ca``), on the input whitened by an AR model of what is
    left once the hum is taken out (``WHITEN_CHUNKS`` chunks on either side): a loud host
    (speech, brown noise) is mostly low-frequency, and unwhitened it moves the boundary by tens
    of samples. ``psi_near``: the smooth phase at the chunk centres ``i - WHITEN_CHUNKS`` to
    ``i + 1 + WHITEN_CHUNKS``."""
    sr = source.sr
    n0 = int(np.ceil(x0 + (i - WHITEN_CHUNKS) * m))
    n1 = int(np.floor(x0 + (i + 1 + WHITEN_CHUNKS) * m)) + 1
    y = source.read(n0, n1 - n0)
    if y.shape[0] < n1 - n0:
        return None
    idx = np.arange(n0, n1)
    centres = x0 + m * (i - WHITEN_CHUNKS + np.arange(len(psi_near)))
    ph = f_ref * idx / sr + np.interp(idx, centres, psi_near)
    rot = np.exp(2j * np.pi * np.mod(np.outer(ph, ks), 1.0))                         # (S, K)
    rb = y - np.real(rot @ cb.T)                                                    # (S, C)
    ra = y - np.real(rot @ ca.T)
    j0, j1 = int(first[0]) - n0, int(first[-1]) - n0 + 1
    misfit = np.zeros(j1 - j0)
    p = AR_ORDER
    if j0 < 2 * p or len(y) - j1 < 2 * p:               # too few samples around (a very low rate)
        return None
    for c in range(y.shape[1]):
        # AR fit on the residual with the hum taken out on each side, the candidates left out
        r = np.concatenate([rb[:j0, c], ra[j1:, c]])
        X = np.stack([r[p - q - 1: len(r) - q - 1] for q in range(p)], axis=1)
        coef = np.linalg.lstsq(X, r[p:], rcond=None)[0]
        a = np.r_[1.0, -coef]
        # the whitening filter is FIR: a causal convolution (scipy.signal costs 0.9 s to import)
        wb, wa = np.convolve(rb[:, c], a)[: len(y)], np.convolve(ra[:, c], a)[: len(y)]
        eb = np.concatenate([[0.0], np.cumsum(wb ** 2)])
        ea = np.concatenate([np.cumsum((wa ** 2)[::-1])[::-1], [0.0]])
        diff = ra[:, c] - rb[:, c]                                                   # = hb - ha
        # whitened residual with the step before sample j: wb before j, wa from j + p on, and at
        # j + r (r < p) wa less the filter's memory of (ha - hb) before j, for every j at once
        js = np.arange(j0, j1)
        mix = np.stack([wa[js + r] for r in range(p)], axis=1)                     # (S, p)
        for r in range(p):
            for q in range(r + 1, p + 1):
                mix[:, r] -= a[q] * diff[js + r - q]
        misfit += eb[js] + np.sum(mix ** 2, axis=1) + ea[js + p]
    return int(first[int(np.argmin(misfit))])


__all__ = ["to_the_sample", "SHARP_MIN", "SHARP_SPAN", "WHITEN_CHUNKS", "AR_ORDER"]
