"""A record pasted twice is refused: its copies would narrow the intervals by 1.41 with no new data."""
import numpy as np

from odnn_sep.cli import main


def _record():
    x = np.linspace(-1, 1, 200)
    return x, 2 * np.sin(5 * x) + np.cos(2 * x) + 0.02 * np.random.default_rng(0).standard_normal(200)


def _write(path, x, y):
    np.savetxt(path, np.c_[x, y], delimiter=",", header="x,y", comments="", fmt="%.17g")


def test_record_pasted_twice_is_refused(tmp_path, capsys):
    x, y = _record()
    f, out = tmp_path / "twice.csv", tmp_path / "parts.csv"
    _write(f, np.r_[x, x], np.r_[y, y])
    assert main(["separate", str(f), "--basis", "sin(5*x)", "--disturbance", "periodic:0.5", "-o", str(out)]) == 1
    assert "repeats 200 row(s) exactly" in capsys.readouterr().err and not out.exists()


def test_copies_sorted_in_are_warned_and_differing_repeats_are_not(tmp_path, capsys):
    x, y = _record()
    f = tmp_path / "sorted.csv"
    _write(f, np.repeat(x, 2), np.repeat(y, 2))
    assert main(["separate", str(f), "--basis", "sin(5*x)", "--quiet"]) == 0
    assert "if they are copies, the intervals are too narrow" in capsys.readouterr().err
    # two readings at each x that differ: real repeated readings, no word
    y2 = y + 0.02 * np.random.default_rng(1).standard_normal(200)
    _write(f, np.r_[x, x], np.r_[y, y2])
    assert main(["separate", str(f), "--basis", "sin(5*x)", "--quiet"]) == 0
    assert "copies" not in capsys.readouterr().err
