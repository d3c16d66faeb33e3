"""Read-ahead for sources read in order (io.FileSource): after two consecutive reads, the next
stretch of the same length is read in a worker thread while the caller computes."""
from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor, wait


class ReadAhead:
    """Reads through ``read_now(start, n)`` (already clipped to the source), one stretch ahead
    when the reads follow each other. The sound-file library releases the GIL while it decodes,
    so a pass over a file decodes while the caller computes; the values are those of
    ``read_now``. Errors of a read ahead surface only when that stretch is asked for.

    The array a read ahead fills is allocated by the caller's thread (``alloc``): freed there
    later, its memory goes back to that thread's heap, where the caller's next arrays reuse it
    (memory allocated by the worker would stay with the worker's heap arena, unused).

    Parameters
    ----------
    read_now : callable
        ``read_now(start, n, out=None)`` -> the samples, into ``out`` when given (not called from
        two threads at once).
    frames : int
        Length of the source.
    alloc : callable
        ``alloc(n)`` -> an empty array for ``n`` samples.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(10.0)
    >>> def read_now(s, n, out=None):
    ...     out = np.empty(n) if out is None else out
    ...     out[:] = x[s: s + n]
    ...     return out
    >>> ra = ReadAhead(read_now, 10, np.empty)
    >>> [ra.read(s, min(3, 10 - s)).tolist() for s in (0, 3, 6, 9)]
    [[0.0, 1.0, 2.0], [3.0, 4.0, 5.0], [6.0, 7.0, 8.0], [9.0]]
    >>> ra.close()
    """

    def __init__(self, read_now, frames: int, alloc):
        self.read_now, self.frames, self.alloc = read_now, int(frames), alloc
        self._ahead = self._end = self._pool = None

    def read(self, start: int, n: int):
        """Samples ``start .. start + n`` (``n >= 1``, inside the source)."""
        ahead, self._ahead = self._ahead, None
        if ahead is not None and ahead[0] == (start, n):
            out = ahead[1].result()
        else:
            if ahead is not None:
                wait([ahead[1]])      # a read-ahead not asked for: let it finish (one file position), unused
            out = self.read_now(start, n)
        if self._end == start and start + n < self.frames:
            nxt = (start + n, min(n, self.frames - start - n))
            if self._pool is None:
                self._pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="audio-read")
            self._ahead = (nxt, self._pool.submit(self.read_now, *nxt, self.alloc(nxt[1])))
        self._end = start + n
        return out

    def close(self):
        """Drop a read in flight (waiting for it) and stop the worker."""
        ahead, self._ahead = self._ahead, None
        if ahead is not None:
            ahead[1].cancel()
        if self._pool is not None:
            self._pool.shutdown(wait=True)
            self._pool = None
