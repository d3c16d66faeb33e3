"""Digital silence at the ends of the input: the stretch between is what the hum is looked for in.

A take that starts or ends in exact zeros (pre-roll, padding, a recorder's first second) has no
hum there, whatever the rest holds. Analysed as part of the input, those zeros read as hum whose
level steps, and the shared level and the block fit spread the hum into them: 5 s of zeros before
15 s of hummed music came out with hum at -29 dB under the hum's level written into the silence,
and the hum under the music removed by 23 dB instead of 41 dB. The pipeline analyses and fits the
sounding stretch as an input of its own and writes the silent ends as read. A gap of zeros
inside the input (silence an editor inserted) parts it the same way: the hum after it is the hum
before it shifted in time, which the whole input's track follows only in part (20 s of hummed
music with 0.5 s of zeros inserted at 10 s: 19.2 dB removed, 35.5 dB with the halves apart).
Shorter runs of zeros (a dropout) are analysed with the rest, but nothing is taken out of them
(:class:`KeepSilence`).
"""
from __future__ import annotations

import numpy as np

SILENT_END_S = 0.1     # zeros at an end shorter than this stay part of the input (a few cycles at most)
GAP_S = 0.5            # zeros inside the input this long or longer part it into stretches analysed apart
MIN_STRETCH_S = 4.0    # ... each at least this long (a shorter one joins its neighbour, the gap inside)
MAX_SCAN_S = 600.0     # inputs up to this long are looked through for gaps (a read pass of their own)
_STEP = 1 << 15        # frames read at a time while looking for the first and last sound


def sounding_extent(source, min_frames: int) -> tuple[int, int]:
    """``(first frame, frames)`` of the input between its silent ends: runs of exact zeros on
    every channel, at least :data:`SILENT_END_S` long, at its start and end. ``(0, frames)``
    where there are none, or where what sounds is shorter than ``min_frames`` (too little to
    analyse: the input is then taken whole, as before).

    Parameters
    ----------
    source : ArraySource or FileSource
        The input (read from each end until the first sample that is not zero).
    min_frames : int
        Shortest sounding stretch analysed on its own.

    Returns
    -------
    tuple of int

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> y = np.r_[np.zeros(8000), np.ones(16000), np.zeros(400)]
    >>> sounding_extent(ArraySource(y, 8000), 1600)       # 1 s of zeros first; 0.05 s at the end stay
    (8000, 16400)
    >>> sounding_extent(ArraySource(np.r_[np.zeros(8000), np.ones(800)], 8000), 1600)
    (0, 8800)
    """
    N, sr = source.frames, source.sr
    first = _first_sound(source, range(0, N, _STEP), forward=True)
    if first is None:               # all zeros: nothing to cut out
        return 0, N
    last = _first_sound(source, range(max(N - _STEP, 0), -_STEP, -_STEP), forward=False)
    least = int(np.ceil(SILENT_END_S * sr))
    a = first if first >= least else 0
    b = last + 1 if N - (last + 1) >= least else N
    if (a, b) == (0, N) or b - a < min_frames:
        return 0, N
    return a, b - a


def sounding_stretches(source, min_frames: int) -> list[tuple[int, int]]:
    """``[(first frame, frames)]`` of the input between its digital silences: its silent ends
    (:func:`sounding_extent`) and, on inputs up to :data:`MAX_SCAN_S`, runs of exact zeros on
    every channel of :data:`GAP_S` or more inside it, where what sounds on each side is at least
    :data:`MIN_STRETCH_S` long (a shorter stretch keeps the gap beside it). ``[(0, frames)]``
    where there is none.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input.
    min_frames : int
        Shortest sounding stretch analysed on its own (see :func:`sounding_extent`).

    Returns
    -------
    list of (int, int)

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; on, gap = np.ones(5 * sr), np.zeros(sr)
    >>> sounding_stretches(ArraySource(np.r_[gap, on, gap, on, gap[:50], on], sr), 200)
    [(1000, 5000), (7000, 10050)]
    >>> sounding_stretches(ArraySource(np.r_[on, gap, on[:2 * sr]], sr), 200)     # 2 s after the gap
    [(0, 8000)]
    """
    a, n = sounding_extent(source, min_frames)
    sr = source.sr
    if n > MAX_SCAN_S * sr:
        return [(a, n)]
    gaps = _gaps(source, a, n, int(np.ceil(GAP_S * sr)))
    bounds = [a] + [g for gap in gaps for g in gap] + [a + n]
    stretches = [(bounds[i], bounds[i + 1]) for i in range(0, len(bounds), 2)]
    least = MIN_STRETCH_S * sr
    while len(stretches) > 1:
        short = [i for i, (s0, s1) in enumerate(stretches) if s1 - s0 < least]
        if not short:
            break
        i = short[0]
        j = i - 1 if i == len(stretches) - 1 else i     # join it to the next one (the last: to the one before)
        stretches[j: j + 2] = [(stretches[j][0], stretches[j + 1][1])]
    return [(int(s0), int(s1 - s0)) for s0, s1 in stretches]


