"""A missing pixel of a field is named by its row and column in z, not by a flat index of "y"."""
import numpy as np

from odnn_sep.cli import main


def test_a_nan_pixel_is_named_by_row_and_column(tmp_path, capsys):
    x, yv = np.linspace(0, 1, 30), np.linspace(0, 1, 25)
    X, Y = np.meshgrid(x, yv)
    z = 20 + 5 * np.exp(-((X - 0.3) ** 2 + (Y - 0.4) ** 2) / 0.02)
    z[3, 4] = np.nan
    f = tmp_path / "field.npz"
    np.savez(f, x=x, y=yv, z=z)
    assert main(["mismatch", str(f), "--model", "heat2d", "--param", "sources=0.3:0.4", "--quiet"]) != 0
    err = capsys.readouterr().err.strip()
    # it read "y contains 1 NaN value(s) (first at index 94)"
    assert "(3, 4)" in err and "row, column" in err and len(err.splitlines()) == 1
