"""Reading several series for a joint fit: a CSV with a series column, or one file per series."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError


def read_series_csv(path, series, column=None):
    """``{series name: (t, y)}`` from a CSV with a header, time first, and a column naming the series.

    Rows are grouped by the series column's value (in order of first appearance); within a series
    they are sorted by time.

    Parameters
    ----------
    path : str or Path
        CSV file.
    series : str
        Header of the column that names the series.
    column : str, optional
        Value column (default: the first column after time that is not the series column).

    Returns
    -------
    dict

    Raises
    ------
    InputError
        Unknown series or value column.
    FormatError
        Non-numeric time or value.

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "mugs.csv")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("t,mug,T\\n0,A,90\\n0,B,80\\n1,A,85\\n1,B,76\\n")
    >>> {k: (t.tolist(), y.tolist()) for k, (t, y) in read_series_csv(path, "mug").items()}
    {'A': ([0.0, 1.0], [90.0, 85.0]), 'B': ([0.0, 1.0], [80.0, 76.0])}
    """
    from odnn_sep.io_read import leading_comments, table_rows
    from odnn_sep.mismatch.model import suggest_name
    rows, _ = table_rows(path)               # commas, or the ';' / tabs / spaces its header shows
    rows = rows[leading_comments(rows):]     # '# sensor: ...' lines above the header
    if len(rows) < 2:
        raise FormatError(f"CSV {str(path)!r} has no data rows below the header")
    header = [h.strip() for h in rows[0]]
    from odnn_sep.io_read import check_header, row_index_column
    check_header(header, path=path)
    if series != header[0] and row_index_column(header, [[r[k] if k < len(r) else "" for r in rows[1:]]
                                                         for k in range(2)]):
        rows = [r[1:] for r in rows]     # a table library's row counter (see row_index_column)
        header = header[1:]
    if series not in header:
        raise InputError(f"--series {series!r} is not a column of {str(path)!r}; {suggest_name(series, header)}"
                         f"columns: {', '.join(header)}")
    js = header.index(series)
    jv = _value_column(header, js, column, path)
    from odnn_sep.io_read import time_values

    # seconds, or date-times as seconds since the file's first row (one origin shared by every series)
    times, _ = time_values([r[0] if r else "" for r in rows[1:]], path=str(path), name=header[0])
    groups: dict = {}
    for k, r in enumerate(rows[1:], start=2):
        if js < len(r) and not r[js].strip():
            # an unnamed row would become a series of its own, named ''
            raise FormatError(f"CSV {str(path)!r} line {k}: the --series column {series!r} is empty; name the "
                              f"series of that row or remove it")
        try:
            groups.setdefault(r[js].strip(), []).append((times[k - 2], float(r[jv])))
        except (ValueError, IndexError):
            raise FormatError(f"CSV {str(path)!r} line {k}: time and {header[jv]!r} must be numbers; "
                              f"got {r}") from None
    out = {}
    for name, pts in groups.items():
        a = np.array(sorted(pts))
        out[name] = (a[:, 0], a[:, 1])
    return out


def _value_column(header, js, column, path):
    """The value column of a series CSV: the rule of every reader (a name or an index, never the time
    column, :func:`odnn_sep.io_read.pick_column`), and never the series column."""
    from odnn_sep.io_read import pick_column
    if js == 0:
        raise InputError(f"--series {header[0]!r} is the time column of {str(path)!r}; give the column that names "
                         f"each series (columns: {', '.join(header)})")
    if column is None:
        rest = [j for j in range(1, len(header)) if j != js]
        if not rest:
            raise InputError(f"CSV {str(path)!r} has no value column besides time and {header[js]!r}")
        return rest[0]
    jv = pick_column(header, column, path=path)
    if jv == js:
        raise InputError(f"--column {column!r} is the --series column {header[js]!r}; give the value column "
                         f"(columns: {', '.join(header)})")
    return jv


def read_series_files(paths, *, load, column=None, start=None, duration=None):
    """``{file stem: (t, y)}``: one series per data file, read by ``load`` (the mismatch loader).

    Examples
    --------
    >>> import os, tempfile
    >>> from odnn_sep.mismatch.io import load_data
    >>> d = tempfile.mkdtemp(); paths = []
    >>> for name in ("a", "b"):
    ...     paths.append(os.path.join(d, name + ".csv"))
    ...     with open(paths[-1], "w") as fh:
    ...         _ = fh.write("t,T\\n0,90\\n1,85\\n")
    >>> list(read_series_files(paths, load=load_data))
    ['a', 'b']
    """
    out = {}
    for p in paths:
        name = Path(p).stem
        if name in out:
            raise InputError(f"two data files share the name {name!r}; a series is named after its file")
        t, y, info = load(p, column=column, start=start, duration=duration)
        if np.ndim(t) != 1:
            raise InputError(f"{str(p)!r} is a 2D field; joint series are time series")
        out[name] = (t, y)
    return out
