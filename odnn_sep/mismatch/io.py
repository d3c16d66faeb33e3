"""Reading mismatch-finder inputs: CSV (time + value column), WAV (audio), NPZ (2D field x, y, z)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError
from odnn_sep.io_paths import check_input_path


def _pick_column(header, column, path="the CSV"):
    # the same --column rule as `separate` (name, or index from 0 where 0 is time)
    from odnn_sep.io_read import pick_column

    return pick_column(header, column, path=path)


def _numeric_columns(rows, skip, why=None):
    """{header: values} for every all-numeric column of ``rows[1:]`` not in ``skip`` (aux channels);
    ``why`` (a dict), when given, gets the first line and cell that kept each other column out."""
    header = [h.strip() for h in rows[0]]
    out = {}
    for j, name in enumerate(header):
        if j in skip:
            continue
        vals = []
        for k, r in enumerate(rows[1:], start=2):
            try:
                vals.append(float(r[j]))
            except (ValueError, IndexError):
                # a label or unit column, not a channel
                if why is not None:
                    why[name or f"col{j}"] = f"line {k} ({r[j]!r})" if j < len(r) else f"line {k} (no cell)"
                break
        else:
            out[name or f"col{j}"] = np.array(vals)
    return out


def read_csv(path, column=None, *, aux=False):
    """Return (t, y, info) from a CSV with a header row; time is the first column.

    Time is in seconds, or ISO 8601 date-times read as seconds since the first row (``info["time_origin"]``
    is then that row's time stamp).

    With ``aux=True`` return (t, y, info, aux): ``aux`` holds every other all-numeric column.

    Parameters
    ----------
    path : str or Path
        CSV file with a header row.
    column : str or int, optional
        Value column: header name, or index where 0 is time (default: the first after time).
    aux : bool, optional
        Also return the other numeric columns.

    Returns
    -------
    t, y : ndarray
        Time and value columns.
    info : dict
        ``format``, ``column`` and ``time`` (the header names used).
    aux : dict, optional
        ``{header: values}`` of the other numeric columns (only with ``aux=True``).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "run.csv")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("t,T,ref\\n0,90,1\\n1,85,2\\n")
    >>> t, y, info, others = read_csv(path, "T", aux=True)
    >>> t.tolist(), y.tolist(), info["column"], list(others)
    ([0.0, 1.0], [90.0, 85.0], 'T', ['ref'])
    """
    from odnn_sep.io_read import check_header, leading_comments, row_index_column, table_rows
    rows, read_as = table_rows(path)         # commas, or the ';' / tabs / spaces its header shows
    rows = rows[leading_comments(rows):]     # '# sensor: ...' lines above the header
    if len(rows) < 2:
        raise FormatError(f"CSV {str(path)!r} has no data rows below the header")
    header = rows[0]
    check_header(header, path=path)
    dropped = None
    if row_index_column(header, [[r[k] if k < len(r) else "" for r in rows[1:]] for k in range(2)]):
        # a table library's row counter (pandas' unnamed index): time is the next column
        dropped = header[0].strip()
        rows = [r[1:] for r in rows]
        header = rows[0]
    j = _pick_column(header, column, path)
    y = []
    for k, r in enumerate(rows[1:], start=2):
        try:
            y.append(float(r[j]))
        except (ValueError, IndexError):
            cell = r[j].strip() if j < len(r) else ""
            fix = ("the cell is empty (a missing value): remove that row or fill it" if not cell
                   else "remove or repair that row (units belong in the header, e.g. 'T_degC')")
            raise FormatError(f"CSV {str(path)!r} line {k}: time and column {header[j]!r} must be numbers; "
                              f"got {r[:max(j + 1, 1)]}; {fix}") from None
    from odnn_sep.io_read import time_values

    # seconds, or date-times read as seconds since the first (the origin goes in the report)
    t, origin = time_values([r[0] for r in rows[1:]], path=path, name=header[0].strip())
    info = {"format": "csv", "column": header[j].strip(), "time": header[0].strip()}
    if read_as is not None:
        info["read_as"] = read_as
    if dropped is not None:
        info["row_index_column"] = dropped
    if origin is not None:
        info["time_origin"] = origin
    if aux:
        info["not_numeric"] = {}
        return np.array(t), np.array(y), info, _numeric_columns(rows, {0, j}, info["not_numeric"])
    return np.array(t), np.array(y), info


def read_wav(path, column=None, *, aux=False):
    """Return (t, y, info) from an audio file (WAV, FLAC); ``t`` is the sample index over the rate.

    Parameters
    ----------
    path : str or Path
        Audio file.
    column : int or str, optional
        Channel to analyse (default: the first).
    aux : bool, optional
        Also return the other channels as ``{"ch<k>": samples}``.

    Returns
    -------
    t, y : ndarray
        Times (s) and samples of the channel.
    info : dict
        ``format``, ``sr`` (sample rate) and ``channel``.
    aux : dict, optional
        The other channels (only with ``aux=True``).

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np, soundfile as sf
    >>> path = os.path.join(tempfile.mkdtemp(), "hum.wav")
    >>> sf.write(path, np.zeros((8, 2)), 8000, subtype="FLOAT")
    >>> t, y, info, others = read_wav(path, aux=True)
    >>> len(t), float(t[1]), info, list(others)
    (8, 0.000125, {'format': 'wav', 'sr': 8000, 'channel': 0}, ['ch1'])
    """
    import soundfile as sf

    from odnn_sep.io_utils import ensure_readable
    data, sr = ensure_readable(path, lambda p: sf.read(str(p), dtype="float64", always_2d=True), what="WAV file")
    from odnn_sep.io_read import pick_channel

    ch = pick_channel(column, data.shape[1], path=path)
    y = data[:, ch]
    info = {"format": "wav", "sr": sr, "channel": ch}
    if aux:
        others = {f"ch{k}": data[:, k].copy() for k in range(data.shape[1]) if k != ch}
        return np.arange(len(y)) / sr, y, info, others
    return np.arange(len(y)) / sr, y, info


def read_npz(path):
    """Return (xy, z, info) from an .npz holding a 2D field: arrays ``x``, ``y`` and ``z[len(y), len(x)]``.

    Parameters
    ----------
    path : str or Path
        The .npz file.

    Returns
    -------
    xy : ndarray, shape (n, 2)
        Coordinates of every grid point (row-major over ``z``).
    z : ndarray, shape (n,)
        Field values.
    info : dict
        ``format`` and ``shape`` (of ``z``).

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> path = os.path.join(tempfile.mkdtemp(), "field.npz")
    >>> np.savez(path, x=np.arange(3.0), y=np.arange(2.0), z=np.arange(6.0).reshape(2, 3))
    >>> xy, z, info = read_npz(path)
    >>> xy.shape, xy[4].tolist(), float(z[4]), info
    ((6, 2), [1.0, 1.0], 4.0, {'format': 'npz', 'shape': [2, 3]})
    """
    from odnn_sep.io_read import load_npz_arrays
    d = load_npz_arrays(path, max_points=True)  # shapes and types checked before loading
    x, yy, z = (d[k] for k in ("x", "y", "z"))
    _refuse_missing_pixels(path, z)
    if z.ndim == 3:
        return _read_frames(path, x, yy, z)
    if z.shape != (len(yy), len(x)):
        raise FormatError(f"NPZ z has shape {z.shape}; expected (len(y), len(x)) = ({len(yy)}, {len(x)})")
    X, Y = np.meshgrid(x, yy)
    return np.column_stack([X.ravel(), Y.ravel()]), z.ravel(), {"format": "npz", "shape": list(z.shape)}


def _refuse_missing_pixels(path, z):
    """NaN/inf in a field named by its place in z (it read as "y contains NaN at index 94" of the flat field)."""
    z = np.asarray(z)
    if not np.issubdtype(z.dtype, np.number):
        return
    bad = ~np.isfinite(z)
    if bad.any():
        where = tuple(int(i) for i in np.argwhere(bad)[0])
        axes = ("frame, row, column" if z.ndim == 3 else "row, column") if z.ndim in (2, 3) else "index"
        raise InputError(f"NPZ {str(path)!r}: z has {int(bad.sum())} missing (NaN or inf) value(s), the first at "
                         f"{axes} {where}; fill or interpolate them before fitting (a field needs every pixel)")


def _read_frames(path, x, yy, z):
    """Several frames of a field (z: (n_frames, ny, nx), t: frame times): frame k's points have x
    shifted by k * frame_dx (see :mod:`odnn_sep.mismatch.presets_heat2d`)."""
    from odnn_sep.io_read import load_npz_arrays
    if z.shape[1:] != (len(yy), len(x)):
        raise FormatError(f"NPZ z has shape {z.shape}; frames need (n_frames, len(y), len(x)) = "
                          f"(n_frames, {len(yy)}, {len(x)})")
    try:
        tf = load_npz_arrays(path, keys=("t",))["t"]
    except FormatError:
        raise FormatError(f"NPZ {str(path)!r} has {z.shape[0]} frames (z is 3-D) but no array t of frame "
                          f"times; add t (n_frames,)") from None
    if tf.shape != (z.shape[0],) or tf[0] <= 0 or (len(tf) > 1 and np.ptp(np.diff(tf)) > 1e-9 * np.ptp(tf)) \
            or (len(tf) > 1 and tf[1] <= tf[0]):
        # which rule failed: a first frame at 0 (time counted from the recording's start) is the usual slip
        why = (f"it has {tf.size} values for {z.shape[0]} frames" if tf.shape != (z.shape[0],) else
               "the first is not after 0: t is the time since the sources started (at t = 0 a point "
               "source's heat has not spread), so give each frame's time since then" if tf[0] <= 0 else
               "they do not increase evenly")
        raise FormatError(f"NPZ frame times t must be {z.shape[0]} positive, increasing, evenly spaced "
                          f"values; {why}; got {tf.tolist()[:6]}")
    dt = float(tf[1] - tf[0]) if len(tf) > 1 else 0.0
    dx = float(10.0 ** np.ceil(np.log10(10.0 * max(np.abs(x).max(), np.abs(yy).max(), np.ptp(x), 1e-9))))
    X, Y = np.meshgrid(x, yy)
    xy = np.vstack([np.column_stack([X.ravel() + k * dx, Y.ravel()]) for k in range(z.shape[0])])
    info = {"format": "npz", "shape": list(z.shape), "frames": int(z.shape[0]), "frame_t0": float(tf[0]),
            "frame_dt": dt, "frame_dx": dx}
    return xy, z.reshape(-1), info


def load_data(path, *, column=None, start=None, duration=None, with_aux=False):
    """Load (t, y, info) from CSV, WAV or NPZ; ``start``/``duration`` (in the time column's unit) select a time range.

    With ``with_aux=True`` return (t, y, info, aux): ``aux`` maps the file's other channels (WAV
    channels ``ch<k>``, other numeric CSV columns by header) to arrays aligned with ``y``, for the
    ``channel_coupling`` effect; ``info["aux_channels"]`` lists their names.

    Parameters
    ----------
    path : str or Path
        ``.csv``, ``.wav``/``.flac`` or ``.npz`` file.
    column : str or int, optional
        CSV column or audio channel.
    start, duration : float, optional
        Time range to keep (in the unit of the time column, seconds for audio; series only).
    with_aux : bool, optional
        Also return the other channels.

    Returns
    -------
    t : ndarray
        Times (series) or (n, 2) coordinates (field).
    y : ndarray
        Values.
    info : dict
        What was read (format, column or channel, ...).
    aux : dict, optional
        The other channels (only with ``with_aux=True``).

    Examples
    --------
    >>> import os, tempfile
    >>> path = os.path.join(tempfile.mkdtemp(), "run.csv")
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("t,T\\n" + "".join(f"{i},{90 - i}\\n" for i in range(10)))
    >>> t, y, info = load_data(path, start=2, duration=3)
    >>> t.tolist(), y.tolist(), info["column"]
    ([2.0, 3.0, 4.0], [88.0, 87.0, 86.0], 'T')
    """
    p = check_input_path(path, what="data file")
    ext = Path(p).suffix.lower()
    aux = {}
    _check_size_before_reading(p, ext, start, duration)
    if ext == ".csv":
        t, y, info, aux = read_csv(p, column, aux=True)
    elif ext in (".wav", ".flac"):
        t, y, info, aux = read_wav(p, column, aux=True)
    elif ext == ".npz":
        # a field's values are its array z, and all of its frames are fitted: these options were ignored
        given = [o for o, v in (("--column", column), ("--start", start), ("--duration", duration)) if v is not None]
        if given:
            raise InputError(f"{' and '.join(given)} {'is' if len(given) == 1 else 'are'} for time series (CSV "
                             f"columns, WAV channels); {str(p)!r} is a field whose values are its array z, fitted "
                             f"whole: leave {'it' if len(given) == 1 else 'them'} out")
        t, y, info = read_npz(p)
    else:
        raise FormatError(f"data file {str(p)!r} has extension {ext!r}; use .csv (time + value columns), "
                          f".wav (audio) or .npz (arrays x, y, z)")
    if (start is not None or duration is not None) and t.ndim == 1:
        lo = t[0] if start is None else float(start)
        hi = np.inf if duration is None else lo + float(duration)
        sel = (t >= lo) & (t < hi)
        if sel.sum() == 0:
            raise InputError(f"--start {start} / --duration {duration} select no samples; "
                             f"the data spans {t[0]:g} to {t[-1]:g}")
        if sel.sum() < MIN_WINDOW <= len(t) and sel.sum() < len(t) / 4:
            # a window given in seconds on a record timed in ms keeps a handful of samples, and the
            # analysis then failed on "too little data" with no word on the window
            window = " ".join(f"--{k} {v:g}" for k, v in (("start", start), ("duration", duration)) if v is not None)
            raise InputError(f"{window} keeps {int(sel.sum())} of {len(t)} samples "
                             f"(the data spans {t[0]:g} to {t[-1]:g}); --start and --duration are in the unit of "
                             f"the time column, so widen the window in that unit")
        t, y = t[sel], y[sel]
        aux = {k: v[sel] for k, v in aux.items()}
    _check_loaded(t, y, aux)
    if with_aux:
        info["aux_channels"] = list(aux)
        return t, y, info, aux
    return t, y, info


# fewest samples a --start/--duration window may keep when it cuts away most of the record: the
# held-out test's least (2 folds, --folds 2)
MIN_WINDOW = 16


def _check_size_before_reading(p, ext, start, duration):
    """Binary data under .csv, and CSVs far beyond the row limit, are refused before parsing."""
    from odnn_sep import limits
    from odnn_sep.io_read import count_lines, looks_binary

    if ext != ".csv":
        return
    if looks_binary(p):
        raise FormatError(f"data file {str(p)!r} is not a text CSV (it holds binary data); give a CSV with a header "
                          "row, a .wav or an .npz")
    if start is None and duration is None:
        n = count_lines(p) - 1
        limits.check("rows", n, f"the row count of data file {str(p)!r}",
                     hint="select a part with --start/--duration, or decimate the data")


def _check_loaded(t, y, aux):
    from odnn_sep import limits

    limits.check("rows", int(np.size(y)), "the number of samples to analyse",
                 hint="select a part with --start/--duration, or decimate the data")
    limits.check_magnitude("the data values", y)
    limits.check_magnitude("the time (or coordinate) values", t)
    for name, a in aux.items():
        limits.check_magnitude(f"channel {name!r}", a)
