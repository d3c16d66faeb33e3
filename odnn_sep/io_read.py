"""Reading helpers shared by the front-ends: one --column rule, safe .npz and CSV checks.

Each refuses bad input with one line before any large allocation: a small file that declares a huge
array, a pickled object, a damaged archive, or binary data under a .csv name.
"""
from __future__ import annotations

from pathlib import Path

from odnn_sep.errors import FormatError, InputError


def check_header(header, *, path) -> None:
    """Refuse a CSV whose first row holds only numbers.

    A first row of numbers is data, not a header: reading it as one would drop that row and name
    the columns by its values. (A file with ``;``, tabs or spaces between its cells is split at
    them first: :func:`table_rows`.)

    Parameters
    ----------
    header : list of str
        The first row's cells.
    path : str or Path
        The file (for the message).

    Raises
    ------
    FormatError
        When every cell of the first row is a number.

    Examples
    --------
    >>> check_header(["t", "T"], path="a.csv")
    >>> check_header(["0.0", "90.1"], path="a.csv")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.FormatError: 'a.csv' has no header row (its first row, ['0.0', '90.1'], holds only numbers); add a first line naming the columns, e.g. t,y
    """
    cells = [str(c).strip() for c in header]
    if not cells or not any(cells):
        return
    for c in cells:
        try:
            float(c)
        except ValueError:
            return
    raise FormatError(f"{str(path)!r} has no header row (its first row, {cells[:4]}, holds only numbers); add a "
                      f"first line naming the columns, e.g. t,y")


def separator_of(header, first_row=None):
    """The separator of a CSV that is not comma-separated, read off its header split at commas.

    Parameters
    ----------
    header : list of str
        The first row's cells, split at commas.
    first_row : list of str, optional
        The first data row's cells, split at commas.

    Returns
    -------
    (str, bool) or None
        The separator in words (``"';'"``, ``"tabs"`` or ``"spaces"``) and whether the data use decimal commas;
        None for a comma-separated header (or a single column without ``;`` or tabs).

    Examples
    --------
    >>> separator_of(["t", "x"]) is None, separator_of(["t;x"], ["0.5;1.5"]), separator_of(["t" + chr(9) + "x"])
    (True, ("';'", False), ('tabs', False))
    >>> separator_of(["t;x"], ["0", "000000;1", "001257"])
    ("';'", True)
    >>> separator_of(["t T"], ["0.0 80.0"])
    ('spaces', False)
    """
    cells = [str(c) for c in header]
    if len(cells) != 1:
        return None
    cell = cells[0].strip().lstrip("\ufeff")
    for sep, name in ((";", "';'"), ("\t", "tabs")):
        if sep in cell:
            raw = ",".join(str(c) for c in first_row or []).strip()
            return name, any("," in v and _is_number(v.strip().replace(",", ".")) for v in raw.split(sep))
    row = [str(c).strip() for c in first_row or []]
    if len(cell.split()) >= 2 and len(row) == 1 and len(row[0].split()) >= 2 and all(map(_is_number, row[0].split())):
        return "spaces", False     # 't T' over '0.0 80.0': a whitespace-separated table
    return None


# byte-order marks of the Unicode encodings a spreadsheet writes: Excel's "Unicode text" export is
# UTF-16 with a mark (and tabs). UTF-32's marks are checked first: UTF-32-LE's starts with UTF-16-LE's.
_BOMS = ((b"\xff\xfe\x00\x00", "utf-32"), (b"\x00\x00\xfe\xff", "utf-32"),
         (b"\xff\xfe", "utf-16"), (b"\xfe\xff", "utf-16"))


