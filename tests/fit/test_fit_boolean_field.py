"""A field whose z (or an axis) is boolean is refused, not fitted as 0/1."""
import numpy as np
import pytest

from odnn_sep.cli import main


@pytest.mark.parametrize("which", ["z", "x"])
def test_boolean_array_in_a_field_is_refused(tmp_path, capsys, which):
    xa, ya = np.linspace(-1, 1, 30), np.linspace(-1, 1, 20)
    X, _ = np.meshgrid(xa, ya)
    arrays = {"x": xa, "y": ya, "z": X + 0.3 * X**2}
    arrays[which] = arrays[which] > 0            # a mask saved in place of the numbers
    f, out = tmp_path / "field.npz", tmp_path / "parts.csv"
    np.savez(f, **arrays)
    assert main(["separate", str(f), "--basis", "x", "--disturbance", "even", "-o", str(out)]) == 1
    err = capsys.readouterr().err
    assert f"array {which!r}" in err and "True/False" in err and "astype(float)" in err
    assert not out.exists()


def test_integer_field_is_still_read(tmp_path):
    xa, ya = np.linspace(-1, 1, 30), np.linspace(-1, 1, 20)
    X, _ = np.meshgrid(xa, ya)
    f = tmp_path / "field.npz"
    np.savez(f, x=xa, y=ya, z=np.round(10 * X + 3 * X**2).astype(np.int64))
    assert main(["separate", str(f), "--basis", "x", "--disturbance", "even", "--quiet"]) == 0


def test_boolean_field_is_refused_by_mismatch_too(tmp_path, capsys):
    # the same .npz reader serves mismatch: a boolean z was fitted there as a 0/1 field
    g = np.linspace(0, 1, 24)
    X, Y = np.meshgrid(g, g)
    f, rep = tmp_path / "field.npz", tmp_path / "r.json"
    np.savez(f, x=g, y=g, z=(X - 0.3) ** 2 + (Y - 0.4) ** 2 < 0.05)
    assert main(["mismatch", str(f), "--model", "heat2d", "--param", "sources=0.3:0.4", "--quiet",
                 "--report", str(rep)]) == 1
    err = capsys.readouterr().err
    assert "array 'z'" in err and "True/False" in err
    assert not rep.exists()
