"""Analysis steps of ``denoise`` run beside each other (pipeline.py): a worker thread, and the
further-comb search's finer spectrum read through a second handle on the input."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import detect as _detect


class Background:
    """One worker thread for analysis steps that do not depend on each other (NumPy releases the
    GIL in their array work, so on two cores they overlap); the same computations as in turn.
    A context manager: leaving it waits for what is still running.

    Examples
    --------
    >>> with Background() as bg:
    ...     total = bg.submit(np.sum, np.arange(10)).result()
    >>> int(total)
    45
    """

    def __enter__(self):
        from concurrent.futures import ThreadPoolExecutor

        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="denoise-analysis")
        return self

    def __exit__(self, *exc):
        self.pool.shutdown(wait=True, cancel_futures=True)
        return False

    def submit(self, fn, *args):
        return self.pool.submit(fn, *args)

    def spectrum(self, source, keep_hz: float):
        """The further-comb search's finer spectrum (:func:`fine_spectrum`), from a second handle.

        Examples
        --------
        >>> from odnn_sep.audio.io import ArraySource
        >>> with Background() as bg:
        ...     s = bg.spectrum(ArraySource(np.zeros(8000 * 20), 8000), 500.0).result()
        >>> round(1 / s.df, 1)
        5.0
        """
        return self.submit(fine_spectrum, source, keep_hz)


def fine_spectrum(source, keep_hz: float):
    """The spectrum of the further-comb search: segments of a quarter of the input, 4-16 s, read
    through a second handle on ``source`` (safe beside reads of the first one in another thread).

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> s = fine_spectrum(ArraySource(np.zeros(8000 * 20), 8000), 500.0)
    >>> round(1 / s.df, 1)
    5.0
    """
    sr, N = source.sr, source.frames
    seg_hr = float(np.clip(N / sr / 4, 4.0, 16.0))
    src = source.reopen()
    try:
        return _detect.excerpt_spectrum(src, seg_s=seg_hr, keep_segments_hz=keep_hz)
    finally:
        if src is not source:
            src.close()
