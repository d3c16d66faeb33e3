"""channel_coupling: crosstalk from another channel's non-hum content into the analysed hum channel."""
import json

import numpy as np
import pytest
from scipy.signal import butter, sosfiltfilt

from odnn_sep.cli import main
from odnn_sep.errors import InputError
from odnn_sep.mismatch import explain, make_model
from odnn_sep.mismatch.coupling import hum_free

SR = 1000
N = 2 * SR
T = np.arange(N) / SR


def _speech(rng, scale=0.3):
    """Speech-like content: band-passed noise under a syllable-rate (3 Hz) envelope."""
    x = sosfiltfilt(butter(4, [100, 450], btype="band", fs=SR, output="sos"), rng.normal(size=N))
    env = np.clip(np.sin(2 * np.pi * 3.1 * T + rng.uniform(0, 6)), 0, None) ** 2
    x = x * env
    return scale * x / np.std(x)


def _pair(seed, *, kappa, same_hum=True):
    """Channel A: own hum + noise (+ kappa x channel B). Channel B: hum + speech + noise."""
    rng = np.random.default_rng(seed)
    f_b = 50.03 if same_hum else 49.96
    b = 0.4 * np.sin(2 * np.pi * f_b * T + 1.1) + _speech(rng) + 0.01 * rng.normal(size=N)
    a = 0.5 * np.sin(2 * np.pi * 50.03 * T + 0.3) + 0.01 * rng.normal(size=N) + kappa * b
    return a, b


def test_coupling_detected_named_and_gain_recovered():
    a, b = _pair(0, kappa=0.05)
    res = explain("hum", T, a, params={"f0": 50.0}, aux={"B": b})
    assert res.effect == "channel_coupling"
    p = res.verdict.effect_params
    assert set(p) == {"kappa_B", "kappaq_B"}
    assert abs(p["kappa_B"] - 0.05) < 0.15 * 0.05
    assert abs(p["kappaq_B"]) < 0.15 * 0.05
    d = res.as_dict()
    assert d["verdict"]["effect"] == "channel_coupling"
    # the coupled content (rms 0.015) is gone: what is left is the 0.01 noise
    assert d["fit"]["after"]["residual_rms"] < 0.011 < 0.015 < d["fit"]["before"]["residual_rms"]
    lo, hi = d["verdict"]["intervals"]["kappa_B"]
    assert lo < 0.05 < hi


@pytest.mark.parametrize("same_hum", [True, False])
def test_null_twin_not_flagged(same_hum):
    # independent channels; with the same mains hum on both, B's raw hum would be collinear with
    # A's hum basis: the coupling regressor is B with its hum removed, so it must not be named
    a, b = _pair(1, kappa=0.0, same_hum=same_hum)
    res = explain("hum", T, a, params={"f0": 50.0}, aux={"B": b})
    assert res.effect is None
    c = next(c for c in res.candidates if c.effect == "channel_coupling")
    assert c.score < 10.0


def test_shared_hum_mismatch_is_not_taken_for_coupling():
    # both channels share a drifting mains frequency and a 3rd harmonic the model leaves out: what
    # the fitted hum leaves behind in B correlates with A's own hum mismatch; the band-stop around
    # the harmonics keeps it out of the coupling regressor, so A's verdict stays a hum effect
    rng = np.random.default_rng(5)
    ma = make_model("hum", {"f0": 50.0, "a1": 0.5, "b1": 0.2}).with_effect("frequency_drift", {"f1": 0.1})
    mb = make_model("hum", {"f0": 50.0, "a1": 0.3, "b1": -0.3}).with_effect("frequency_drift", {"f1": 0.1})
    a = ma.predict(T) + 0.05 * np.cos(2 * np.pi * 150 * T) + 0.01 * rng.normal(size=N)
    b = mb.predict(T) + 0.04 * np.cos(2 * np.pi * 150 * T + 1) + 0.01 * rng.normal(size=N)
    res = explain("hum", T, a, params={"f0": 50.0}, aux={"B": b})
    assert res.effect in ("frequency_drift", "missing_harmonic")
    c = next(c for c in res.candidates if c.effect == "channel_coupling")
    assert c.score < 10.0


