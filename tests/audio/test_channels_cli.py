"""``odnn-sep denoise --picks/--spatial`` on multichannel files: exit codes, untouched channels,
atomic output, reports (odnn_sep/audio/channels_file.py)."""
from __future__ import annotations

import json
import os

import numpy as np
import pytest
import soundfile as sf

from odnn_sep.cli import main


@pytest.fixture(scope="module")
def multi(tmp_path_factory):
    d = tmp_path_factory.mktemp("multi")
    sr, n = 2000, 2000 * 12
    t = np.arange(n) / sr
    rng = np.random.default_rng(5)
    hum = np.cos(2 * np.pi * 50.03 * t) + 0.4 * np.cos(2 * np.pi * 100.06 * t + 1)
    y = 0.05 * rng.standard_normal((n, 3)) + 0.1 * hum[:, None] * np.array([1.0, 0.7, 0.4])
    p = d / "three.wav"
    sf.write(p, y, sr, subtype="PCM_24")
    mono = d / "mono.wav"
    sf.write(mono, y[:, 0], sr, subtype="PCM_16")
    return d, p, mono


def _only(d, *names):
    assert sorted(os.listdir(d)) == sorted(names)


def test_picks_leave_other_channels_bit_exact(multi, tmp_path, capsys):
    _, p, _ = multi
    out, rep = tmp_path / "o.wav", tmp_path / "r.json"
    assert main(["denoise", str(p), "-o", str(out), "--picks", "0,2", "--report", str(rep)]) == 0
    assert "removed hum on channel(s) [0, 2]" in capsys.readouterr().out
    a, _ = sf.read(p, dtype="int32")
    b, _ = sf.read(out, dtype="int32")
    assert sf.info(str(out)).subtype == "PCM_24" and b.shape == a.shape
    assert np.array_equal(a[:, 1], b[:, 1]) and not np.array_equal(a[:, 0], b[:, 0])
    r = json.loads(rep.read_text())
    assert r["schema"] == "odnn-sep/denoise" and r["picks"] == [0, 2] and r["channels"] == 3
    assert {ln["channel"] for ln in r["lines"]} == {0, 2}
    _only(tmp_path, "o.wav", "r.json")


def test_spatial_on_a_multichannel_file(multi, tmp_path, capsys):
    _, p, _ = multi
    out = tmp_path / "o.flac"
    assert main(["denoise", str(p), "-o", str(out), "--spatial"]) == 0
    assert "spatial component(s): fundamental 50.0" in capsys.readouterr().out
    y, sr = sf.read(out)
    x, _ = sf.read(p)
    f = np.fft.rfftfreq(len(x), 1 / sr)
    band = np.abs(f - 50.03) < 0.5
    before = np.sum(np.abs(np.fft.rfft(x, axis=0)[band]) ** 2)
    after = np.sum(np.abs(np.fft.rfft(y, axis=0)[band]) ** 2)
    assert after < 0.01 * before


@pytest.mark.parametrize("extra, msg", [
    (["--spatial"], "--spatial needs a file with several channels sharing the hum"),
    (["--picks", "3"], "picks index 3 is out of range for 1 channel(s)"),
    (["--picks", "a,b"], "--picks must be comma-separated channel indices such as 0,2; got 'a,b'"),
    (["--picks", "0", "--plot", "p.png"], "--plot is not available with --picks/--spatial"),
])
def test_errors_exit_1_and_leave_nothing(multi, tmp_path, capsys, extra, msg):
    _, _, mono = multi
    extra = [str(tmp_path / e) if e.endswith(".png") else e for e in extra]
    assert main(["denoise", str(mono), "-o", str(tmp_path / "o.wav"), *extra]) == 1
    err = capsys.readouterr().err
    assert msg in err and len(err.strip().splitlines()) == 1
    _only(tmp_path)


def test_in_memory_limit(multi, tmp_path, capsys, monkeypatch):
    _, p, _ = multi
    monkeypatch.setenv("ODNN_SEP_MAX_IN_MEMORY_SAMPLES", "1000")
    assert main(["denoise", str(p), "-o", str(tmp_path / "o.wav"), "--spatial"]) == 1
    assert "ODNN_SEP_MAX_IN_MEMORY_SAMPLES" in capsys.readouterr().err
    _only(tmp_path)
