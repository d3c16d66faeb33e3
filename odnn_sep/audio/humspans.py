"""Hum over part of the input only (hum spans): a device switched on or off during the take, a cable moved.

The whole-input tests ask that a line persist through the recording (detect.py's persistence
test, the lock test of lock.py): that is what tells hum from a held note. Hum that sounds for 8 s
of a 25 s take fails them and was left in whole (5 of 6 such generated cases: "no mains hum
found"). When the whole input shows no hum, the detection spectrum's per-segment periodograms
(4 s Hann, 2 s apart) are read for the segments in which ``MIN_LINES`` or more harmonics of one
family stand over their own segment's floor. Runs of such segments, ``MIN_STRETCH_S`` long or
more, are then analysed as inputs of their own by every test the whole input gets (detection,
phase lock, tracking, the shared level and its steps); only what those tests accept there is
removed there, and only with ``MIN_LINES`` harmonics or more (a held note has one line near a
harmonic, not a locked comb). The rest of the input is written as read.
"""
from __future__ import annotations

import numpy as np
from scipy import special

from odnn_sep.audio import detect as _detect
from odnn_sep.audio import track as _track

MIN_LINES = 2          # harmonics standing in one segment (and locked in the stretch's analysis)
ALPHA_SHARE = 0.01     # a stretch's own tests run at this share of the significance level
SEGMENT_P = 1e-3       # one harmonic's p-value in one segment, against that segment's floor
RING_HZ = 6.0          # the segment's floor: this many Hz of bins each side, beyond twice the band
TOP_HZ = 1000.0        # harmonics looked at in the segments: up to this frequency
MIN_STRETCH_S = 6.0    # shortest stretch analysed (at least two of the lock test's 4 s segments)
MAX_SHARE = 0.95       # a stretch covering more of the input than this is the whole input's business
MAX_STRETCHES = 8      # stretches analysed at most (the longest first)
MARGIN_S = 0.5         # added on each side of a run of segments (a switch inside a segment's taper)
TIGHT_SEG_S = 1.0      # segments of the finer look at a stretch's edges (tighten)
TIGHT_MIN_S = 4.0      # shortest run the finer look keeps (the held notes last up to 4 s)
TIGHT_MARGIN_S = 0.25
EDGE_S = 2.0           # a switch this near a stretch's end is where the stretch is cut (cut_at_switches)
SWITCH_WINDOW_S = 0.1  # the Hann over which the lines are demodulated to place a switch
ABSENT_S = 4.0         # a lone hum line found in the whole input but absent this long at its start or
ABSENT_SHARE = 0.01    # end (power under this share of its level) is fitted where it sounds (hum_extent)
CUT_MIN_S = 2.0        # ... unless less than this would be left between the switches


class SliceSource:
    """Frames ``start .. start + frames`` of another source, read through it.

    Parameters
    ----------
    base : ArraySource or FileSource
        The whole input.
    start, frames : int
        First frame and length of the slice.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> s = SliceSource(ArraySource(np.arange(10.0), 8000), 3, 4)
    >>> s.frames, s.read(0, 2).ravel().tolist(), s.read(3, 9).ravel().tolist()
    (4, [3.0, 4.0], [6.0])
    """

    def __init__(self, base, start: int, frames: int):
        self.base, self.start = base, int(start)
        self.frames = int(min(frames, base.frames - self.start))
        self.sr, self.channels, self.mono, self.name = base.sr, base.channels, base.mono, base.name

    def read(self, start: int, n: int) -> np.ndarray:
        start = max(start, 0)
        n = max(0, min(n, self.frames - start))
        return self.base.read(self.start + start, n)

    def reopen(self) -> SliceSource:
        """A slice of the base opened again (for another thread); close it after use."""
        return SliceSource(self.base.reopen(), self.start, self.frames)

    def close(self):
        if self.base is not None and hasattr(self.base, "f"):     # a reopened file: its own handle
            self.base.close()


