"""heat2d: ambient level, continuous sources, several frames, source_moved (presets_heat2d.py)."""
import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import FormatError
from odnn_sep.mismatch import explain
from odnn_sep.mismatch.io import read_npz
from odnn_sep.mismatch.model import make_model

SRC = "0.3:0.4;0.7:0.6"
BASE = {"alpha": 0.01, "t": 1.0, "sources": SRC, "S1": 1.0, "S2": 0.7}


def _grid(n=24):
    g = np.linspace(0, 1, n)
    X, Y = np.meshgrid(g, g)
    return np.column_stack([X.ravel(), Y.ravel()])


def _noisy(m, xy, noise=0.05, seed=0):
    return m.predict(xy) + noise * np.random.default_rng(seed).normal(size=len(xy))


def test_moved_source_is_source_moved_not_an_extra_one():
    xy = _grid()
    truth = make_model("heat2d", BASE).with_effect("source_moved", {"k_src": 2.0, "dx_src": 0.06, "dy_src": -0.04})
    res = explain("heat2d", xy, _noisy(truth, xy), params={"sources": SRC}, effects=["extra_source", "source_moved"])
    assert res.effects == ["source_moved"]
    p = res.final_fit.params
    assert p["k_src"] == 2 and abs(p["dx_src"] - 0.06) < 0.01 and abs(p["dy_src"] + 0.04) < 0.01


def test_extra_source_away_from_the_given_ones_is_still_named():
    xy = _grid()
    truth = make_model("heat2d", BASE).with_effect("extra_source", {"xs": 0.5, "ys": 0.85, "S_extra": 0.4})
    res = explain("heat2d", xy, _noisy(truth, xy, seed=1), params={"sources": SRC},
                  effects=["extra_source", "source_moved"])
    assert res.effects == ["extra_source"]
    p = res.final_fit.params
    assert abs(p["xs"] - 0.5) < 0.02 and abs(p["ys"] - 0.85) < 0.02


def test_extra_source_never_on_a_given_one():
    from odnn_sep.mismatch.presets_heat2d import extra_position
    p = {**make_model("heat2d", BASE).start, "xs": 0.3, "ys": 0.4}
    for dx in (0.0, 0.01, 0.05, 0.1, 0.19):
        x, y = extra_position({**p, "xs": 0.3 + dx})
        assert np.hypot(x - 0.3, y - 0.4) >= 0.1 - 1e-12                # R = sqrt(alpha t) = 0.1
    assert extra_position({**p, "xs": 0.55}) == (0.55, 0.4)


def test_ambient_level_fitted():
    xy = _grid()
    truth = make_model("heat2d", {**BASE, "ambient": 1.0, "T_amb": 20.0})
    res = explain("heat2d", xy, _noisy(truth, xy, seed=2), params={"sources": SRC, "ambient": 1.0})
    assert res.effects == [] and res.disturbances == []
    lo, hi = res.final_intervals["T_amb"]
    assert lo < 20.0 < hi


def test_continuous_sources_recover_alpha():
    xy = _grid()
    truth = make_model("heat2d", {**BASE, "continuous": 1.0, "alpha": 0.02})
    res = explain("heat2d", xy, _noisy(truth, xy, noise=0.05, seed=3), params={"sources": SRC, "continuous": 1.0})
    assert res.effects == []
    assert abs(res.final_fit.params["alpha"] - 0.02) < 0.002


def _frames_npz(path, *, extra=None, n=16, times=(0.5, 1.0, 1.5), seed=4):
    g = np.linspace(0, 1, n)
    X, Y = np.meshgrid(g, g)
    xy = np.column_stack([X.ravel(), Y.ravel()])
    rng = np.random.default_rng(seed)
    z = []
    for tf in times:
        m = make_model("heat2d", {**BASE, "t": tf})
        if extra:
            m = m.with_effect("extra_source", extra)
        z.append((m.predict(xy) + 0.03 * rng.normal(size=len(xy))).reshape(n, n))
    np.savez(path, x=g, y=g, z=np.array(z), t=np.array(times))


def test_frames_read_and_fitted_over_time(tmp_path, capsys):
    path = tmp_path / "frames.npz"
    _frames_npz(path, extra={"xs": 0.5, "ys": 0.85, "S_extra": 0.4})
    xy, z, info = read_npz(path)
    assert info["frames"] == 3 and info["frame_dt"] == 0.5 and len(z) == 3 * 256
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(path), "--model", "heat2d", "--param", f"sources={SRC}",
                 "--effects", "extra_source,source_moved", "--report", str(rep), "--quiet"]) == 0
    import json
    d = json.loads(rep.read_text())
    assert d["verdict"]["effect"] == "extra_source"
    assert abs(d["verdict"]["parameters"]["xs"] - 0.5) < 0.03       # frame-0 coordinates


def test_frames_bad_times_one_line(tmp_path):
    g = np.linspace(0, 1, 5)
    np.savez(tmp_path / "a.npz", x=g, y=g, z=np.zeros((2, 5, 5)))
    with pytest.raises(FormatError, match="has 2 frames .* but no array t of frame times"):
        read_npz(tmp_path / "a.npz")
    np.savez(tmp_path / "b.npz", x=g, y=g, z=np.zeros((3, 5, 5)), t=np.array([1.0, 2.0, 4.0]))
    with pytest.raises(FormatError, match="evenly spaced"):
        read_npz(tmp_path / "b.npz")
