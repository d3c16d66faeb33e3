"""Path checks shared by front-ends: what a run may read and where it may write.

* an input must exist, be readable and not be a folder;
* an output is never an input of the run, nor another output of the same run;
* only regular files (or new paths) are written: devices, pipes and folders are refused;
* a name longer than the file system allows is refused before any work is done.

The writes themselves (atomic, all or nothing) are in :mod:`odnn_sep.io_utils`.
"""
from __future__ import annotations

import contextlib
import os
import stat
from pathlib import Path

from odnn_sep.errors import FormatError, InputError


def _name_max(folder: Path) -> int:
    try:
        return int(os.pathconf(str(folder), "PC_NAME_MAX"))
    except (OSError, ValueError):
        return 255


def check_name_length(p: Path, what: str) -> None:
    """Refuse a file name the file system cannot hold, before any work is done.

    Parameters
    ----------
    p : pathlib.Path
        The file path.
    what : str
        What the file is, for the message.

    Raises
    ------
    odnn_sep.errors.InputError
        When the name is longer than the folder's file system allows (255 bytes if unknown).

    Examples
    --------
    >>> check_name_length(Path("out") / ("x" * 300 + ".wav"), "output")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: output name is too long (304 bytes; the file system allows 255); choose a shorter name
    """
    parent = p.parent if str(p.parent) else Path(".")
    limit = _name_max(parent) if parent.is_dir() else 255
    n = len(os.fsencode(p.name))
    if n > limit:
        raise InputError(f"{what} name is too long ({n} bytes; the file system allows {limit}); "
                         "choose a shorter name")


def check_input_path(path, *, what: str = "input file") -> Path:
    """Return ``path`` as a Path if it names a non-empty regular file, else raise one clear error.

    Parameters
    ----------
    path : str or path-like
        The file to read.
    what : str, optional
        What the file is, for the messages.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    odnn_sep.errors.InputError
        For a missing, unopenable, directory or non-regular path, or a name too long.
    odnn_sep.errors.FormatError
        For an empty file.

    Examples
    --------
    >>> check_input_path("no/such/file.wav")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: input file 'no/such/file.wav' does not exist; check the path
    """
    p = Path(path)
    check_name_length(p, what)
    try:
        st = p.stat()
    except FileNotFoundError:
        raise InputError(f"{what} {str(p)!r} does not exist; check the path") from None
    except OSError as exc:
        raise InputError(f"{what} {str(p)!r} cannot be opened: {exc.strerror}") from None
    if stat.S_ISDIR(st.st_mode):
        raise InputError(f"{what} {str(p)!r} is a directory; pass a file")
    if not stat.S_ISREG(st.st_mode):
        raise InputError(f"{what} {str(p)!r} is not a regular file (a device or pipe); pass a file")
    if st.st_size == 0:
        raise FormatError(f"{what} {str(p)!r} is empty (0 bytes)")
    return p


def _same_file(a: Path, b: Path) -> bool:
    """True if ``a`` and ``b`` name the same file (symlinks, hard links and ``..`` resolved)."""
    with contextlib.suppress(OSError):
        if a.exists() and b.exists() and os.path.samefile(a, b):
            return True
    with contextlib.suppress(OSError, RuntimeError):
        return a.resolve() == b.resolve()
    return False


def check_output_target(out, what: str = "output") -> Path:
    """Refuse an output that is not a regular file or a new path, or whose folder cannot take it.

    Parameters
    ----------
    out : str or path-like
        The file to write.
    what : str, optional
        What the file is, for the messages.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    odnn_sep.errors.InputError
        For a folder, broken link, device or pipe, a missing or read-only folder, or a name too long.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     check_output_target(d)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: output path '...' is a folder; give a file name
    """
    o = Path(out)
    check_name_length(o, f"{what} file")
    if os.path.lexists(o):
        try:
            st = o.stat()
        except OSError:
            raise InputError(f"{what} path {str(o)!r} is a broken link; remove it or choose another path") from None
        if stat.S_ISDIR(st.st_mode):
            raise InputError(f"{what} path {str(o)!r} is a folder; give a file name")
        if not stat.S_ISREG(st.st_mode):
            raise InputError(f"{what} path {str(o)!r} is not a regular file (a device or pipe); odnn-sep writes "
                             "only to regular files or new paths")
    parent = o.resolve().parent
    if not parent.is_dir():
        raise InputError(f"output directory {str(parent)!r} does not exist; create it first")
    if not os.access(parent, os.W_OK):
        raise InputError(f"output directory {str(parent)!r} is not writable; choose another output path")
    return o


def check_output_path(out, *inputs) -> Path:
    """Refuse an output equal to an input, a non-regular output, or a missing/read-only folder.

    Parameters
    ----------
    out : str or path-like
        The file to write.
    *inputs : str or path-like
        The files the run reads.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    odnn_sep.errors.InputError
        When ``out`` is one of ``inputs`` (links resolved) or fails :func:`check_output_target`.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     src = os.path.join(d, "in.csv")
    ...     with open(src, "w") as fh:
    ...         _ = fh.write("x,y")
    ...     check_output_path(os.path.join(d, "out.csv"), src).name
    'out.csv'
    >>> with tempfile.TemporaryDirectory() as d:
    ...     src = os.path.join(d, "in.csv")
    ...     check_output_path(src, src)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: output path '...in.csv' is the input file; choose a different output path
    """
    o = Path(out)
    for i in inputs:
        if i is not None and _same_file(o, Path(i)):
            raise InputError(f"output path {str(o)!r} is the input file; choose a different output path")
    return check_output_target(o)


def check_run_paths(inputs: dict, outputs: dict) -> None:
    """Check every output of a run against every input and against the other outputs.

    Parameters
    ----------
    inputs, outputs : dict
        ``{option name: path}`` (paths may be None: option not given).

    Examples
    --------
    >>> check_run_paths({"the input": "rec.wav"}, {"--output": "clean.wav", "--report": "clean.wav"})
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --report 'clean.wav' is the same file as --output; choose different paths
    """
    ins = {k: Path(v) for k, v in inputs.items() if v is not None}
    outs = {k: Path(v) for k, v in outputs.items() if v is not None}
    seen: dict[str, Path] = {}
    for flag, o in outs.items():
        for iflag, i in ins.items():
            if _same_file(o, i):
                what = "the input file" if iflag == "the input" else f"the {iflag} file"
                name = "output" if flag == "--output" else flag
                raise InputError(f"{name} path {str(o)!r} is {what}; choose a different output path")
        for oflag, other in seen.items():
            if _same_file(o, other):
                raise InputError(f"{flag} {str(o)!r} is the same file as {oflag}; choose different paths")
        check_output_target(o, flag)
        seen[flag] = o