def text_encoding(path) -> str:
    """The codec to read a text table with: ``utf-16``/``utf-32`` behind their byte-order mark, else ``utf-8-sig``.

    The returned codecs consume the mark, so it never reaches the first header cell.

    Parameters
    ----------
    path : str or path-like

    Returns
    -------
    str

    Examples
    --------
    >>> import os, tempfile
    >>> d = tempfile.mkdtemp()
    >>> with open(os.path.join(d, "u16.csv"), "w", encoding="utf-16") as fh:
    ...     _ = fh.write("t\tT")
    >>> with open(os.path.join(d, "u8.csv"), "w") as fh:
    ...     _ = fh.write("t,T")
    >>> text_encoding(os.path.join(d, "u16.csv")), text_encoding(os.path.join(d, "u8.csv"))
    ('utf-16', 'utf-8-sig')
    """
    with open(path, "rb") as fh:
        head = fh.read(4)
    return next((codec for bom, codec in _BOMS if head.startswith(bom)), "utf-8-sig")


def table_rows(path) -> tuple[list[list[str]], str | None]:
    """The non-empty rows of a text table, split at its separator, with decimal commas made points.

    Commas, or what the header shows (:func:`separator_of`): ``;`` (a spreadsheet saved in a locale
    with decimal commas, ``t;T`` over ``0,5;80,1``), tabs (an instrument's export) or spaces. Cells
    that read as numbers once their one comma is a point get the point; other cells are kept.

    Parameters
    ----------
    path : str or Path
        A text file.

    Returns
    -------
    rows : list of list of str
        The rows with at least one non-blank cell, comment lines included.
    note : str or None
        How the file was read when not comma-separated (for the report), else None.

    Examples
    --------
    >>> import os, tempfile
    >>> p = os.path.join(tempfile.mkdtemp(), "excel.csv")
    >>> with open(p, "w") as fh:
    ...     _ = fh.write("t;T\\n0;80,5\\n1,5;79\\n")
    >>> table_rows(p)
    ([['t', 'T'], ['0', '80.5'], ['1.5', '79']], "read as ';'-separated with decimal commas")
    """
    import csv
    import io

    # 'utf-8-sig': a spreadsheet's "CSV UTF-8" (and pandas' encoding="utf-8-sig") starts with a byte-order
    # mark, which would stay in the first header cell: an unnamed index column was then not seen as one;
    # a UTF-16/32 file ("Unicode text") is decoded by its mark
    with open(path, newline="", encoding=text_encoding(path)) as fh:
        text = fh.read()
    rows = [r for r in csv.reader(io.StringIO(text)) if r and any(c.strip() for c in r)]
    k = leading_comments(rows)
    if len(rows) < k + 2:
        return rows, None
    sep = separator_of(rows[k], rows[k + 1])
    if sep is None:
        return rows, None
    name, decimal = sep
    if name == "spaces":
        rows = [ln.split() for ln in text.splitlines() if ln.strip()]
    else:
        rows = [r for r in csv.reader(io.StringIO(text), delimiter=";" if name == "';'" else "\t")
                if r and any(c.strip() for c in r)]
    if decimal:
        rows = [[c.replace(",", ".") if c.count(",") == 1 and _is_number(c.strip().replace(",", ".")) else c
                 for c in r] for r in rows]
    what = {"';'": "';'-separated", "tabs": "tab-separated", "spaces": "space-separated"}[name]
    return rows, f"read as {what}" + (" with decimal commas" if decimal else "")


def leading_comments(rows) -> int:
    """How many rows at the top of a CSV are comments (first cell starting with ``#``) before its header.

    Loggers and instruments write lines such as ``# sensor: PT100`` above the header; they were read
    as the header ("needs at least two columns, found ['# sensor: PT100']"). A ``#`` row directly
    above rows of numbers with as many cells is the header itself (``#,t,T``, a row-number column).

    Parameters
    ----------
    rows : list of list of str
        The file's first rows, split at commas.

    Returns
    -------
    int

    Examples
    --------
    >>> leading_comments([["# export"], ["# sensor: PT100", " range 0-100"], ["t", "T"], ["0", "80"]])
    2
    >>> leading_comments([["#", "t", "T"], ["0", "0.0", "80"]])
    0
    """
    k = 0
    while k + 1 < len(rows) and rows[k] and str(rows[k][0]).lstrip().lstrip("\ufeff").startswith("#"):
        nxt = rows[k + 1]
        if len(rows[k]) == len(nxt) and all(_is_number(c) for c in nxt if str(c).strip()):
            break
        k += 1
    return k


