"""Load a 1-D signal (CSV: first column x, value column chosen) or a 2-D field (.npz with x, y, z)."""
from __future__ import annotations

import logging
import warnings
from pathlib import Path

import numpy as np

from odnn_sep import limits
from odnn_sep.errors import FormatError, InputError, check_finite
from odnn_sep.io_paths import check_input_path
from odnn_sep.io_read import (
    check_header,
    column_index,
    count_lines,
    leading_comments,
    load_npz_arrays,
    looks_binary,
    pick_column,
    row_index_column,
    separator_of,
    table_rows,
    text_encoding,
)

log = logging.getLogger(__name__)
# Comment lines ('# ...') looked for above a CSV's header.
MAX_COMMENT_LINES = 50


def _load_field(p: Path, value_name: list | None):
    """The NPZ branch of :func:`load_signal`: grid axes x, y and the field z (ny, nx), flattened."""
    d = load_npz_arrays(p, max_points=True)     # boolean arrays refused there
    x, y, z = _grid_axes(d["x"], d["y"], d["z"], p)
    if x.ndim != 1 or y.ndim != 1 or z.shape != (y.size, x.size):
        raise InputError(f"z has shape {z.shape} but len(y) x len(x) is {(y.size, x.size)}; they must match "
                         "(x and y 1-D grid axes)")
    limits.check("points", z.size, f"the field in {str(p)!r} has {z.shape[0]} x {z.shape[1]} points; its size")
    check_finite("x", x)
    check_finite("y", y)
    check_finite("z", z)
    X, Y = np.meshgrid(x, y)
    if value_name is not None:
        value_name.append("z")
    return np.c_[X.ravel(), Y.ravel()], z.ravel(), ("x", "y"), z.shape


def _grid_axes(x, y, z, p):
    """``(x, y, z)`` with 1-D axes: ``x``, ``y`` as ``np.meshgrid`` writes them (both 2-D, z's shape) are
    reduced to their axes (``indexing="ij"``: z transposed to (ny, nx)); anything else is left as given."""
    if not (x.ndim == y.ndim == 2 and x.shape == y.shape == z.shape):
        return x, y, z
    if (x == x[:1]).all() and (y == y[:, :1]).all():        # np.meshgrid(x, y): rows repeat x
        return x[0], y[:, 0], z
    if (x == x[:, :1]).all() and (y == y[:1]).all():        # indexing="ij": columns repeat x
        return x[:, 0], y[0], z.T
    raise InputError(f"x and y in {str(p)!r} are 2-D but not a grid (as np.meshgrid writes it); give the 1-D "
                     "grid axes x (nx,), y (ny,) and z (ny, nx)")


