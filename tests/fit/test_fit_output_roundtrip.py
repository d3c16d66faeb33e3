"""The parts CSV of `separate -o` reads back to the same numbers, so it can be fitted again."""
import numpy as np

from odnn_sep.cli import main


def test_parts_keep_epoch_seconds_and_refit_the_same(tmp_path):
    # a logger's clock: epoch seconds sampled every 0.01 s (10 significant digits wrote 1700000000 for all)
    x = 1.7e9 + np.arange(400) * 0.01
    t = x - x[0]
    y = 3 * np.sin(2 * np.pi * 1.3 * t) + np.cos(2 * np.pi * 0.25 * t) + 0.02 * np.random.default_rng(0).normal(size=400)
    data, parts, again = tmp_path / "log.csv", tmp_path / "parts.csv", tmp_path / "again.csv"
    np.savetxt(data, np.c_[x, y], delimiter=",", header="x,y", comments="", fmt="%.17g")
    basis = ["--basis", "sin(2*pi*1.3*(x-1.7e9))", "--disturbance", "band:0:0.5", "--quiet"]
    assert main(["separate", str(data), *basis, "-o", str(parts)]) == 0
    back = np.genfromtxt(parts, delimiter=",", names=True)
    assert np.array_equal(back["x"], x) and np.array_equal(back["y"], y)
    # the written file is a valid input of its own, with the same fit
    assert main(["separate", str(parts), *basis, "-o", str(again)]) == 0
    assert np.array_equal(np.genfromtxt(again, delimiter=",", names=True)["physics"], back["physics"])


def test_parts_of_a_field_are_not_read_as_a_record_of_its_y_coordinate(tmp_path, capsys):
    xa, ya = np.linspace(-1, 1, 31), np.linspace(-1, 1, 21)
    X, Y = np.meshgrid(xa, ya)
    field, parts = tmp_path / "field.npz", tmp_path / "parts.csv"
    np.savez(field, x=xa, y=ya, z=2 * X * Y**2 + np.cos(X) + np.cos(2 * Y))
    assert main(["separate", str(field), "--basis", "x*y**2", "--disturbance", "even", "--quiet", "-o", str(parts)]) == 0
    capsys.readouterr()
    # the default value column of that CSV is the coordinate y: it was fitted without a word
    assert main(["separate", str(parts), "--basis", "x", "--quiet"]) == 1
    assert "parts CSV of a 2-D field" in capsys.readouterr().err
    assert main(["separate", str(parts), "--basis", "x", "--column", "z", "--quiet"]) == 0
