"""Lines of a periodic host: a drum loop or a sequenced pattern placed to the sample.

A pattern that repeats every P seconds exactly is a sum of steady sinusoids at multiples of 1/P
(a hit every 0.25 s: a line every 4 Hz, and so on every multiple of 50 and 60 Hz). Those lines are
as steady and as phase-locked as hum, and the lock tests pass them: clean drum loops were "cleaned"
of harmonics 1-6 and more, changing them by -7 to -37 dB. What a lock test cannot see, the spectrum
shows: such a line has neighbours of its own kind on both sides at the same distance (the lines of
the pattern between the harmonics), and a hum harmonic has none. A locked line with a symmetric pair
of lines beside it and a second pair at twice the distance, each steady over the input and at least
a quarter of its power, is read as the host's (a hum's own amplitude modulation would need a depth
of 100 % to make such sidebands). lockcomb drops such lines only when most of a comb's lines are.

A pattern with a longer period (4 s: lines every 0.25 Hz) puts its neighbours inside the harmonic's
own band, where the spectrum cannot see them; the whole input's tracked baseband resolves them as
sidebands (:func:`baseband_sidebands`). Once the spectrum has given most of a comb's lines to a
host, the comb's other lines with such sidebands go too, and no later test adds a dropped line back.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio.detect import band_halfwidth
from odnn_sep.audio.spectrum import Spectrum

SIDE_MAX_HZ = 20.0      # farthest neighbour (the pair at twice the distance): pattern steps of 0.1 s and longer
SIDE_SHARE = 0.25       # each neighbour at least this share of the line's peak power
SIDE_OVER_FLOOR = 4.0   # and this far over the floor between the lines (a line, not a bump of noise)
# and steady: its median over the spectrum's segments at least this share of its mean (a steady
# line ~1; a bin of noise 0.69, its exponential law's median; a burst of speech far less)
STEADY_SHARE = 0.85


def grid_lines(spec: Spectrum, f0: float, ks, spread_hz: float = 0.0) -> list[int]:
    """The harmonics of ``ks`` (of fundamental ``f0``) that sit on a periodic host's grid: a line
    at the harmonic with lines at the same distance on both sides and at twice that distance
    (beyond the harmonic's own band, within :data:`SIDE_MAX_HZ`), each at least :data:`SIDE_SHARE`
    of its power.

    Parameters
    ----------
    spec : Spectrum
        The spectrum (channels pooled here), with its per-segment periodograms (none are
        flagged without them).
    f0 : float
        Fundamental (Hz).
    ks : sequence of int
        Harmonics to look at.
    spread_hz : float
        Range of the tracked fundamental over the input: harmonic ``k``'s own band widens by
        ``k`` times half of it (a fast ramp smears a line over several hertz, and the ripples of
        its top are not neighbours).

    Returns
    -------
    list of int

    Examples
    --------
    >>> sr = 2000; t = np.arange(20 * sr) / sr
    >>> loop = sum(np.cos(2 * np.pi * 4 * j * t) for j in range(10, 40))     # a line every 4 Hz
    >>> hum = 3 * np.cos(2 * np.pi * 50 * t)                                 # 50 Hz is not on it
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.spectrum import excerpt_spectrum
    >>> y = loop + hum + 0.01 * np.random.default_rng(0).standard_normal(t.size)
    >>> spec = excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=300)
    >>> grid_lines(spec, 60.0, [1, 2]), grid_lines(spec, 50.0, [1])
    ([1, 2], [])
    """
    if spec.segments is None:
        return []
    pooled = spec.psd.sum(axis=1)
    seg = spec.segments.sum(axis=1)                      # (nf_keep, n_segments)
    steady = np.median(seg, axis=1) >= STEADY_SHARE * np.maximum(seg.mean(axis=1), 1e-300)
    freqs, df = spec.freqs, spec.df
    out = []
    for k in ks:
        fk = k * f0
        bw = band_halfwidth(spec, k) + 0.5 * k * spread_hz
        own = np.flatnonzero(np.abs(freqs - fk) <= bw)
        if len(own) == 0:
            continue
        ic = int(own[np.argmax(pooled[own])])
        p_line = float(pooled[ic])
        near = np.abs(freqs - fk) <= SIDE_MAX_HZ + bw
        side = pooled[near & (np.abs(freqs - fk) > bw)]
        # the floor between lines: a low quantile, since the lines of a dense pattern hold the median
        floor = float(np.quantile(side, 0.1)) if len(side) else 0.0
        need = max(SIDE_SHARE * p_line, SIDE_OVER_FLOOR * floor)
        m_lo, m_hi = int(np.ceil((bw + df) / df)), int(SIDE_MAX_HZ / df)
        if _symmetric_pair(pooled, steady, ic, m_lo, m_hi, need):
            out.append(int(k))
    return out


def _is_peak(p, i) -> bool:
    return 0 < i < len(p) - 1 and p[i] >= p[i - 1] and p[i] >= p[i + 1]


def _peak_near(p, steady, i: int, need: float) -> bool:
    """A steady peak of at least ``need`` at bin ``i`` or next to it."""
    return any(0 < j < min(len(p), len(steady)) - 1 and _is_peak(p, j) and p[j] >= need and steady[j]
               for j in (i - 1, i, i + 1))


def _symmetric_pair(p, steady, ic: int, m_lo: int, m_hi: int, need: float) -> bool:
    """Peaks of at least ``need`` ``m`` and ``2 m`` bins (+-1) below and above ``ic``: the line
    sits in a grid of its own kind (note partials around a harmonic rarely form one)."""
    for m in range(m_lo, m_hi // 2 + 1):
        if all(_peak_near(p, steady, ic + s * j * m, need) for s in (-1, 1) for j in (1, 2)):
            return True
    return False


# A tracked line's baseband: power at a symmetric pair of offsets 0.15-4 Hz, each at least this
# share of the line's own (DC) power, marks a line of a host's fine grid (development cases: loop
# lines 0.17-0.70 of their line, hum lines under the same loops 0.00-0.14). Used only on a comb the
# spectrum's test already gave to a host (lockcomb): a hum line under speech can show 0.4-1.2 too
# (the syllables' modulation of the speech partials beside it), so this alone decides nothing.
BASEBAND_SIDE = 0.3
BASEBAND_SIDE_HZ = (0.15, 4.0)


def baseband_sidebands(v: np.ndarray, fs: float) -> np.ndarray:
    """Each line's strongest symmetric pair of sidebands in its tracked baseband, against its own
    power: ``max over d of min(P(+d), P(-d)) / P(0)`` for d in ``BASEBAND_SIDE_HZ``.

    A pattern placed to the sample with a period of 1-4 s has lines every 0.25-1 Hz: too close to
    the harmonic for the spectrum's test (:func:`grid_lines`, which needs its neighbours outside the
    harmonic's own band), but resolved by the whole input's baseband, where they are sidebands as
    strong as the line. A hum line's baseband holds its level changes only.

    Parameters
    ----------
    v : np.ndarray
        (n, K) complex baseband of K lines at ``fs`` Hz (``finetrack.decimated_baseband``, one
        channel or channels summed).
    fs : float
        Its sample rate (Hz).

    Returns
    -------
    (K,) float array

    Examples
    --------
    >>> t = np.arange(200) / 10.0
    >>> loop = 1 + 2 * np.cos(2 * np.pi * 0.5 * t)            # lines at -0.5, 0, +0.5 Hz, equal
    >>> hum = np.ones(200) + 0.01 * np.random.default_rng(0).standard_normal(200)
    >>> np.round(baseband_sidebands(np.stack([loop, hum], axis=1).astype(complex), 10.0), 2).tolist()
    [1.0, 0.0]
    """
    n = len(v)
    m = 4 * n
    P = np.abs(np.fft.fft(v * np.hanning(n)[:, None], n=m, axis=0)) ** 2
    dc = np.maximum(P[0], 1e-300)
    lo, hi = (int(np.ceil(d * m / fs)) for d in BASEBAND_SIDE_HZ)
    hi = min(hi, m // 2 - 2)
    if hi <= lo:
        return np.zeros(v.shape[1])
    idx = np.arange(lo, hi + 1)
    # each side's peak within a bin of the offset (the pattern's lines fall between the bins)
    pos = np.maximum.reduce([P[idx + j] for j in (-1, 0, 1)])
    neg = np.maximum.reduce([P[-idx + j] for j in (-1, 0, 1)])
    return np.max(np.minimum(pos, neg), axis=0) / dc


def sideband_prominence(v: np.ndarray, fs: float) -> np.ndarray:
    """How far the strongest symmetric pair of sidebands of :func:`baseband_sidebands` stands over
    the baseband's own level: ``max over d of min(P(+d), P(-d))`` over the median of ``P`` at the
    offsets searched. A periodic host's neighbouring lines are lines (thousands of times the
    median); the content's noise under a weak line gives 3-4 (the largest of many pairs of bins),
    and so can reach the weak line's own power without being a host's grid.

    Parameters
    ----------
    v : np.ndarray
        (n, K) complex baseband of K lines at ``fs`` Hz.
    fs : float
        Its sample rate (Hz).

    Returns
    -------
    (K,) float array

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(300) / 10.0
    >>> noise = 0.3 * (rng.standard_normal(300) + 1j * rng.standard_normal(300))
    >>> loop = 1 + 2 * np.cos(2 * np.pi * 0.5 * t) + noise
    >>> p = sideband_prominence(np.stack([loop, 1 + noise], axis=1), 10.0)
    >>> bool(p[0] > 100), bool(p[1] < 10)
    (True, True)
    """
    n = len(v)
    m = 4 * n
    P = np.abs(np.fft.fft(v * np.hanning(n)[:, None], n=m, axis=0)) ** 2
    lo, hi = (int(np.ceil(d * m / fs)) for d in BASEBAND_SIDE_HZ)
    hi = min(hi, m // 2 - 2)
    if hi <= lo:
        return np.zeros(v.shape[1])
    idx = np.arange(lo, hi + 1)
    pos = np.maximum.reduce([P[idx + j] for j in (-1, 0, 1)])
    neg = np.maximum.reduce([P[-idx + j] for j in (-1, 0, 1)])
    level = np.median(np.concatenate([P[idx], P[-idx]]), axis=0)
    return np.max(np.minimum(pos, neg), axis=0) / np.maximum(level, 1e-300)
