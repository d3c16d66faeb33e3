"""Clipping in the input: hum too loud for the recorder's range has its tops cut flat, and what
the clipping took (flat tops, the harmonics they add) is no sum of steady lines, so it cannot be
removed. 20 s of music under hum clipped on 27 % of its samples came out 5.5 dB under the music
(35.7 dB without the clipping), with "removed hum" and no word of it. :class:`ClipWatch` counts
the clipped samples as pass 2 goes by, and the result warns of them.
"""
from __future__ import annotations

import numpy as np

CLIP_RUN = 3         # samples in a row at full scale that count as clipped (a peak touches it once or twice)
CLIP_SHARE = 1e-3    # share of the samples clipped from which the result is warned of


def full_scale(source) -> tuple[float, float] | None:
    """The band of magnitudes at which a sample of ``source`` sits at its full scale: from just
    under the largest value of an integer file's subtype up, up to 1.0 for a float file (a float
    file may hold larger values, which are not clipped), the largest magnitude of an array (arrays
    have no full scale of their own); None for an array of zeros.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> [round(v, 6) for v in full_scale(ArraySource(np.array([0.1, -0.4, 0.2]), 8000))]
    [0.4, 0.4]
    """
    subtype = getattr(source, "subtype", None)
    if subtype is None:
        peak = float(np.max(np.abs(source.data))) if source.data.size else 0.0
        return (peak * (1 - 1e-9), peak) if peak > 0 else None
    from odnn_sep.audio.io import is_integer_subtype

    if not is_integer_subtype(subtype):
        # (from just under 1: a float file written from a clipped 16-bit one tops at 1 - 2^-15)
        return 1.0 - 2.0 ** -14, 1.0 + 1e-9
    # the largest 8-bit value is 127/128; every wider integer subtype reaches above 1 - 2^-14
    return (1.0 - 2.0 ** -7 if subtype in ("PCM_S8", "PCM_U8") else 1.0 - 2.0 ** -14), 1.0


class ClipWatch:
    """A sink (``sink(piece, removed)``) that counts the input's samples in runs of
    :data:`CLIP_RUN` or more at full scale (runs cut by a piece's edge are counted in
    their parts), then passes the piece on.

    Parameters
    ----------
    sink : callable
        The sink to pass the pieces on to.
    level : (float, float) or None
        The band of magnitudes at full scale (:func:`full_scale`); None counts nothing.

    Examples
    --------
    >>> got = []
    >>> watch = ClipWatch(lambda piece, removed: got.append(piece), (1.0, 1.0))
    >>> x = np.r_[np.zeros(1000), np.ones(5), np.zeros(3), -np.ones(2), np.zeros(990)][:, None]   # 5 in a run
    >>> watch(x, np.zeros_like(x)); watch.clipped, watch.total
    (5, 2000)
    >>> watch.message() is not None, watch.share
    (True, 0.0025)
    """

    def __init__(self, sink, level):
        self.sink, self.level = sink, level
        self.clipped = self.total = 0

    def __call__(self, piece, removed):
        self.total += piece.size
        # most pieces stay under full scale: their extremes say so without a pass of comparisons
        if self.level is not None and piece.size and max(piece.max(), -piece.min()) >= self.level[0]:
            mag = np.abs(piece)
            at = (mag >= self.level[0]) & (mag <= self.level[1])
            if at.any():
                self.clipped += _in_runs(at)
        self.sink(piece, removed)

    @property
    def share(self) -> float:
        """Share of the samples clipped."""
        return self.clipped / max(self.total, 1)

    def message(self) -> str | None:
        """The warning, or None under :data:`CLIP_SHARE`."""
        if self.share < CLIP_SHARE:
            return None
        return (f"the input is clipped: {100 * self.share:.2g} % of its samples sit at full scale in runs of "
                f"{CLIP_RUN} or more; the hum cannot be removed where it was clipped (the flat tops stay), "
                f"record at a lower gain to avoid it")


def _in_runs(at: np.ndarray) -> int:
    """Samples of ``at`` (frames, channels) in runs of True along the frames of CLIP_RUN or more."""
    n = 0
    for col in at.T:
        d = np.diff(np.r_[0, col.astype(np.int8), 0])
        lengths = np.flatnonzero(d == -1) - np.flatnonzero(d == 1)
        n += int(lengths[lengths >= CLIP_RUN].sum())
    return n
