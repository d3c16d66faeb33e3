"""File helpers shared by front-ends: atomic writes, all-or-nothing runs, strict JSON (the path
checks they rely on are in :mod:`odnn_sep.io_paths`).

Safety rules every command follows through these helpers:

* an output is never an input of the run, nor another output of the same run;
* only regular files (or new paths) are written: devices, pipes and folders are refused;
* a file is written to a temporary folder named ``.odnn-tmp-XXXX`` beside its target and renamed
  into place, so a crash leaves no half-written file and no temporary name that a glob such as
  ``*.wav`` could take as an input;
* inside :func:`output_transaction` (the CLI opens one per run), a failure after some outputs
  were written removes them again (or restores the file they replaced): every output or none.
"""
from __future__ import annotations

import contextlib
import errno
import os
import shutil
from pathlib import Path

from odnn_sep.errors import FormatError
from odnn_sep.io_paths import check_output_target

#: Prefix of the temporary folders holding files being written; ``batch`` never takes them as input.
TMP_PREFIX = ".odnn-tmp-"


class _Transaction:
    """Outputs written so far in one run, so that a later failure can take them back."""

    def __init__(self):
        # [target, backup of the file it replaced or None, temporary folder, replaced yet?]
        self.done: list[list] = []

    def rollback(self) -> None:
        for target, backup, tmpdir, replaced in reversed(self.done):
            with contextlib.suppress(OSError):
                if replaced and backup is not None:
                    os.replace(backup, target)
                elif replaced:
                    os.unlink(target)
            shutil.rmtree(tmpdir, ignore_errors=True)
        self.done.clear()

    def commit(self) -> None:
        for _, _, tmpdir, _ in self.done:
            shutil.rmtree(tmpdir, ignore_errors=True)
        self.done.clear()


_ACTIVE: list[_Transaction] = []


@contextlib.contextmanager
def output_transaction():
    """Every output written by :func:`atomic_output` inside the block stays only if the block succeeds.

    A file the run replaced is restored on failure (it is kept as a hard link until the end).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     try:
    ...         with output_transaction():
    ...             with atomic_output(os.path.join(d, "a.txt")) as tmp:
    ...                 with open(tmp, "w") as fh:
    ...                     _ = fh.write("first output")
    ...             raise RuntimeError("the second output failed")
    ...     except RuntimeError:
    ...         pass
    ...     os.listdir(d)                    # all or nothing: the first output was removed again
    []
    """
    tr = _Transaction()
    _ACTIVE.append(tr)
    try:
        yield tr
    except BaseException:
        tr.rollback()
        raise
    else:
        tr.commit()
    finally:
        _ACTIVE.remove(tr)


@contextlib.contextmanager
def atomic_output(out, suffix: str | None = None):
    """Yield a temporary path for ``out``; move it onto ``out`` only if the block succeeds.

    The temporary file lives in a fresh ``.odnn-tmp-XXXX`` folder beside ``out`` and keeps the
    output's suffix (writers pick the format from it). A failure, or SIGINT/SIGTERM under the CLI,
    leaves nothing behind.

    Parameters
    ----------
    out : str or path-like
        The final output path (checked with :func:`check_output_target`).
    suffix : str, optional
        Suffix of the temporary file (default that of ``out``).

    Yields
    ------
    pathlib.Path
        The temporary file to write.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = os.path.join(d, "result.txt")
    ...     with atomic_output(out) as tmp:
    ...         with open(tmp, "w") as fh:
    ...             _ = fh.write("done")
    ...     with open(out) as fh:
    ...         fh.read(), os.listdir(d)
    ('done', ['result.txt'])
    """
    import secrets

    o = check_output_target(out)
    ext = (suffix if suffix is not None else o.suffix)[:32]
    # the name is known before the folder exists, so an interrupt at any point can still remove it
    # the writer's pid is in the name, so whoever stops a killed writer can sweep what it left
    tmpdir = o.resolve().parent / f"{TMP_PREFIX}{os.getpid()}-{secrets.token_hex(6)}"
    record = None
    try:
        os.mkdir(tmpdir, 0o700)
        tmp = tmpdir / ("part" + ext)
        yield tmp
        if not tmp.exists():
            raise FormatError(f"nothing was written for {str(o)!r}")
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)  # the permissions a normally created file would have
        check_output_target(o)  # it may have been replaced by a device or folder meanwhile
        if _ACTIVE:
            backup = None
            if o.exists():
                backup = tmpdir / "replaced"
                try:
                    os.link(o, backup)
                except OSError:
                    backup = None  # no hard links here: the old file cannot be restored on a later failure
            record = [o, backup, tmpdir, False]
            _ACTIVE[-1].done.append(record)  # from here on the transaction cleans up
        os.replace(tmp, o)
        if record is not None:
            record[3] = True
    except BaseException:
        if record is None:
            shutil.rmtree(tmpdir, ignore_errors=True)
        raise
    if record is None:
        shutil.rmtree(tmpdir, ignore_errors=True)


