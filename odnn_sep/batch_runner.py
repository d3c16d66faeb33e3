"""Run batch jobs in a local process pool or on Dask, stoppable by Ctrl-C / SIGTERM.

The pool's workers ignore SIGINT (the parent decides what stops) and die with their parent
(Linux ``PR_SET_PDEATHSIG``), so killing the parent, even with SIGKILL, orphans no worker. On an
interrupt the parent sends SIGTERM to the workers: the file each was writing is rolled back by the
worker's own clean-up, and the jobs not started are dropped.
"""
from __future__ import annotations

import logging
import os
import signal
import sys

log = logging.getLogger(__name__)

#: Seconds to wait for a Dask scheduler (``ODNN_SEP_DASK_TIMEOUT`` overrides).
DASK_TIMEOUT_S = 10


def _die_with_parent() -> None:
    """Worker initializer: no SIGINT (the parent handles Ctrl-C); SIGTERM when the parent dies."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    if sys.platform.startswith("linux"):
        import ctypes

        try:
            libc = ctypes.CDLL("libc.so.6", use_errno=True)
            libc.prctl(1, signal.SIGTERM)  # PR_SET_PDEATHSIG
        except OSError:
            pass
        if os.getppid() == 1:  # the parent died before prctl took effect
            os._exit(1)
    _start_orphan_watch(os.getppid())


#: Seconds an orphaned worker is given to roll back its file (after SIGTERM) before it exits anyway.
ORPHAN_GRACE_S = 10


def _start_orphan_watch(parent: int) -> None:
    """A thread that ends the worker if its parent is gone, even when SIGTERM cannot be acted on
    (a long numerical call holds the interpreter; numpy releases the lock this thread needs)."""
    import threading
    import time

    def watch():
        while os.getppid() == parent:
            time.sleep(1.0)
        time.sleep(ORPHAN_GRACE_S)
        os._exit(143)

    threading.Thread(target=watch, name="odnn-sep-orphan-watch", daemon=True).start()


def run_jobs(jobs, args, stopped=None):
    """Run ``jobs`` (process_one argument tuples); return (results, interrupt name or None).

    The pids of local workers stopped by an interrupt are appended to ``stopped``, so the caller can
    sweep temporary files a worker had no time to remove.

    Parameters
    ----------
    jobs : list of tuple
        ``(target, src, dst, extra)`` for :func:`odnn_sep.batch.process_one`, one per file.
    args : argparse.Namespace
        Batch options: ``target``, ``quiet``, ``jobs`` (local workers; one runs in this process) and
        ``dask`` (scheduler address, ``"local"`` or None).
    stopped : list of int, optional
        Receives the pids of local workers stopped by an interrupt.

    Returns
    -------
    results : list of dict
        One :func:`~odnn_sep.batch.process_one` record per finished file, in order of completion.
    interrupt : str or None
        ``"Interrupted"`` (Ctrl-C), ``"Terminated"`` (SIGTERM) or None when every job ran.

    Examples
    --------
    >>> import argparse
    >>> args = argparse.Namespace(target="mismatch", quiet=True, jobs=1, dask=None)
    >>> results, interrupt = run_jobs([("mismatch", "a.csv", "a.json", [])], args)
    >>> interrupt, [(r["input"], r["exit_code"]) for r in results]    # no --model: a usage error
    (None, [('a.csv', 2)])
    """
    from tqdm import tqdm

    show = not args.quiet and sys.stderr.isatty()
    bar = tqdm(total=len(jobs), desc=f"batch {args.target}", unit="file", disable=not show, file=sys.stderr)
    results: list[dict] = []
    interrupt = None
    try:
        if args.dask:
            _run_dask(jobs, args, results, bar)
        else:
            _run_pool(jobs, args, results, bar, stopped if stopped is not None else [])
    except KeyboardInterrupt as exc:
        interrupt = "Terminated" if type(exc).__name__ == "Terminated" else "Interrupted"
    finally:
        bar.close()
    return results, interrupt


def _run_pool(jobs, args, results, bar, stopped) -> None:
    from concurrent.futures import ProcessPoolExecutor, as_completed

    from odnn_sep.batch import process_one

    n = max(1, min(args.jobs or os.cpu_count() or 1, len(jobs)))
    if n == 1:
        for j in jobs:
            r = process_one(*j)
            if r["exit_code"] in (130, 143):  # the file was interrupted in this process
                raise KeyboardInterrupt()
            results.append(r)
            bar.update(1)
        return
    pool = ProcessPoolExecutor(max_workers=n, initializer=_die_with_parent)
    try:
        for fut in as_completed([pool.submit(process_one, *j) for j in jobs]):
            results.append(fut.result())
            bar.update(1)
    except BaseException:
        stopped.extend(_stop_pool(pool))
        raise
    pool.shutdown(wait=True)


def _stop_pool(pool) -> list[int]:
    """Drop queued jobs and terminate the workers (each rolls back the file it was writing); return
    their pids."""
    # the executor keeps its worker processes in a private mapping; there is no public terminate()
    procs = list(getattr(pool, "_processes", {}).values())
    pool.shutdown(wait=False, cancel_futures=True)
    for p in procs:
        if p.is_alive():
            p.terminate()
    for p in procs:
        p.join(timeout=10)
        if p.is_alive():
            p.kill()
            p.join(timeout=5)
    return [p.pid for p in procs if p.pid is not None]


def _run_dask(jobs, args, results, bar) -> None:
    from odnn_sep.batch import process_one
    from odnn_sep.errors import InputError

    try:
        from dask.distributed import Client, LocalCluster, as_completed
    except ImportError:
        raise InputError('--dask needs dask.distributed, which is not installed; install it with: '
                         'pip install "odnn-sep[dask]"') from None
    timeout = float(os.environ.get("ODNN_SEP_DASK_TIMEOUT", DASK_TIMEOUT_S))
    address = args.dask
    cluster = None
    if address == "local":
        cluster = LocalCluster(n_workers=min(args.jobs or os.cpu_count() or 1, len(jobs)), threads_per_worker=1,
                               processes=True, dashboard_address=None)
    elif "://" not in address and ":" not in address:
        raise InputError(f"--dask {address!r} is not a scheduler address; give tcp://HOST:PORT (or 'local')")
    try:
        try:
            client = Client(cluster if cluster is not None else address, timeout=timeout)
        except (OSError, TimeoutError, ValueError, TypeError) as exc:
            raise InputError(f"could not connect to the Dask scheduler at {address!r} within {timeout:g} s "
                             f"({type(exc).__name__}: {str(exc).splitlines()[0] if str(exc) else ''}); check the "
                             "address, or raise ODNN_SEP_DASK_TIMEOUT") from None
        with client:
            futures = [client.submit(process_one, *j, pure=False) for j in jobs]
            try:
                for fut in as_completed(futures):
                    results.append(fut.result())
                    bar.update(1)
            except BaseException:
                client.cancel(futures)
                raise
    finally:
        if cluster is not None:
            cluster.close()
