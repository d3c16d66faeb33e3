"""A declared line above the Nyquist frequency is refused in the caller's time unit.

A record whose span is far from seconds-like is analysed on ``t / 1000``; the refusal of
``--disturbance periodic:HZ`` named the internal numbers (``periodic:1000 ... Nyquist 100 Hz`` for a
1 Hz line on a record sampled every 5 s), which read as a line well below the Nyquist frequency.
"""
import numpy as np

from odnn_sep.cli import main


def _cooling(path, series=False):
    t = np.arange(0, 2000, 5.0)
    rng = np.random.default_rng(0)
    with open(path, "w") as fh:
        if series:
            fh.write("t,mug,T\n")
            for mug, h in (("a", 0.002), ("b", 0.003)):
                T = 20 + 60 * np.exp(-h * t) + rng.normal(0, 0.05, t.size)
                fh.writelines(f"{a},{mug},{b}\n" for a, b in zip(t, T, strict=True))
        else:
            fh.write("t,T\n")
            T = 20 + 60 * np.exp(-0.002 * t) + rng.normal(0, 0.05, t.size)
            fh.writelines(f"{a},{b}\n" for a, b in zip(t, T, strict=True))


def test_line_above_nyquist_named_in_seconds(tmp_path, capsys):
    data = tmp_path / "cool.csv"
    _cooling(data)
    code = main(["mismatch", str(data), "--model", "cooling", "--disturbance", "periodic:1", "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 1
    assert err == "Error: --disturbance periodic:1: the frequency is above the Nyquist frequency 0.1 Hz of the data"


def test_line_above_nyquist_named_in_seconds_joint(tmp_path, capsys):
    data = tmp_path / "mugs.csv"
    _cooling(data, series=True)
    code = main(["mismatch", str(data), "--model", "cooling", "--series", "mug", "--disturbance", "periodic:1",
                 "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 1
    assert "periodic:1:" in err and "Nyquist frequency 0.1 Hz" in err, err
