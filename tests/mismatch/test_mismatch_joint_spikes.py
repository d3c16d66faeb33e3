"""Joint series: each series' spikes are repaired on its own, as a single record's are (spikes_series.py)."""
import json

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.mismatch.joint import explain_joint, joint_estimates
from odnn_sep.mismatch.model import make_model

H = (0.010, 0.015, 0.020, 0.025, 0.030)
SPIKES = (5, 9, 14)


def _mugs(spikes, seed=1, n=60):
    """Five mugs; mug1 has a precise thermometer (noise 0.01) with three spikes of +0.45, the others 0.1."""
    rng = np.random.default_rng(seed)
    out = {}
    for i, h in enumerate(H):
        t = np.linspace(0, 300, n) + 3.0 * i
        m = make_model("cooling", {"h": h, "T_ambient": 21.5, "T0": 90.0 - 4 * i})
        y = m.predict(t) + (0.01 if i == 0 else 0.1) * rng.normal(size=n)
        if i == 0 and spikes:
            y[list(SPIKES)] += 0.45
        out[f"mug{i + 1}"] = (t, y)
    return out


def _mug1(res):
    s = joint_estimates(res)["series"]["mug1"]
    return s["T0"][0], s["h"][0]


@pytest.fixture(scope="module")
def clean():
    return explain_joint("cooling", _mugs(spikes=False))


def test_a_quiet_series_spikes_are_repaired_and_listed_with_its_name(clean):
    # on the stacked axis the noise level was pooled over the five mugs (0.1): 0.45 stayed under
    # 5 noise levels, was not repaired, and moved mug1's T0 by 0.09 (20 times its standard error, 0.004,
    # in a fit of mug1 alone)
    s = _mugs(spikes=True)
    res = explain_joint("cooling", s)
    entries = [d for d in res.disturbances if d["effect"] == "spikes"]
    assert len(entries) == 1 and entries[0]["series"] == "mug1" and entries[0]["parameters"] == {"count": 3}
    assert entries[0]["at"] == pytest.approx(s["mug1"][0][list(SPIKES)].tolist())   # mug1's own clock
    assert entries[0]["description"].startswith("series mug1: 3 isolated outliers")
    assert res.effects == clean.effects == []
    (T0, h), (T0c, hc) = _mug1(res), _mug1(clean)
    assert abs(T0 - T0c) < 0.005 and abs(h - hc) < 2e-6
    kept = explain_joint("cooling", s, despike=False)
    assert not any(d["effect"] == "spikes" for d in kept.disturbances)
    assert abs(_mug1(kept)[0] - T0c) > 0.05            # unrepaired, the spikes move mug1's parameters


def test_cli_joint_keep_spikes(tmp_path):
    path = tmp_path / "mugs.csv"
    with open(path, "w") as fh:
        fh.write("time,mug,T\n")
        for name, (t, y) in _mugs(spikes=True).items():
            fh.writelines(f"{a:.3f},{name},{b:.5f}\n" for a, b in zip(t, y, strict=True))
    found = []
    for extra in ([], ["--keep-spikes"]):
        out = tmp_path / f"r{len(extra)}.json"
        assert main(["mismatch", str(path), "--model", "cooling", "--series", "mug", "--quiet",
                     "--report", str(out), *extra]) == 0
        found.append([d.get("series") for d in json.loads(out.read_text())["verdict"]["disturbances"]
                      if d["effect"] == "spikes"])
    assert found == [["mug1"], []]
