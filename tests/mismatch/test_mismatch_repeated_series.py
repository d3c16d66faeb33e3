"""The same record given twice to a joint fit is refused: its noise would count twice."""
import numpy as np

from odnn_sep.cli import main


def _write(path, t, y):
    path.write_text("t,T\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), y.tolist())))


def test_one_record_under_two_names_is_refused(tmp_path, capsys):
    t = np.linspace(0, 300, 300)
    y = 20 + 60 * np.exp(-0.01 * t) + 0.05 * np.random.default_rng(5).normal(size=t.size)
    _write(tmp_path / "run1.csv", t, y)
    _write(tmp_path / "run1_copy.csv", t, y)
    report = tmp_path / "r.json"
    # it was fitted as two mugs, and T_ambient's interval narrowed from +-0.0103 to +-0.0073
    rc = main(["mismatch", str(tmp_path / "run1.csv"), str(tmp_path / "run1_copy.csv"), "--model", "cooling",
               "--quiet", "--report", str(report)])
    err = capsys.readouterr().err.strip()
    assert rc != 0 and not report.exists()
    assert len(err.splitlines()) == 1 and "same 300 values" in err and "run1_copy" in err


def test_a_series_column_with_a_copied_series_is_refused_but_distinct_ones_fit(tmp_path, capsys):
    t = np.linspace(0, 300, 100)
    rng = np.random.default_rng(1)
    ys = [20 + 60 * np.exp(-0.01 * t) + 0.05 * rng.normal(size=t.size) for _ in range(2)]
    rows = [("a", ys[0]), ("b", ys[1]), ("c", ys[0])]
    f = tmp_path / "mugs.csv"
    f.write_text("t,T,mug\n" + "".join(f"{a!r},{b!r},{nm}\n" for nm, y in rows for a, b in zip(t.tolist(), y.tolist())))
    assert main(["mismatch", str(f), "--model", "cooling", "--series", "mug", "--quiet"]) != 0
    assert "'a' and 'c' hold the same" in capsys.readouterr().err
    g = tmp_path / "two.csv"
    g.write_text("t,T,mug\n" + "".join(f"{a!r},{b!r},{nm}\n" for nm, y in rows[:2] for a, b in zip(t.tolist(), y.tolist())))
    assert main(["mismatch", str(g), "--model", "cooling", "--series", "mug", "--quiet"]) == 0