def segment_presence(spec, nominal_hz: float, top_hz: float = TOP_HZ) -> np.ndarray:
    """How many harmonics of ``nominal_hz`` stand over their own segment's floor, per segment of
    ``spec`` (its ``segments``: per-segment periodograms, channels pooled); under no line a
    segment's band mean over the mean of the bins beside it is F-distributed.

    Parameters
    ----------
    spec : Spectrum
        With ``segments`` (detect.excerpt_spectrum(..., keep_segments_hz=...)).
    nominal_hz : float
        Family (Hz); each band allows for the drift detect.py allows for.
    top_hz : float
        Highest harmonic frequency looked at.

    Returns
    -------
    (n_segments,) int array

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(20 * sr) / sr
    >>> hum = np.where((t > 8) & (t < 16), np.cos(2 * np.pi * 50 * t) + np.cos(2 * np.pi * 150 * t), 0.0)
    >>> y = hum + 0.1 * np.random.default_rng(0).standard_normal(len(t))
    >>> spec = _detect.excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=1200)
    >>> segment_presence(spec, 50.0).tolist()
    [0, 0, 0, 2, 2, 2, 2, 2, 0]
    """
    S = spec.segments
    if S is None or S.shape[-1] < 2:
        return np.zeros(0 if S is None else S.shape[-1], int)
    fr = spec.freqs[: S.shape[0]]
    P = S.sum(axis=1, dtype=np.float64)                      # (bins, segments), channels pooled
    count = np.zeros(S.shape[-1], int)
    k = 1
    while k * nominal_hz + RING_HZ <= min(top_hz, fr[-1]):
        d = np.abs(fr - k * nominal_hz)
        bw = _detect.band_halfwidth(spec, k)
        band, ring = d <= bw, (d > 2 * bw) & (d <= 2 * bw + RING_HZ)
        if band.any() and ring.sum() >= 4:
            r = P[band].mean(axis=0) / np.maximum(P[ring].mean(axis=0), 1e-300)
            # band and floor are both means of a few Hann bins (neighbours correlated: 1.5 bins
            # count as one): their ratio is F-distributed under no line
            m, m_ring = (max(1.0, sel.sum() / 1.5) * S.shape[1] for sel in (band, ring))
            count += special.fdtrc(2 * m, 2 * m_ring, r) < SEGMENT_P
        k += 1
    return count


