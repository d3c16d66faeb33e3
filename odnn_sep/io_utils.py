"""File helpers shared by front-ends: atomic writes and input/output path checks."""
from __future__ import annotations

import contextlib
import os
import tempfile
from pathlib import Path

from odnn_sep.errors import FormatError, InputError


def check_input_path(path, *, what: str = "input file") -> Path:
    p = Path(path)
    if not p.exists():
        raise InputError(f"{what} {str(p)!r} does not exist; check the path")
    if p.is_dir():
        raise InputError(f"{what} {str(p)!r} is a directory; pass a file")
    if p.stat().st_size == 0:
        raise FormatError(f"{what} {str(p)!r} is empty (0 bytes)")
    return p


def check_output_path(out, *inputs) -> Path:
    """Refuse an output equal to an input and an output directory that is missing or read-only."""
    o = Path(out)
    for i in inputs:
        if i is not None and Path(i).exists() and o.exists() and os.path.samefile(o, i):
            raise InputError(f"output path {str(o)!r} is the input file; choose a different output path")
        if i is not None and o.resolve() == Path(i).resolve():
            raise InputError(f"output path {str(o)!r} is the input file; choose a different output path")
    parent = o.resolve().parent
    if not parent.is_dir():
        raise InputError(f"output directory {str(parent)!r} does not exist; create it first")
    if not os.access(parent, os.W_OK):
        raise InputError(f"output directory {str(parent)!r} is not writable; choose another output path")
    return o


@contextlib.contextmanager
def atomic_output(out, suffix: str | None = None):
    """Yield a temporary path next to ``out``; rename it onto ``out`` only if the block succeeds.

    A failure leaves no partial file behind.
    """
    o = Path(out)
    fd, tmp = tempfile.mkstemp(prefix=f".{o.name}.", suffix=suffix if suffix is not None else o.suffix,
                               dir=str(o.resolve().parent))
    os.close(fd)
    try:
        yield Path(tmp)
        # mkstemp creates 0600; give the result the permissions a normally created file would have
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, o)
    except BaseException:
        with contextlib.suppress(FileNotFoundError):
            os.unlink(tmp)
        raise


def write_json(out, obj) -> None:
    """Write ``obj`` as JSON atomically (numpy scalars/arrays and paths converted)."""
    import json

    check_output_path(out)
    with atomic_output(out, suffix=".json") as tmp, open(tmp, "w") as fh:
        json.dump(to_jsonable(obj), fh, indent=2, allow_nan=True)
        fh.write("\n")


def ensure_readable(path, reader, *, what: str):
    """Call ``reader(path)`` and turn library-specific read failures into one FormatError line."""
    try:
        return reader(path)
    except (OSError, RuntimeError, ValueError) as exc:
        raise FormatError(f"could not read {what} {str(path)!r}: {str(exc).splitlines()[0]}") from None


def to_jsonable(v):
    """Recursively convert numpy scalars/arrays, tuples and paths to plain JSON types."""
    import numpy as np

    if isinstance(v, Path):
        return str(v)
    if isinstance(v, np.ndarray):
        return v.tolist()
    if isinstance(v, np.generic):
        return v.item()
    if isinstance(v, dict):
        return {k: to_jsonable(w) for k, w in v.items()}
    if isinstance(v, (list, tuple)):
        return [to_jsonable(w) for w in v]
    return v