def _gaps(source, a: int, n: int, least: int) -> list[tuple[int, int]]:
    """``[(start, end)]`` of the runs of zeros on every channel, ``least`` frames or longer, in
    frames ``a .. a + n`` of ``source``."""
    gaps, run0 = [], None
    for s in range(a, a + n, _STEP):
        silent = ~(source.read(s, min(_STEP, a + n - s)) != 0).any(axis=1)
        d = np.diff(np.r_[0, silent.astype(np.int8), 0])
        starts, ends = (np.flatnonzero(d == 1) + s).tolist(), (np.flatnonzero(d == -1) + s).tolist()
        if run0 is not None:            # a run from the last piece goes on
            if starts and starts[0] == s:
                starts[0] = run0
            else:
                if s - run0 >= least:
                    gaps.append((run0, s))
        run0 = None
        if ends and ends[-1] == min(s + _STEP, a + n) and ends[-1] < a + n:
            run0 = starts.pop()          # runs on into the next piece
            ends.pop()
        gaps += [(g0, g1) for g0, g1 in zip(starts, ends, strict=True) if g1 - g0 >= least]
    return gaps


def _first_sound(source, starts, *, forward: bool) -> int | None:
    """The first (or, reading backwards, the last) frame with a sample that is not zero."""
    for s in starts:
        s = max(s, 0)
        piece = source.read(s, min(_STEP, source.frames - s))
        loud = np.flatnonzero((piece != 0).any(axis=1))
        if loud.size:
            return s + int(loud[0] if forward else loud[-1])
    return None


class KeepSilence:
    """A sink (``sink(piece, removed)``, pieces in order from the input's first frame) that
    passes nothing of the hum fitted where the input is digitally silent: runs of exact zeros on
    every channel at least :data:`SILENT_END_S` long stay zeros in the output.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input (read for a run's length beyond each piece's ends, to see the runs crossing them).
    sink : callable
        The sink to pass the pieces on to.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> y = np.r_[np.ones(100), np.zeros(1000), np.ones(100), np.zeros(5)][:, None]
    >>> got = []
    >>> keep = KeepSilence(ArraySource(y, 8000), lambda piece, removed: got.append(removed))
    >>> keep(y[:600], np.full((600, 1), 0.5)); keep(y[600:], np.full((605, 1), 0.5))
    >>> r = np.concatenate(got)[:, 0]
    >>> float(r[:100].min()), float(r[100:1100].max()), float(r[1100:].min())    # 5 zeros are not a run
    (0.5, 0.0, 0.5)
    """

    def __init__(self, source, sink):
        self.source, self.sink, self.pos = source, sink, 0
        self.least = int(np.ceil(SILENT_END_S * source.sr))

    def __call__(self, piece, removed):
        n, L = piece.shape[0], self.least
        if not _may_touch_run(piece, L):    # most pieces: no run can reach into them, nothing to read
            self.pos += n
            self.sink(piece, removed)
            return
        lo = max(self.pos - L, 0)
        silent = ~(self.source.read(lo, self.pos - lo) != 0).any(axis=1)
        silent = np.r_[silent, ~(piece != 0).any(axis=1)]
        silent = np.r_[silent, ~(self.source.read(self.pos + n, L) != 0).any(axis=1)]
        if silent.any():
            keep = _long_runs(silent, L)[self.pos - lo: self.pos - lo + n]
            if keep.any():
                removed = np.where(keep[:, None], 0.0, removed)
        self.pos += n
        self.sink(piece, removed)


def _may_touch_run(piece: np.ndarray, least: int) -> bool:
    """Whether a run of ``least`` or more silent frames can cross ``piece``: such a run holds the
    piece's first or last frame, or lies inside it and then holds one of every ``least``-th frame.
    Looks at about 1 / ``least`` of the piece, where a full test reads and compares all of it.

    Examples
    --------
    >>> x = np.ones((1000, 2)); x[310:390] = 0          # 80 silent frames
    >>> _may_touch_run(x, 50), _may_touch_run(x, 100)
    (True, False)
    """
    n = piece.shape[0]
    if n == 0:
        return False
    rows = np.r_[0:n:max(least, 1), n - 1]
    return bool((piece[rows] == 0).all(axis=1).any())


def _long_runs(mask: np.ndarray, least: int) -> np.ndarray:
    """``mask`` with its runs of True shorter than ``least`` set False."""
    d = np.diff(np.r_[0, mask.astype(np.int8), 0])
    starts, ends = np.flatnonzero(d == 1), np.flatnonzero(d == -1)
    long = ends - starts >= least
    # +1 where a long run starts, -1 where it ends (quiet 16-bit audio has many short runs)
    edges = np.zeros(mask.size + 1, np.int32)
    edges[starts[long]] += 1
    edges[ends[long]] -= 1
    return np.cumsum(edges[:-1]) > 0
