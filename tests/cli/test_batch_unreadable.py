"""Files of a batch folder that match the pattern but cannot be read: named, not left out without a word.

A broken link (a git-annex or DataLad file whose content was never fetched) or a pipe named ``*.wav``
was skipped silently: the console said "2 of 2 file(s) processed" and the summary did not list it. A
folder of unreadable files printed one console line per file (10 000 lines); the summary keeps them all.
"""
import json
import os

import numpy as np
import pytest
import soundfile as sf

from odnn_sep.cli import main


def _wav(path):
    sr = 8000
    t = np.arange(2 * sr) / sr
    sf.write(path, 0.02 * np.random.default_rng(0).normal(size=t.size) + 0.05 * np.sin(2 * np.pi * 50 * t), sr)


def test_broken_link_and_pipe_are_reported(tmp_path, capsys):
    src = tmp_path / "in"
    src.mkdir()
    _wav(src / "take.wav")
    os.symlink("never-fetched.wav", src / "annexed.wav")
    os.mkfifo(src / "pipe.wav")
    assert main(["batch", "denoise", str(src), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 1
    err = capsys.readouterr().err
    assert "1 of 3 file(s) processed" in err
    assert "is a broken link (its target 'never-fetched.wav' does not exist); not processed" in err
    res = {os.path.basename(r["input"]): r for r in
           json.loads((tmp_path / "out" / "batch_summary.json").read_text())["results"]}
    assert res["take.wav"]["exit_code"] == 0
    assert res["annexed.wav"]["exit_code"] == 1 and res["annexed.wav"]["output"] is None
    assert "is not a regular file" in res["pipe.wav"]["message"]
    assert sorted(os.listdir(tmp_path / "out")) == ["batch_summary.json", "take.wav"]


def test_only_broken_links_named_in_the_error(tmp_path, capsys):
    src = tmp_path / "in"
    src.mkdir()
    for k in range(3):
        os.symlink(f"gone{k}.wav", src / f"a{k}.wav")
    assert main(["batch", "denoise", str(src), "-o", str(tmp_path / "out")]) == 1
    err = capsys.readouterr().err.strip()
    assert "is a broken link (its target 'gone0.wav' does not exist), and 2 more like it" in err
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("n", [25])
def test_console_lists_at_most_twenty_failures(tmp_path, capsys, n):
    src = tmp_path / "in"
    src.mkdir()
    for k in range(n):
        (src / f"f{k:02d}.wav").write_bytes(b"x")
    assert main(["batch", "denoise", str(src), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 1
    lines = capsys.readouterr().err.splitlines()
    assert sum(ln.startswith("  failed: ") for ln in lines) == 20
    assert f"  ... and {n - 20} more failed file(s); see the summary" in lines
    assert len(json.loads((tmp_path / "out" / "batch_summary.json").read_text())["results"]) == n