def find_stretches(spec, sr: int, frames: int, nominals, *, seg_s: float = 4.0,
                   min_s: float = MIN_STRETCH_S, margin_s: float = MARGIN_S) -> list[tuple[int, int, float]]:
    """Stretches of the input (first frame, frame count, family) where ``MIN_LINES`` harmonics of
    one of ``nominals`` stand segment after segment (one quiet segment between two runs joins
    them), ``min_s`` or longer and under ``MAX_SHARE`` of the input; the longest first. Only for
    a spectrum of the whole input (its segments of ``seg_s`` in time order, 50 % overlap).

    Parameters
    ----------
    spec : Spectrum
        The detection spectrum of the whole input.
    sr, frames : int
        The input's sample rate and length.
    nominals : iterable of float
        Families to look for (50 and 60 Hz, or the given one).
    seg_s, min_s, margin_s : float
        The spectrum's segment length, the shortest stretch kept and the margin added on each
        side (s).

    Returns
    -------
    list of (int, int, float)

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(24 * sr) / sr
    >>> hum = np.where((t > 8) & (t < 17), np.cos(2 * np.pi * 60 * t) + np.cos(2 * np.pi * 180 * t), 0.0)
    >>> y = hum + 0.1 * np.random.default_rng(0).standard_normal(len(t))
    >>> spec = _detect.excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=1200)
    >>> [(a / sr, n / sr, f) for a, n, f in find_stretches(spec, sr, len(y), (50.0, 60.0))]
    [(5.5, 15.0, 60.0)]
    """
    S = spec.segments
    if S is None or abs(spec.seconds - frames / sr) > 1e-6 * frames / sr + 1.0 / sr:
        return []
    L = S.shape[-1]
    nper = int(min(seg_s * sr, max(frames // 2, 16)))
    step = nper - nper // 2
    if L < 3 or 1 + (frames - nper) // step != L:
        return []
    out = []
    for nominal in nominals:
        on = segment_presence(spec, float(nominal)) >= MIN_LINES
        on[1:-1] |= on[:-2] & on[2:]                          # one quiet segment between two runs
        edges = np.flatnonzero(np.diff(np.concatenate([[0], on.astype(int), [0]])))
        for j0, j1 in zip(edges[::2], edges[1::2], strict=True):
            a = max(0, j0 * step - int(margin_s * sr))
            # a run through the last segment reaches the input's end (the segments stop short of it)
            b = frames if j1 == L else min(frames, (j1 - 1) * step + nper + int(margin_s * sr))
            if b - a >= min_s * sr and b - a <= MAX_SHARE * frames:
                out.append((int(a), int(b - a), float(nominal)))
    out.sort(key=lambda s: -s[1])
    kept = []
    for a, n, f in out:                     # the longest first; a stretch overlapping a kept one goes
        if all(a + n <= a2 or a2 + n2 <= a for a2, n2, _ in kept):
            kept.append((a, n, f))
    return sorted(kept[:MAX_STRETCHES])


def tighten(source, a: int, n: int, nominal: float) -> tuple[int, int]:
    """The stretch ``a .. a + n`` of ``source`` cut to where its lines stand in 1 s segments
    (0.5 s apart): the 4 s segments that found it overhang a switch by up to 4 s, and hum
    absent from part of a stretch weakens its lock test as it did the whole input's. Returns the
    stretch unchanged where the finer look finds no run of ``TIGHT_MIN_S``.

    Parameters
    ----------
    source : ArraySource or FileSource
        The whole input.
    a, n : int
        The stretch (first frame, frames).
    nominal : float
        Its family (Hz).

    Returns
    -------
    (int, int)

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(24 * sr) / sr
    >>> hum = np.where((t > 8) & (t < 17), np.cos(2 * np.pi * 60 * t) + np.cos(2 * np.pi * 180 * t), 0.0)
    >>> y = hum + 0.1 * np.random.default_rng(0).standard_normal(len(t))
    >>> a, n = tighten(ArraySource(y, sr), 5 * sr, 17 * sr, 60.0)
    >>> a / sr, (a + n) / sr
    (7.25, 17.75)
    """
    sub = SliceSource(source, a, n)
    spec = _detect.excerpt_spectrum(sub, seg_s=TIGHT_SEG_S, keep_segments_hz=TOP_HZ + 2 * RING_HZ)
    runs = find_stretches(spec, sub.sr, sub.frames, (nominal,), seg_s=TIGHT_SEG_S, min_s=TIGHT_MIN_S,
                          margin_s=TIGHT_MARGIN_S)
    if not runs:
        return a, n
    first, last = min(r[0] for r in runs), max(r[0] + r[1] for r in runs)
    return a + first, last - first


def cut_at_switches(source, a: int, n: int, f0: float, ks) -> tuple[int, int]:
    """The stretch ``a .. a + n`` cut where its hum switches on and off, within ``EDGE_S`` of
    either end: the hum's lines (``k f0``, ``ks``) demodulated over a 0.1 s Hann, their powers
    summed, and each end moved to the first or last instant that power reaches a quarter of its
    mean over the stretch's middle, where the hum sounds (half its amplitude: a switch, blurred
    by the window). The stretch's own fit gives the hum one level beside
    a switch, averaged over the half second or so around it: where the hum is absent a third of
    it was subtracted. Returns the stretch unchanged where less than ``CUT_MIN_S`` would be left.

    Parameters
    ----------
    source : ArraySource or FileSource
        The whole input.
    a, n : int
        The stretch (first frame, frames).
    f0 : float
        The stretch's fundamental (Hz).
    ks : sequence of int
        Its harmonics.

    Returns
    -------
    (int, int)

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(20 * sr) / sr
    >>> on = (t > 6.3) & (t < 13.7)
    >>> y = on * (np.cos(2 * np.pi * 50 * t) + np.cos(2 * np.pi * 100 * t))
    >>> y = y + 0.3 * np.random.default_rng(0).standard_normal(len(t))
    >>> a, n = cut_at_switches(ArraySource(y, sr), 5 * sr, 10 * sr, 50.0, [1, 2])
    >>> round(a / sr, 2), round((a + n) / sr, 2)
    (6.3, 13.7)
    """
    sr = source.sr
    e = int(min(EDGE_S * sr, n // 2))
    h = int(SWITCH_WINDOW_S * sr) | 1
    win = np.hanning(h + 2)[1:-1]
    win /= win.sum()

    def power(s0, length):
        # the lines' demodulated power over the window, summed, at each sample of s0 .. s0 + length
        x = source.read(s0, length).sum(axis=1)                  # channels pooled
        t = (np.arange(x.size) + s0) / sr
        return sum(np.abs(np.convolve(x * np.exp(-2j * np.pi * k * f0 * t), win, mode="same")) ** 2 for k in ks)

    heads = [(s0 - h, power(s0 - h, e + 2 * h)) for s0 in (a, a + n - e)]      # h beyond each side
    # the power in the middle of the stretch, where the hum sounds: its level
    ref = float(np.mean(power(a + n // 2 - e // 2, e)))
    if ref <= 0:
        return a, n
    (o1, P1), (o2, P2) = heads
    lo, hi = h, h + e                                            # the samples inside the stretch
    above1 = np.flatnonzero(P1[lo:hi] >= 0.25 * ref)
    above2 = np.flatnonzero(P2[lo:hi] >= 0.25 * ref)
    first = o1 + lo + (int(above1[0]) if above1.size else 0)
    last = o2 + lo + (int(above2[-1]) + 1 if above2.size else e)
    # at the input's own ends the window runs out of samples and the power falls: not a switch
    first = 0 if a == 0 and first <= a + h else first
    last = a + n if a + n >= source.frames and last >= a + n - h else last
    if last - first < CUT_MIN_S * sr:
        return a, n
    return first, last - first


def hum_extent(source, f0: float, k: int, max_seconds: float = 240.0) -> tuple[int, int] | None:
    """Where a lone hum line (harmonic ``k`` of ``f0``) the whole input's analysis found sounds,
    when it is absent for ``ABSENT_S`` or more at the input's start or end: ``(first frame,
    frames)``, else None. Its chunk sums (track.demodulate) summed over 0.1 s give its power; its
    level is the 90th percentile of that power; it sounds from the first to the last instant at a
    quarter of that level, and is absent before and after when the power there averages under
    ``ABSENT_SHARE`` of it (a line masked by loud content is not absent: the content counts).
    A shared level (envelope.py) needs two lines, so a lone line is fitted with one level per
    block, smeared across a switch: a line on for 15 s of 26 s gained 6 dB.

    Parameters
    ----------
    source : ArraySource or FileSource
        The whole input.
    f0 : float
        The tracked fundamental's median (Hz).
    k : int
        The line's harmonic number.
    max_seconds : float
        Longer inputs are not looked at (None).

    Returns
    -------
    (int, int) or None

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(30 * sr) / sr
    >>> y = ((t > 9.0) & (t < 24.0)) * np.cos(2 * np.pi * 50 * t)
    >>> y = y + 0.1 * np.random.default_rng(0).standard_normal(len(t))
    >>> a, n = hum_extent(ArraySource(y, sr), 50.0, 1)
    >>> round(a / sr, 1), round((a + n) / sr, 1)
    (9.0, 24.0)
    >>> hum_extent(ArraySource(np.cos(2 * np.pi * 50 * t), sr), 50.0, 1) is None
    True
    """
    sr, N = source.sr, source.frames
    if N > max_seconds * sr:
        return None
    D = _track.demodulate(source, f0, [k])
    m = _track.chunk_length(sr)
    L = max(1, int(round(SWITCH_WINDOW_S * sr / m)))
    if D.shape[0] < 3 * L:
        return None
    cs = np.concatenate([np.zeros((1,) + D.shape[1:], complex), np.cumsum(D, axis=0, dtype=complex)])
    P = (np.abs(cs[L:] - cs[:-L]) ** 2).sum(axis=(1, 2))          # window j: chunks j .. j + L - 1
    level = float(np.percentile(P, 90))
    above = np.flatnonzero(P >= 0.25 * level)
    if level <= 0 or not above.size:
        return None
    j0, j1 = int(above[0]), int(above[-1])
    first = max(0, (j0 + L // 2) * m)                # the window at a quarter of the level: about on the switch
    last = min(N, (j1 + L // 2 + 1) * m)
    lead, tail = P[: max(0, j0 - L)], P[j1 + L + 1:]
    absent = [len(p) * m >= ABSENT_S * sr and float(np.mean(p)) < ABSENT_SHARE * level for p in (lead, tail)]
    if not any(absent) or last - first < CUT_MIN_S * sr:
        return None
    first, last = (first if absent[0] else 0), (last if absent[1] else N)
    return first, last - first


def enough_lines(source, opts) -> bool:
    """Whether the detection spectrum of ``source`` (a stretch) holds ``MIN_LINES`` harmonics or
    more at ``opts``' level (detect.detect_hum): a stretch whose spectrum shows fewer cannot
    lock that many, and its lock tests (the costly part of an analysis) are skipped. Stretches
    proposed by music (a voice's partials near the harmonics) are most of those looked at.

    Parameters
    ----------
    source : SliceSource
        The stretch.
    opts : DenoiseOptions
        Validated options (mains, alpha, max_hz).

    Returns
    -------
    bool

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.options import DenoiseOptions
    >>> sr = 4000; t = np.arange(8 * sr) / sr
    >>> noise = 0.3 * np.random.default_rng(0).standard_normal(t.size)
    >>> hum = np.cos(2 * np.pi * 50 * t) + np.cos(2 * np.pi * 100 * t)
    >>> opts = DenoiseOptions().validated(sr)
    >>> enough_lines(ArraySource(hum + noise, sr), opts), enough_lines(ArraySource(noise, sr), opts)
    (True, False)
    """
    top = _detect.top_hz(source.sr, opts.max_hz)
    spec = _detect.excerpt_spectrum(source, keep_segments_hz=top + 2 * _detect.FLOOR_WIDTH_HZ)
    det = _detect.detect_hum(spec, source.sr, mains=opts.mains, harmonics="auto", alpha=opts.alpha,
                             max_hz=opts.max_hz)
    return len(det.harmonics) >= MIN_LINES