def _is_number(text) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


# First-column names of a row counter written by a table library (pandas writes its index unnamed).
ROW_INDEX_NAMES = frozenset({"", "index", "idx", "unnamed: 0", "#", "row", "rownum", "no", "n"})


def row_index_column(header, columns) -> bool:
    """Whether column 0 of a CSV is a row counter to leave out rather than the coordinate.

    ``pandas.DataFrame.to_csv`` writes the row index first, unnamed: the time column then sat second
    and was read as the values (a cooling record "up to 300 degF", the time column's last value).
    Column 0 is a row counter when its name is one of ``ROW_INDEX_NAMES``, its values count
    0, 1, 2, ... (or from 1), and at least two columns remain; unless it is unnamed (pandas), the next
    column must also rise strictly (it can be the time): a record whose time is the sample number,
    with values that do not rise, keeps it.

    Parameters
    ----------
    header : list of str
        Column names.
    columns : list of sequences
        The first three columns' cells (strings or numbers), column by column.

    Returns
    -------
    bool

    Examples
    --------
    >>> row_index_column(["", "t", "T"], [["0", "1", "2"], ["0.0", "0.5", "1.0"], ["90", "85", "81"]])
    True
    >>> row_index_column(["index", "T", "ref"], [["0", "1", "2"], ["90", "85", "81"], ["1", "1", "1"]])
    False
    >>> row_index_column(["t", "T", "ref"], [["0", "1", "2"], ["0.0", "0.5", "1.0"], ["1", "1", "1"]])
    False
    >>> row_index_column(["", "t", "mug", "T"], [["0", "1", "2"], ["0", "0", "1"]])   # long format, pandas
    True
    """
    if len(header) < 3 or str(header[0]).strip().lower() not in ROW_INDEX_NAMES or len(columns) < 2:
        return False
    try:
        idx = [float(c) for c in columns[0]]
        nxt = [float(c) for c in columns[1]]
    except (TypeError, ValueError):
        return False
    if len(idx) < 2 or idx[0] not in (0.0, 1.0):
        return False
    counts = all(v == idx[0] + k for k, v in enumerate(idx))
    unnamed = str(header[0]).strip().lower() in ("", "unnamed: 0")
    return counts and (unnamed or all(b > a for a, b in zip(nxt, nxt[1:], strict=False)))


def pick_column(header, column, *, path) -> int:
    """Index of the value column of a CSV: the same rule for every command.

    ``column`` is a header name or an index counted from 0, where column 0 is the coordinate
    (time or x) and cannot be the value; the default is column 1.

    Parameters
    ----------
    header : list of str
        The CSV's column names.
    column : str or int or None
        Header name or index given by the user.
    path : str or path-like
        The CSV, for the messages.

    Returns
    -------
    int
        The column index, at least 1.

    Raises
    ------
    odnn_sep.errors.InputError
        For an unknown name (with the closest one), the coordinate column or an index out of range.
    odnn_sep.errors.FormatError
        For a header with fewer than two columns.

    Examples
    --------
    >>> pick_column(["t", "left", "right"], "right", path="rec.csv"), pick_column(["t", "v"], None, path="rec.csv")
    (2, 1)
    """

    names = [str(h).strip() for h in header]
    where = f"{str(path)!r} has columns {', '.join(f'{k}={n!r}' for k, n in enumerate(names))}"
    if column is None:
        if len(names) < 2:
            raise FormatError(f"{str(path)!r} needs a header row and at least two columns (coordinate, value); "
                              f"found {names}")
        return 1
    col = str(column).strip()
    j = column_index(names, col, "--column", path=path, check_range=False)
    if j == 0:
        raise InputError(f"--column {col!r} is the coordinate column (time or x); pick a value column: {where}")
    if not 0 < j < len(names):
        raise InputError(f"--column {col!r} is out of range; {where}")
    return j


