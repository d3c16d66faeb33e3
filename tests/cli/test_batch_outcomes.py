"""The batch summary says what happened to each file: hum removed, nothing found, lossy output.

The commands run --quiet in a batch, which silenced their summary lines and warnings: a file with
no hum looked the same as one cleaned well.
"""
import json

import numpy as np
import soundfile as sf


def test_denoise_batch_outcomes(tmp_path, capsys):
    from odnn_sep.cli import main
    src = tmp_path / "in"
    src.mkdir()
    sr = 8000
    t = np.arange(10 * sr) / sr
    noise = 0.02 * np.random.default_rng(0).normal(size=t.size)
    sf.write(src / "hum.wav", noise + 0.05 * np.sin(2 * np.pi * 50 * t), sr, subtype="PCM_16")
    sf.write(src / "clean.wav", noise, sr, subtype="PCM_16")
    assert main(["batch", "denoise", str(src), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 0
    res = {r["input"].rsplit("/", 1)[-1]: r for r in
           json.loads((tmp_path / "out" / "batch_summary.json").read_text())["results"]}
    assert res["hum.wav"]["outcome"].startswith("removed hum: fundamental ") and "h1" in res["hum.wav"]["outcome"]
    assert res["clean.wav"]["outcome"] == "no hum found: written unchanged"
    assert "outcomes: " in capsys.readouterr().err
    assert not list((tmp_path / "out").glob("*.json.tmp*"))
