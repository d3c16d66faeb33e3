"""One BLAS thread for the engines that solve many small problems.

The mismatch finder's fits solve many small least-squares problems on tall, thin matrices (a Jacobian of a few
thousand rows and a few dozen columns, hundreds of times). BLAS threads only add spin-wait overhead
there, and on a busy machine they collapse: a 4000-sample hum record with 10 harmonics took 68 s of
CPU with two BLAS threads on two loaded cores and 5 s with one. The audio engine's
per-block solves are of the same kind.
"""
from __future__ import annotations

import contextlib


def one_blas_thread():
    """A context manager under which BLAS (OpenBLAS, MKL) runs on one thread; a no-op without threadpoolctl.

    Returns
    -------
    context manager

    Examples
    --------
    >>> import numpy as np
    >>> with one_blas_thread():
    ...     x = np.linalg.lstsq(np.eye(3), np.ones(3), rcond=None)[0]
    >>> x.tolist()
    [1.0, 1.0, 1.0]
    """
    try:
        from threadpoolctl import threadpool_limits  # present through scikit-learn
    except ImportError:  # pragma: no cover
        return contextlib.nullcontext()
    return threadpool_limits(limits=1, user_api="blas")