def column_index(names, given, option: str, *, path, check_range: bool = True) -> int:
    """Index of the CSV column ``given`` (a header name, or an index counted from 0) for ``option``.

    Parameters
    ----------
    names : list of str
        The CSV's column names.
    given : str or int
        What the user gave.
    option : str
        The option's name, for the messages (``--column``, ``--x-column``).
    path : str or path-like
        The CSV, for the messages.
    check_range : bool, optional
        Refuse an index outside the columns (the caller may word that itself).

    Returns
    -------
    int

    Raises
    ------
    odnn_sep.errors.InputError
        For an unknown name (with the closest one) or an index out of range.

    Examples
    --------
    >>> column_index(["time", "velocity", "force"], "force", "--column", path="drag.csv")
    2
    >>> column_index(["time", "velocity"], "veloc", "--x-column", path="drag.csv")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --x-column 'veloc' is not a column of the CSV; did you mean 'velocity'? 'drag.csv' has columns 0='time', 1='velocity'
    """
    import difflib

    names = [str(h).strip() for h in names]
    where = f"{str(path)!r} has columns {', '.join(f'{k}={n!r}' for k, n in enumerate(names))}"
    text = str(given).strip()
    if text in names:
        return names.index(text)
    try:
        k = int(text)
    except ValueError:
        close = difflib.get_close_matches(text, names, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise InputError(f"{option} {text!r} is not a column of the CSV; {hint}{where}") from None
    if check_range and not 0 <= k < len(names):
        raise InputError(f"{option} {text!r} is out of range; {where}")
    return k


# Date-times of one column differ by less than this many years: a longer span is a misread column.
MAX_TIME_SPAN_YEARS = 200


def time_values(cells, *, path, name="time", first_line=2):
    """Seconds of a CSV's time column: numbers as they are, or ISO 8601 date-times as seconds since the first.

    Data loggers write time stamps (``2026-01-31T14:05:00.250``, ``2026-01-31 14:05:00``, with or without
    a UTC offset) more often than seconds; such a column is read as the seconds elapsed since its first
    row, and that row's time stamp is returned as the origin. A column is read one way or the other,
    never mixed.

    Parameters
    ----------
    cells : sequence of str
        The column's cells, in file order.
    path : str or Path
        The file (for the messages).
    name : str, optional
        The column's header (for the messages).
    first_line : int, optional
        The file line of ``cells[0]`` (for the messages).

    Returns
    -------
    (ndarray, str or None)
        The times (s for date-times) and the origin (the first time stamp, ISO 8601) or None for numbers.

    Raises
    ------
    odnn_sep.errors.FormatError
        For a cell that is neither, time stamps with and without a UTC offset, or a span over
        ``MAX_TIME_SPAN_YEARS``.

    Examples
    --------
    >>> t, origin = time_values(["2026-01-31 14:05:00", "2026-01-31 14:05:00.5", "2026-01-31T14:06:00"], path="a.csv")
    >>> t.tolist(), origin
    ([0.0, 0.5, 60.0], '2026-01-31T14:05:00')
    >>> time_values(["0", "1.5"], path="a.csv")[0].tolist()
    [0.0, 1.5]
    """
    import numpy as np

    try:
        return np.array([float(c) for c in cells]), None
    except ValueError:
        pass
    first = str(cells[0]).strip() if len(cells) else ""
    if _is_number(first):
        # a numeric column with a bad cell further down: named as such, not as a failed date-time
        bad = next(k for k, c in enumerate(cells) if not _is_number(c))
        raise FormatError(f"{str(path)!r} line {bad + first_line}: the time column {name!r} holds {cells[bad]!r}, "
                          f"not a number; remove or fix that row")
    from datetime import datetime

    stamps = []
    for k, c in enumerate(cells):
        try:
            stamps.append(datetime.fromisoformat(str(c).strip()))
        except ValueError:
            raise FormatError(f"{str(path)!r} line {k + first_line}: the time column {name!r} holds {c!r}, neither a "
                              f"number nor an ISO 8601 date-time (e.g. 2026-01-31T14:05:00.25); give seconds or "
                              f"time stamps in that form") from None
    if len({s.tzinfo is None for s in stamps}) > 1:
        raise FormatError(f"{str(path)!r}: the time column {name!r} mixes time stamps with and without a UTC offset; "
                          f"give every row the same form")
    t0 = stamps[0]
    t = np.array([(s - t0).total_seconds() for s in stamps])
    if t.size and float(np.max(np.abs(t))) > MAX_TIME_SPAN_YEARS * 365.25 * 86400:
        raise FormatError(f"{str(path)!r}: the time stamps of column {name!r} span more than {MAX_TIME_SPAN_YEARS} "
                          f"years; check that column is the record's time")
    return t, t0.isoformat()


def pick_channel(column, n_channels: int, *, path) -> int:
    """Index of an audio channel given as ``--column`` (counted from 0; default 0).

    Parameters
    ----------
    column : str or int or None
        The channel given as ``--column``.
    n_channels : int
        Channels in the file.
    path : str or path-like
        The audio file, for the messages.

    Returns
    -------
    int

    Raises
    ------
    odnn_sep.errors.InputError
        For a non-number or a channel out of range.

    Examples
    --------
    >>> pick_channel("1", 2, path="rec.wav")
    1
    >>> pick_channel("left", 2, path="rec.wav")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --column 'left' is not a channel number; 'rec.wav' has channels 0..1
    """
    if column is None:
        return 0
    col = str(column).strip()
    try:
        ch = int(col)
    except ValueError:
        raise InputError(f"--column {col!r} is not a channel number; {str(path)!r} has channels "
                         f"0..{n_channels - 1}") from None
    if not 0 <= ch < n_channels:
        raise InputError(f"--column {ch} is not a channel; {str(path)!r} has channels 0..{n_channels - 1}")
    return ch


def load_npz_arrays(path, keys=("x", "y", "z"), *, max_points=None) -> dict:
    """Read numeric arrays ``keys`` from an .npz safely.

    Shapes and types are read from the array headers first, so a small file that declares a huge
    array, a pickled object, or a damaged archive is refused with one line before any allocation.

    Parameters
    ----------
    path : str or path-like
        The .npz file.
    keys : tuple of str, optional
        Arrays to read.
    max_points : int, optional
        When given, each array's size is checked against the ``points`` limit.

    Returns
    -------
    dict
        Key -> float64 array.

    Raises
    ------
    odnn_sep.errors.FormatError
        For a damaged archive, a missing or non-numeric array.
    odnn_sep.errors.InputError
        For arrays beyond the limits, or a boolean array.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = os.path.join(d, "field.npz")
    ...     np.savez(path, x=np.arange(3.0), y=np.arange(2.0), z=np.zeros((2, 3)))
    ...     arrays = load_npz_arrays(path)
    >>> {k: v.shape for k, v in arrays.items()}
    {'x': (3,), 'y': (2,), 'z': (2, 3)}
    """
    import zipfile

    import numpy as np

    from odnn_sep import limits

    p = Path(path)
    try:
        with zipfile.ZipFile(p) as zf:
            headers = {}
            for name in zf.namelist():
                if not name.endswith(".npy"):
                    continue
                with zf.open(name) as fh:
                    version = np.lib.format.read_magic(fh)
                    read = (np.lib.format.read_array_header_1_0 if version == (1, 0)
                            else np.lib.format.read_array_header_2_0)
                    shape, _, dtype = read(fh)
                headers[name[:-4]] = (tuple(shape), np.dtype(dtype))
    except (zipfile.BadZipFile, OSError, ValueError, EOFError, KeyError) as exc:
        raise FormatError(f"could not read {str(p)!r} as .npz (a zip of .npy arrays): "
                          f"{str(exc).splitlines()[0] if str(exc) else type(exc).__name__}") from None
    missing = [k for k in keys if k not in headers]
    if missing:
        raise FormatError(f"{str(p)!r} lacks array(s) {missing}; a 2-D field needs x (nx,), y (ny,), z (ny, nx); "
                          f"found {sorted(headers)}")
    for k in keys:
        shape, dtype = headers[k]
        if dtype.kind == "b":
            # True/False were read as 1/0 without a word: a mask saved in place of the data fitted a
            # step, a boolean axis put every point at 0 or 1
            what = "coordinates" if k in ("x", "y", "t") else "values"
            raise InputError(f"array {k!r} in {str(p)!r} holds True/False, not numbers (a mask saved in place of the "
                             f"{what}?); save the measured {what}, or {k}.astype(float) if 0 and 1 are what was "
                             "measured")
        if dtype.kind not in "iuf":
            raise FormatError(f"array {k!r} in {str(p)!r} holds {dtype} values; it must be numeric")
        n = int(np.prod(shape, dtype=np.float64))
        if max_points is not None:
            limits.check("points", n, f"array {k!r} in {str(p)!r} (shape {shape}) size",
                         hint="use a coarser grid")
    try:
        with np.load(p, allow_pickle=False) as d:
            out = {k: np.asarray(d[k], dtype=float) for k in keys}
    except (OSError, ValueError, EOFError, zipfile.BadZipFile) as exc:
        raise FormatError(f"could not read {str(p)!r} as .npz: {str(exc).splitlines()[0]} (truncated or "
                          "damaged file?)") from None
    for k, a in out.items():
        limits.check_magnitude(f"array {k!r}", a)
    return out


def looks_binary(path, nbytes: int = 8192) -> bool:
    """True if the start of ``path`` holds NUL bytes or is not UTF-8 text (not a CSV).

    A file behind a UTF-16 or UTF-32 byte-order mark (:func:`text_encoding`) is judged on its
    decoded text: its NUL bytes are halves of characters.

    Parameters
    ----------
    path : str or path-like
    nbytes : int, optional
        How much of the start to read.

    Returns
    -------
    bool

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     with open(os.path.join(d, "a.csv"), "w") as fh:
    ...         _ = fh.write("t,v")
    ...     with open(os.path.join(d, "b.wav"), "wb") as fh:
    ...         _ = fh.write(bytes(16))
    ...     looks_binary(os.path.join(d, "a.csv")), looks_binary(os.path.join(d, "b.wav"))
    (False, True)
    """
    with open(path, "rb") as fh:
        head = fh.read(nbytes)
    codec = text_encoding(path)
    if codec != "utf-8-sig":
        unit = 4 if codec == "utf-32" else 2
        try:
            # a character cut by the read is dropped; UTF-16 may end inside a surrogate pair
            text = head[: len(head) // unit * unit].decode(codec, errors="strict" if unit == 4 else "surrogatepass")
        except UnicodeDecodeError:
            return True
        return "\0" in text
    if b"\0" in head:
        return True
    try:
        head.decode("utf-8")
    except UnicodeDecodeError as exc:
        return exc.start < len(head) - 4  # a multi-byte character cut by the read is fine
    return False


def count_lines(path, stop_after: int | None = None) -> int:
    """Number of lines of a text file, counted in binary blocks (cheap even for large files).

    Parameters
    ----------
    path : str or path-like
    stop_after : int, optional
        Stop counting once more lines than this were seen.

    Returns
    -------
    int
        Newline characters counted.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = os.path.join(d, "a.csv")
    ...     with open(path, "w") as fh:
    ...         _ = fh.write(chr(10).join(["t,v", "0,1", "1,2", ""]))
    ...     count_lines(path)
    3
    """
    n = 0
    codec = text_encoding(path)
    if codec != "utf-8-sig":
        # a UTF-16/32 file's newline is two or four bytes, and a byte 0x0A may be half of another character
        with open(path, encoding=codec, errors="replace", newline="") as fh:
            while block := fh.read(1 << 20):
                n += block.count("\n")
                if stop_after is not None and n > stop_after:
                    break
        return n
    with open(path, "rb") as fh:
        while block := fh.read(1 << 20):
            n += block.count(b"\n")
            if stop_after is not None and n > stop_after:
                break
    return n