def load_signal(path, column: str | int | None = None, *, value_name: list | None = None,
                x_column: str | int | None = None):
    """Return (coords, values, coord_names, grid_shape).

    CSV: header row, first column is x, the value column is ``column`` (name, or index counted from
    0 where 0 is x; default 1). With ``x_column`` (name or index) that column is x instead, and
    ``column`` defaults to the first other column. NPZ: arrays ``x`` (nx,), ``y`` (ny,), ``z`` (ny, nx); coords are the
    (ny*nx, 2) points. Sizes are limited (:mod:`odnn_sep.limits`, ``points``). If ``value_name``
    is a list, the value column's name is appended to it (for labels).

    Parameters
    ----------
    path : str or path-like
        A CSV or .npz file.
    column : str or int, optional
        Value column of a CSV: header name or index (0 is x); default 1.
    value_name : list, optional
        Receives the value column's name.
    x_column : str or int, optional
        Coordinate column of a CSV (a lab table: velocity and force among other columns); default
        the first.

    Returns
    -------
    coords : ndarray
        (n,) x values of a CSV, or (ny*nx, 2) points of a field.
    values : (n,) ndarray
    coord_names : tuple of str
        ``(x_name,)`` or ``("x", "y")``.
    grid_shape : tuple of int or None
        ``(ny, nx)`` of a field, None for a CSV.

    Raises
    ------
    odnn_sep.errors.FormatError
        When the file is not a readable CSV or .npz.
    odnn_sep.errors.InputError
        For missing or non-finite values, or sizes above the limits.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = os.path.join(d, "signal.csv")
    ...     with open(path, "w") as fh:
    ...         _ = fh.write(chr(10).join(["t,v", "0,1", "1,3", "2,5"]))
    ...     coords, values, names, shape = load_signal(path)
    >>> coords.tolist(), values.tolist(), names, shape
    ([0.0, 1.0, 2.0], [1.0, 3.0, 5.0], ('t',), None)
    """
    p = check_input_path(path)
    if p.suffix.lower() == ".npz":
        if x_column is not None:
            raise InputError(f"--x-column is for a CSV; {str(p)!r} is a field whose coordinates are its arrays x "
                             "and y: leave --x-column out")
        if column is not None:     # it was ignored: the field's values are always its array z
            raise InputError(f"--column is for the value column of a CSV; {str(p)!r} is a field whose values are "
                             "its array z: leave --column out")
        return _load_field(p, value_name)
    if p.suffix.lower() not in (".csv", ".txt", ".tsv", ""):
        raise FormatError(f"{str(p)!r} has extension {p.suffix!r}; give a .csv (header; first column x) or an "
                          ".npz with arrays x, y, z")
    if looks_binary(p):
        raise FormatError(f"{str(p)!r} is not a text CSV (it holds binary data); give a .csv with a header row "
                          "or an .npz field")
    rows = count_lines(p)
    limits.check("points", max(rows - 1, 0), f"the row count of {str(p)!r}",
                 hint="decimate the data")
    try:
        # 'utf-8-sig': a byte-order mark (a spreadsheet's "CSV UTF-8") is not part of the first column's name;
        # a UTF-16/32 file ("Unicode text") is decoded by its mark
        encoding = text_encoding(p)
        with open(p, newline="", encoding=encoding) as fh:
            top = [fh.readline().strip().split(",") for _ in range(MAX_COMMENT_LINES + 2)]
        skip = leading_comments([r for r in top if r != [""]])   # '# sensor: ...' lines above the header
        header = [h.strip() for h in top[skip]]
        first = top[skip + 1] if skip + 1 < len(top) else []
        if separator_of(header, first) is not None:
            # ';' with decimal commas (a spreadsheet in such a locale), tabs or spaces: read cell by cell
            header, data = _other_separator(p)
        else:
            check_header(header, path=p)
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # empty or ragged input: reported below in one line
                data = np.genfromtxt(p, delimiter=",", skip_header=skip + 1, dtype=float, invalid_raise=True,
                                     **({} if encoding == "utf-8-sig" else {"encoding": encoding}))
    except FormatError:
        raise
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise FormatError(f"could not read {str(p)!r} as CSV: {str(exc).strip().splitlines()[-1]}") from None
    data = np.atleast_2d(data)
    first_col = 0      # the file's column of x (1 behind a row counter)
    if data.ndim == 2 and len(header) == data.shape[1] and row_index_column(header, [data[:, 0], data[:, 1]]):
        # a table library's row counter (pandas' index) before the coordinate: left out
        log.warning("the first column (%r) of %s counts the rows (a table's index): left out; x is column %r",
                    header[0], p.name, header[1])
        data, header, first_col = data[:, 1:], header[1:], 1
    if data.size == 0 or data.shape[1] < 2 or data.shape[0] < 2:
        raise FormatError(f"{str(p)!r} needs a header row, at least two data rows and at least two columns "
                          "(x and a value)")
    if column is None and [h.lower() for h in header[:4]] == ["x", "y", "z", "physics"]:
        # the parts CSV (-o) of a 2-D field: its default value column is the coordinate y
        raise InputError(f"{str(p)!r} is the parts CSV of a 2-D field (columns x, y, z, physics, ...): its values are "
                         "column z, on a grid of x and y; fit the field's .npz again, or give --column z (or "
                         "--column residual) to read it as a 1-D record along x")
    names = header if len(header) == data.shape[1] else [f"col{k}" for k in range(data.shape[1])]
    if x_column is None:
        ix, j = 0, pick_column(names, column, path=p)
    else:
        ix, j = _x_and_value_columns(names, x_column, column, p)
    x, v = data[:, ix], data[:, j]
    label = header[j] if j < len(header) else str(j)
    if np.isnan(x).any() and ix == 0:
        # date-times (a logger's time stamps) as seconds since the first, as mismatch reads them; a
        # cell that is neither is named by its line
        x = _time_stamps(p, header[0] if header else "x", x.size, first_col)
    for name, a in ((f"column {label!r}", v), ("x (first column)", x)):
        if np.isnan(a).any():
            k = int(np.argmax(np.isnan(a)))
            raise InputError(f"{name} of {str(p)!r} has {int(np.isnan(a).sum())} missing or non-numeric value(s) "
                             f"(first on data row {k + 1}); fix or remove those rows")
        check_finite(name, a)
        limits.check_magnitude(name, a)
    name = header[ix] if ix < len(header) and header[ix].isidentifier() else "x"
    if value_name is not None:
        value_name.append(label)
    return x, v, (name,), None


def _x_and_value_columns(names, x_column, column, p) -> tuple[int, int]:
    """Indices of the coordinate column ``x_column`` and the value column (``column``, or the first other)."""
    ix = column_index(names, x_column, "--x-column", path=p)
    j = (1 if ix == 0 else 0) if column is None else column_index(names, column, "--column", path=p)
    if j == ix:
        where = f"{str(p)!r} has columns {', '.join(f'{k}={n!r}' for k, n in enumerate(names))}"
        raise InputError(f"--column and --x-column both name column {j} ({names[j]!r}); the values must be another "
                         f"column: {where}")
    return ix, j


