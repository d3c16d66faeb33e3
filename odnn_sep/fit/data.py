"""Load a 1-D signal (CSV: first column x, value column chosen) or a 2-D field (.npz with x, y, z)."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError, check_finite
from odnn_sep.io_utils import check_input_path


def load_signal(path, column: str | int | None = None):
    """Return (coords, values, coord_names, grid_shape).

    CSV: header row, first column is x, the value column is ``column`` (name or index; default the
    second). NPZ: arrays ``x`` (nx,), ``y`` (ny,), ``z`` (ny, nx); coords are the (ny*nx, 2) points.
    """
    p = check_input_path(path)
    if p.suffix.lower() == ".npz":
        try:
            d = np.load(p)
        except (OSError, ValueError) as exc:
            raise FormatError(f"could not read {str(p)!r} as .npz: {exc}") from None
        missing = [k for k in ("x", "y", "z") if k not in d.files]
        if missing:
            raise FormatError(f"{str(p)!r} lacks array(s) {missing}; a 2-D field needs x (nx,), y (ny,), z (ny, nx)")
        x, y, z = (np.asarray(d[k], dtype=float) for k in ("x", "y", "z"))
        if z.shape != (y.size, x.size):
            raise InputError(f"z has shape {z.shape} but len(y) x len(x) is {(y.size, x.size)}; they must match")
        X, Y = np.meshgrid(x, y)
        check_finite("z", z)
        return np.c_[X.ravel(), Y.ravel()], z.ravel(), ("x", "y"), z.shape
    try:
        with open(p, newline="") as fh:
            header = [h.strip() for h in fh.readline().strip().split(",")]
        data = np.genfromtxt(p, delimiter=",", skip_header=1, dtype=float)
    except (OSError, ValueError, UnicodeDecodeError) as exc:
        raise FormatError(f"could not read {str(p)!r} as CSV: {exc}") from None
    data = np.atleast_2d(data)
    if data.size == 0 or data.shape[1] < 2:
        raise FormatError(f"{str(p)!r} needs a header row and at least two columns (x and a value)")
    if column is None:
        j = 1
    elif isinstance(column, int) or str(column).isdigit():
        j = int(column)
    elif column in header:
        j = header.index(column)
    else:
        raise InputError(f"column {column!r} is not in {str(p)!r}; columns are {header}")
    if not 0 < j < data.shape[1]:
        raise InputError(f"column index {j} is out of range; {str(p)!r} has columns 1..{data.shape[1] - 1} after x")
    x, v = data[:, 0], data[:, j]
    check_finite(f"column {header[j] if j < len(header) else j!r}", v)
    check_finite("x (first column)", x)
    name = header[0] if header and header[0].isidentifier() else "x"
    return x, v, (name,), None


def write_components(out, x, y, res) -> None:
    """CSV with coordinates, data, physics, disturbance and residual columns (atomic)."""
    from odnn_sep.io_utils import atomic_output, check_output_path

    check_output_path(out)
    X = x[:, None] if x.ndim == 1 else x
    cols = [X, y[:, None], res.physics[:, None], res.disturbance[:, None], res.residual[:, None]]
    head = ",".join([f"x{i}" for i in range(X.shape[1])] if X.shape[1] > 1 else ["x"])
    with atomic_output(out, suffix=Path(out).suffix or ".csv") as tmp:
        np.savetxt(tmp, np.hstack(cols), delimiter=",", header=head + ",y,physics,disturbance,residual",
                   comments="", fmt="%.10g")