def remove_temporaries_of(pids, folders) -> None:
    """Remove the temporary folders that processes ``pids`` (stopped, dead) left directly in ``folders``.

    A writer killed before its clean-up ran (SIGKILL, or SIGTERM while a long numerical call held
    the interpreter) leaves its ``.odnn-tmp-PID-XXXX`` folder; only the process that stopped it
    knows it is dead, so that process sweeps. Other processes' temporaries are left alone.

    Parameters
    ----------
    pids : iterable of int
        Process ids of the stopped writers.
    folders : iterable of str or path-like
        Folders the writers wrote into (not searched recursively; missing ones are skipped).

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     for name in (".odnn-tmp-41-a1b2", ".odnn-tmp-42-c3d4", "results"):
    ...         os.mkdir(os.path.join(d, name))
    ...     remove_temporaries_of([41], [d])
    ...     sorted(os.listdir(d))
    ['.odnn-tmp-42-c3d4', 'results']
    """
    prefixes = tuple(f"{TMP_PREFIX}{int(pid)}-" for pid in pids)
    if not prefixes:
        return
    for folder in {Path(f) for f in folders}:
        try:
            entries = list(os.scandir(folder))
        except OSError:
            continue
        for e in entries:
            if e.name.startswith(prefixes) and e.is_dir(follow_symlinks=False):
                shutil.rmtree(e.path, ignore_errors=True)


def is_temporary(path) -> bool:
    """True for files inside this package's temporary folders (and other hidden names).

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    bool
        True when some part of the path is hidden (starts with a dot).

    Examples
    --------
    >>> is_temporary("out/.odnn-tmp-1a2b/clean.wav"), is_temporary("out/clean.wav")
    (True, False)
    """
    return any(part.startswith(".") and part not in (".", "..") for part in Path(path).parts)


def describe_os_error(exc: OSError) -> str:
    """One line for an operating-system error met while reading or writing a file.

    Parameters
    ----------
    exc : OSError
        The error, with its ``errno`` and ``filename`` where known.

    Returns
    -------
    str
        The message, with what to do where the error says it.

    Examples
    --------
    >>> describe_os_error(OSError(errno.ENOSPC, "No space left on device", "out.wav"))
    "no space left on device while writing 'out.wav'; free some space or choose another output path"
    """
    where = f" {exc.filename!r}" if getattr(exc, "filename", None) else ""
    if exc.errno == errno.ENOSPC:
        return f"no space left on device while writing{where}; free some space or choose another output path"
    if exc.errno == errno.EDQUOT:
        return f"disk quota exceeded while writing{where}; free some space or choose another output path"
    if exc.errno in (errno.EACCES, errno.EPERM, errno.EROFS):
        return f"permission denied for{where or ' a file'} ({exc.strerror}); choose another path"
    if exc.errno == errno.ENAMETOOLONG:
        return f"file name too long{where}; choose a shorter name"
    return f"{exc.strerror or exc}{where}"


def write_json(out, obj) -> None:
    """Write ``obj`` as strict JSON atomically: NaN and infinities become null, numpy types plain.

    Reports written during a CLI run also get the header of :mod:`odnn_sep.report.schema`
    (``schema_version``, ``odnn_sep_version``, ``command``, ``options``).

    Parameters
    ----------
    out : str or path-like
        The JSON file.
    obj : object
        Dicts, lists, numbers, strings, numpy values, paths (see :func:`to_jsonable`).

    Examples
    --------
    >>> import json, os, tempfile
    >>> import numpy as np
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = os.path.join(d, "report.json")
    ...     write_json(out, {"theta": np.array([1.5, np.nan])})
    ...     with open(out) as fh:
    ...         json.load(fh)
    {'theta': [1.5, None]}
    """
    import json

    from odnn_sep.report.schema import with_header

    check_output_target(out)
    text = json.dumps(to_jsonable(with_header(obj)), indent=2, allow_nan=False)
    with atomic_output(out, suffix=".json") as tmp, open(tmp, "w") as fh:
        fh.write(text + "\n")


def ensure_readable(path, reader, *, what: str):
    """Call ``reader(path)`` and turn library-specific read failures into one FormatError line.

    Parameters
    ----------
    path : str or path-like
        The file.
    reader : callable
        ``reader(path)``, e.g. a library's file loader.
    what : str
        What the file is, for the message.

    Returns
    -------
    object
        What ``reader`` returns.

    Raises
    ------
    odnn_sep.errors.FormatError
        When ``reader`` raises OSError, RuntimeError or ValueError.

    Examples
    --------
    >>> def reader(path):
    ...     raise RuntimeError("Error opening 'x.wav': Format not recognised.")
    >>> ensure_readable("x.wav", reader, what="audio file")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.FormatError: could not read audio file 'x.wav': Error opening 'x.wav': Format not recognised.
    """
    try:
        return reader(path)
    except (OSError, RuntimeError, ValueError) as exc:
        raise FormatError(f"could not read {what} {str(path)!r}: {str(exc).splitlines()[0]}") from None


def to_jsonable(v):
    """Recursively convert numpy scalars/arrays, tuples and paths to plain JSON types.

    Non-finite floats become None, so the JSON is strict (``allow_nan=False`` parsers accept it).

    Parameters
    ----------
    v : object
        A value, possibly nested in dicts, lists, tuples and sets.

    Returns
    -------
    object
        Plain dicts (string keys), lists, numbers, strings, None; complex numbers as [real, imag].

    Examples
    --------
    >>> import numpy as np
    >>> to_jsonable({"a": np.float32(0.5), "b": (1, np.inf), "c": np.arange(2)})
    {'a': 0.5, 'b': [1, None], 'c': [0, 1]}
    """
    import math

    import numpy as np

    if isinstance(v, Path):
        return str(v)
    if isinstance(v, np.ndarray):
        return to_jsonable(v.tolist())
    if isinstance(v, np.generic):
        return to_jsonable(v.item())
    if isinstance(v, float):
        return v if math.isfinite(v) else None
    if isinstance(v, complex):
        return [to_jsonable(v.real), to_jsonable(v.imag)]
    if isinstance(v, dict):
        return {str(k): to_jsonable(w) for k, w in v.items()}
    if isinstance(v, (list, tuple, set)):
        return [to_jsonable(w) for w in v]
    return v