def copied_rows(path, x: np.ndarray, v: np.ndarray) -> str | None:
    """Rows of a 1-D record that repeat others exactly (same x and value): an error for a block of them,
    a warning text when they are spread out, None when there are none.

    A block of copied rows (a record pasted twice) is an InputError: copies are not new readings, and
    fitting them narrowed the intervals (by 1.41 for a record given twice). When every repeated x
    carries the very same value but the repeats are spread out (copies sorted in, or a quantised
    sensor read twice per time stamp), the returned warning says so. Repeated readings that differ
    are real readings: None.

    Parameters
    ----------
    path : str or path-like
        The file, for the messages.
    x, v : (n,) ndarray
        Coordinates and values in file order.

    Returns
    -------
    str or None

    Raises
    ------
    odnn_sep.errors.InputError
        For a block of copied rows.

    Examples
    --------
    >>> x = np.arange(4.0)
    >>> copied_rows("a.csv", np.r_[x, 1.0], np.r_[x, 5.0]) is None       # x = 1 read twice, differently
    True
    >>> print(copied_rows("a.csv", np.repeat(x, 2), np.repeat(x, 2))[:58])
    'a.csv' repeats 4 row(s) exactly (the same x and value; fi
    >>> copied_rows("a.csv", np.r_[x, x], np.r_[x, x])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: 'a.csv' repeats 4 row(s) exactly (the same x and value; first at data row 5), as one block: copies are not new readings and would narrow the intervals as if they were; remove the copied rows
    """
    order = np.lexsort((v, x))
    xs, vs = x[order], v[order]
    same_x = xs[1:] == xs[:-1]
    if not same_x.any() or not (vs[1:][same_x] == vs[:-1][same_x]).all():
        return None
    rows = np.sort(order[1:][same_x])
    what = (f"{str(path)!r} repeats {rows.size} row(s) exactly (the same x and value; first at data row "
            f"{int(rows[0]) + 1})")
    if rows.size > 1 and rows[-1] - rows[0] + 1 == rows.size:
        raise InputError(f"{what}, as one block: copies are not new readings and would narrow the intervals as if "
                         "they were; remove the copied rows")
    return (f"{what}, and no repeated x has two different values: if they are copies, the intervals are too "
            "narrow; remove them")


def _time_stamps(p, name, n, col):
    """Column ``col`` (x) of a CSV whose cells are not all numbers, read by :func:`odnn_sep.io_read.time_values`."""
    from odnn_sep.io_read import time_values

    rows, _ = table_rows(p)
    rows = rows[leading_comments(rows):]
    cells = [r[col] if len(r) > col else "" for r in rows[1:]]
    if len(cells) != n:      # not the rows the table was read as: leave the reading's own message
        return np.full(n, np.nan)
    x, origin = time_values(cells, path=p, name=name)
    log.warning("column %r of %s holds date-times: x is in seconds since %s", name, p.name, origin)
    return x


def _other_separator(p):
    """(header, float array with NaN for a cell that is not a number) of a table that is not
    comma-separated (``io_read.table_rows``); how it was read goes to the log."""
    rows, note = table_rows(p)
    rows = rows[leading_comments(rows):]
    check_header(rows[0], path=p)
    width = len(rows[0])
    if any(len(r) != width for r in rows[1:]):
        raise FormatError(f"could not read {str(p)!r} as a table: its rows do not all have {width} cells")
    log.warning("%s %s", p.name, note)

    def num(c):
        try:
            return float(c)
        except ValueError:
            return np.nan
    return [h.strip() for h in rows[0]], np.array([[num(c) for c in r] for r in rows[1:]], dtype=float)


def write_components(out, x, y, res) -> None:
    """CSV with coordinates, data, physics, disturbance and residual columns (atomic).

    Parameters
    ----------
    out : str or path-like
        Output CSV path (its folder must exist).
    x : ndarray
        (n,) coordinates or (n, d) points.
    y : (n,) ndarray
        The data.
    res : odnn_sep.core.result.Result
        The fit, with ``physics``, ``disturbance`` and ``residual``.

    Examples
    --------
    >>> import os, tempfile
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 5); y = 2 * x + x**2
    >>> res = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, y).result_
    >>> with tempfile.TemporaryDirectory() as d:
    ...     out = os.path.join(d, "parts.csv")
    ...     write_components(out, x, y, res)
    ...     with open(out) as fh:
    ...         header = fh.readline().strip()
    >>> header
    'x,y,physics,disturbance,residual'
    """
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output

    check_output_path(out)
    X = x[:, None] if x.ndim == 1 else x
    cols = [X, y[:, None], res.physics[:, None], res.disturbance[:, None], res.residual[:, None]]
    # a field's coordinates are x and y, its values z (a column "y" of values read as the coordinate)
    head = {1: "x,y", 2: "x,y,z"}.get(X.shape[1], ",".join(f"x{i}" for i in range(X.shape[1])) + ",y")
    # 17 significant digits: the file reads back to the same floats (10 digits wrote every x of a record
    # in epoch seconds sampled at 0.01 s as 1700000000, so the written parts could not be fitted again)
    with atomic_output(out, suffix=Path(out).suffix or ".csv") as tmp:
        np.savetxt(tmp, np.hstack(cols), delimiter=",", header=head + ",physics,disturbance,residual",
                   comments="", fmt="%.17g")
