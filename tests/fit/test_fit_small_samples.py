"""Intervals of `separate` on few samples use Student's t on the residual degrees of freedom."""
import numpy as np

from odnn_sep.core.uncertainty import intervals


def test_t_quantile_on_few_degrees_of_freedom():
    lo, hi = intervals([0.0], [1.0], dof=4)[0]
    assert abs(hi - 2.776445) < 1e-5 and abs(lo + 2.776445) < 1e-5
    assert abs(intervals([0.0], [1.0])[0][1] - 1.959964) < 1e-6


def test_separate_interval_on_five_points_uses_t(tmp_path):
    import json

    from odnn_sep.cli import main

    x = np.linspace(0, 1, 5)
    y = 0.5 * x + 0.1 * np.random.default_rng(0).normal(size=5)
    f = tmp_path / "s.csv"
    np.savetxt(f, np.column_stack([x, y]), delimiter=",", header="x,y", comments="")
    rep = tmp_path / "r.json"
    assert main(["separate", str(f), "--basis", "x", "-o", str(tmp_path / "o.csv"), "--report", str(rep),
                 "--quiet"]) == 0
    p = json.loads(rep.read_text())["parameters"]["x"]
    half = (p["interval"][1] - p["interval"][0]) / 2
    assert abs(half / p["stderr"] - 2.776445) < 1e-4           # t(0.975, 4 residual dof), not 1.96
