"""Reading mismatch-finder inputs: CSV (time + value column), WAV (audio), NPZ (2D field x, y, z)."""
from __future__ import annotations

import csv
from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError
from odnn_sep.io_utils import check_input_path


def _pick_column(header, column):
    if column is None:
        if len(header) < 2:
            raise FormatError(f"CSV needs at least two columns (time, value); found header {header}")
        return 1
    names = [h.strip() for h in header]
    if str(column) in names:
        return names.index(str(column))
    try:
        i = int(column)
    except (TypeError, ValueError):
        import difflib
        close = difflib.get_close_matches(str(column), names, n=1)
        hint = f"did you mean {close[0]!r}? " if close else ""
        raise InputError(f"--column {column!r} is not a column of the CSV; {hint}columns: {', '.join(names)}") from None
    if not 0 <= i < len(names):
        raise InputError(f"--column {i} is out of range; the CSV has columns 0..{len(names) - 1} ({', '.join(names)})")
    return i


def _numeric_columns(rows, skip):
    """{header: values} for every all-numeric column of ``rows[1:]`` not in ``skip`` (aux channels)."""
    header = [h.strip() for h in rows[0]]
    out = {}
    for j, name in enumerate(header):
        if j in skip:
            continue
        try:
            out[name or f"col{j}"] = np.array([float(r[j]) for r in rows[1:]])
        except (ValueError, IndexError):
            continue   # a label or unit column, not a channel
    return out


def read_csv(path, column=None, *, aux=False):
    """Return (t, y, info) from a CSV with a header row; time is the first column.

    With ``aux=True`` return (t, y, info, aux): ``aux`` holds every other all-numeric column.
    """
    with open(path, newline="") as fh:
        rows = list(csv.reader(fh))
    rows = [r for r in rows if r and any(c.strip() for c in r)]
    if len(rows) < 2:
        raise FormatError(f"CSV {str(path)!r} has no data rows below the header")
    header = rows[0]
    j = _pick_column(header, column)
    t, y = [], []
    for k, r in enumerate(rows[1:], start=2):
        try:
            t.append(float(r[0]))
            y.append(float(r[j]))
        except (ValueError, IndexError):
            raise FormatError(f"CSV {str(path)!r} line {k}: time and column {header[j]!r} must be numbers; "
                              f"got {r[:max(j + 1, 1)]}") from None
    info = {"format": "csv", "column": header[j].strip(), "time": header[0].strip()}
    if aux:
        return np.array(t), np.array(y), info, _numeric_columns(rows, {0, j})
    return np.array(t), np.array(y), info


def read_wav(path, column=None, *, aux=False):
    import soundfile as sf

    from odnn_sep.io_utils import ensure_readable
    data, sr = ensure_readable(path, lambda p: sf.read(str(p), dtype="float64", always_2d=True), what="WAV file")
    ch = 0 if column is None else int(column)
    if not 0 <= ch < data.shape[1]:
        raise InputError(f"--column {ch} is not a channel; the WAV has channels 0..{data.shape[1] - 1}")
    y = data[:, ch]
    info = {"format": "wav", "sr": sr, "channel": ch}
    if aux:
        others = {f"ch{k}": data[:, k].copy() for k in range(data.shape[1]) if k != ch}
        return np.arange(len(y)) / sr, y, info, others
    return np.arange(len(y)) / sr, y, info


def read_npz(path):
    from odnn_sep.io_utils import ensure_readable
    d = ensure_readable(path, np.load, what="NPZ file")
    missing = [k for k in ("x", "y", "z") if k not in d]
    if missing:
        raise FormatError(f"NPZ {str(path)!r} must hold arrays x, y (grid axes) and z (values, len(y) x len(x)); "
                          f"missing {', '.join(missing)}")
    x, yy, z = (np.asarray(d[k], float) for k in ("x", "y", "z"))
    if z.shape != (len(yy), len(x)):
        raise FormatError(f"NPZ z has shape {z.shape}; expected (len(y), len(x)) = ({len(yy)}, {len(x)})")
    X, Y = np.meshgrid(x, yy)
    return np.column_stack([X.ravel(), Y.ravel()]), z.ravel(), {"format": "npz", "shape": list(z.shape)}


def load_data(path, *, column=None, start=None, duration=None, with_aux=False):
    """Load (t, y, info) from CSV, WAV or NPZ; ``start``/``duration`` (seconds) select a time range.

    With ``with_aux=True`` return (t, y, info, aux): ``aux`` maps the file's other channels (WAV
    channels ``ch<k>``, other numeric CSV columns by header) to arrays aligned with ``y``, for the
    ``channel_coupling`` effect; ``info["aux_channels"]`` lists their names.
    """
    p = check_input_path(path, what="data file")
    ext = Path(p).suffix.lower()
    aux = {}
    if ext == ".csv":
        t, y, info, aux = read_csv(p, column, aux=True)
    elif ext in (".wav", ".flac"):
        t, y, info, aux = read_wav(p, column, aux=True)
    elif ext == ".npz":
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
        t, y = t[sel], y[sel]
        aux = {k: v[sel] for k, v in aux.items()}
    if with_aux:
        info["aux_channels"] = list(aux)
        return t, y, info, aux
    return t, y, info
