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
