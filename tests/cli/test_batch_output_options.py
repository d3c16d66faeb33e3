"""Options after ``--`` that name an output file, and inputs whose output names meet.

Every file of a batch ran with the same options: ``-- --plot p.png`` had each file write the same
figure (one kept), ``-- -o x.wav`` sent every denoised file to x.wav while the summary listed outputs
in OUT_DIR that were never written. A figure or side report is now written per file beside its
output; options replacing the batch's own output are refused before anything runs. And ``a.csv``,
``a.wav`` and ``a.csv.npz`` were all planned, two of them to ``a.csv.json``.
"""
import json
from pathlib import Path

import numpy as np
import pytest
import soundfile as sf

from odnn_sep.batch import plan_outputs
from odnn_sep.cli import main


def _mugs(folder):
    folder.mkdir()
    t = np.arange(0, 300, 1.0)
    rng = np.random.default_rng(0)
    for name, h in (("a", 0.01), ("b", 0.02)):
        T = 20 + 60 * np.exp(-h * t) + rng.normal(0, 0.05, t.size)
        np.savetxt(folder / f"{name}.csv", np.c_[t, T], delimiter=",", header="t,T", comments="")


def test_mismatch_plot_per_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _mugs(tmp_path / "in")
    assert main(["batch", "mismatch", "in", "-o", "out", "--jobs", "1", "--quiet", "--",
                 "--model", "cooling", "--effects", "radiation", "--plot", "fig.png"]) == 0
    assert not (tmp_path / "fig.png").exists()
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [
        "a.json", "a.plot.png", "b.json", "b.plot.png", "batch_summary.json"]


@pytest.mark.parametrize("given", [["--report", "r.json"], ["--rep=r.json"]])
def test_mismatch_report_after_dashes_refused(tmp_path, monkeypatch, capsys, given):
    monkeypatch.chdir(tmp_path)
    _mugs(tmp_path / "in")
    assert main(["batch", "mismatch", "in", "-o", "out", "--", "--model", "cooling", *given]) == 1
    err = capsys.readouterr().err
    assert "would send every file's output to one path" in err and "r.json" in err
    assert not (tmp_path / "out").exists() and not (tmp_path / "r.json").exists()


def _hums(folder):
    folder.mkdir()
    sr = 8000
    t = np.arange(3 * sr) / sr
    for k, name in enumerate(("one.wav", "two.wav")):
        noise = 0.02 * np.random.default_rng(k).normal(size=t.size)
        sf.write(folder / name, noise + 0.05 * np.sin(2 * np.pi * 50 * t), sr, subtype="PCM_16")


def test_denoise_output_after_dashes_refused(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    _hums(tmp_path / "in")
    assert main(["batch", "denoise", "in", "-o", "out", "--", "-o", "x.wav"]) == 1
    assert "'-o x.wav' after --" in capsys.readouterr().err
    assert not (tmp_path / "x.wav").exists() and not (tmp_path / "out").exists()


def test_denoise_report_per_file(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    _hums(tmp_path / "in")
    assert main(["batch", "denoise", "in", "-o", "out", "--jobs", "1", "--quiet", "--", "--report", "r.json"]) == 0
    out = tmp_path / "out"
    assert not (tmp_path / "r.json").exists()
    for name in ("one", "two"):
        assert json.loads((out / f"{name}.wav.report.json").read_text())["lines"]
    summary = json.loads((out / "batch_summary.json").read_text())["results"]
    assert all(r["outcome"].startswith("removed hum") for r in summary), summary


def test_outputs_never_meet():
    files = [Path("in/a.csv"), Path("in/a.wav"), Path("in/a.csv.npz"), Path("in/a.csv.npz.csv")]
    dsts = [str(p) for p in plan_outputs(files, Path("in"), Path("out"), ".json")]
    assert len(set(dsts)) == len(dsts), dsts