def test_hum_free_removes_hum_and_keeps_content():
    rng = np.random.default_rng(2)
    s = _speech(rng)
    hum = 0.8 * np.sin(2 * np.pi * 50.02 * T) + 0.2 * np.cos(2 * np.pi * 150.06 * T)
    c, q = hum_free(T, hum + s, f0=50.0, harmonics=1)
    # what is left correlates with the content, not with the hum (3rd harmonic included)
    assert abs(np.dot(c, hum)) / (np.linalg.norm(c) * np.linalg.norm(hum)) < 0.02
    assert np.dot(c, s) / (np.linalg.norm(c) * np.linalg.norm(s)) > 0.97
    # the quadrature is the Hilbert transform: orthogonal to the in-phase part, same energy
    assert abs(np.dot(c, q)) / np.dot(c, c) < 0.02
    assert np.linalg.norm(q) == pytest.approx(np.linalg.norm(c), rel=0.05)


def test_coupling_needs_aux_and_hum():
    a, b = _pair(3, kappa=0.0)
    with pytest.raises(InputError, match="effect 'channel_coupling' needs the recording's other channels"):
        explain("hum", T, a, params={"f0": 50.0}, effects=["channel_coupling"])
    with pytest.raises(InputError, match=r"aux\['B'\] has 10 samples but y has 2000"):
        explain("hum", T, a, params={"f0": 50.0}, aux={"B": b[:10]})
    with pytest.raises(InputError, match="aux channels are used by the channel_coupling effect of the 'hum'"):
        explain("cooling", T, 20 + 50 * np.exp(-T), aux={"B": b})
    with pytest.raises(InputError, match="channel_coupling needs the recording's other channels"):
        make_model("hum").with_effect("channel_coupling")
    # without aux the effect is simply not a candidate
    res = explain("hum", T, a, params={"f0": 50.0})
    assert "channel_coupling" not in [c.effect for c in res.candidates]


def test_cli_two_channel_wav(tmp_path):
    import soundfile as sf
    a, b = _pair(4, kappa=0.05)
    p = tmp_path / "two.wav"
    sf.write(p, np.column_stack([a, b]) / 2.0, SR, subtype="FLOAT")
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(p), "--model", "hum", "--param", "f0=50", "--column", "0", "--quiet",
                 "--report", str(rep)]) == 0
    d = json.loads(rep.read_text())
    assert d["input"]["aux_channels"] == ["ch1"]
    assert d["verdict"]["effect"] == "channel_coupling"
    assert abs(d["verdict"]["parameters"]["kappa_ch1"] - 0.05) < 0.15 * 0.05
    rep2 = tmp_path / "r2.json"
    assert main(["mismatch", str(p), "--model", "hum", "--param", "f0=50", "--column", "0", "--quiet",
                 "--no-aux", "--effects", "missing_harmonic", "--report", str(rep2)]) == 0
    d2 = json.loads(rep2.read_text())
    assert d2["input"]["aux_channels"] == []
    assert "channel_coupling" not in [c["effect"] for c in d2["candidates"]]


def test_csv_other_numeric_columns_become_aux(tmp_path):
    from odnn_sep.mismatch.io import load_data
    p = tmp_path / "m.csv"
    p.write_text("time,label,a,b\n" + "\n".join(f"{i / 10},x,{i},{2 * i}" for i in range(20)) + "\n")
    t, y, info, aux = load_data(p, column="a", with_aux=True, start=0.5)
    assert list(aux) == ["b"] and info["aux_channels"] == ["b"]
    assert np.allclose(aux["b"], 2 * y)
    assert len(load_data(p, column="a")) == 3


def test_candidate_factory_builds_the_coupling_model_without_starts():
    # the rival re-check rebuilds the final model effect by effect without starts; the coupling
    # effect (built from the aux channels) returned (model, starts) there and the run crashed
    from odnn_sep.mismatch.coupling import EFFECT
    from odnn_sep.mismatch.explain import _candidate_factory
    from odnn_sep.mismatch.fitting import fit

    a, b = _pair(2, kappa=0.05)
    cur = fit(make_model("hum", {"f0": 50.0}), T, a)
    factory = _candidate_factory(T, a, {"B": b}, None, 0.0)
    model = factory(EFFECT, cur, with_starts=False)
    assert "kappa_B" in model.start
    with_starts = factory(EFFECT, cur)
    assert isinstance(with_starts, tuple) and with_starts[0].start.keys() == model.start.keys()
