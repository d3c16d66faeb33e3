"""The thin CLI: version, help without torch, usage errors, batch over a folder."""
import json
import subprocess
import sys

import pytest

from odnn_sep.cli import main


def test_version_and_help_do_not_import_torch():
    code = ("import sys; from odnn_sep.cli import main\n"
            "try:\n    main(['--help'])\nexcept SystemExit:\n    pass\n"
            "print('torch' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip().endswith("False")
    v = subprocess.run([sys.executable, "-m", "odnn_sep.cli", "--version"], capture_output=True, text=True)
    assert v.returncode == 0 and v.stdout.startswith("odnn-sep ")


def test_no_command_is_usage_error(capsys):
    assert main([]) == 2


def test_unknown_command_exits_2():
    with pytest.raises(SystemExit) as e:
        main(["frobnicate"])
    assert e.value.code == 2


def test_batch_missing_folder(tmp_path, capsys):
    assert main(["batch", "denoise", str(tmp_path / "nope"), "-o", str(tmp_path / "out")]) == 1
    assert "input folder" in capsys.readouterr().err


def test_batch_refuses_output_equal_to_input(tmp_path, capsys):
    (tmp_path / "a.wav").write_bytes(b"x")
    assert main(["batch", "denoise", str(tmp_path), "-o", str(tmp_path)]) == 1
    assert "output folder is the input folder" in capsys.readouterr().err


def test_batch_reports_each_file_and_continues(tmp_path, capsys):
    pytest.importorskip("odnn_sep.audio.command")
    src = tmp_path / "in"
    src.mkdir()
    (src / "broken.wav").write_bytes(b"not a wav file at all")
    (src / "empty.wav").write_bytes(b"")
    code = main(["batch", "denoise", str(src), "-o", str(tmp_path / "out"), "--jobs", "1"])
    assert code == 1
    summary = json.loads((tmp_path / "out" / "batch_summary.json").read_text())
    assert summary["files"] == 2 and summary["failed"] == 2
    assert all(r["exit_code"] == 1 and r["message"].startswith("Error:") for r in summary["results"])
    assert not (tmp_path / "out" / "broken.wav").exists()


def _two_hum_files(folder):
    import numpy as np
    import soundfile as sf

    folder.mkdir()
    sr = 8000
    t = np.arange(4 * sr) / sr
    rng = np.random.default_rng(0)
    for k in range(2):
        y = 0.1 * rng.normal(size=t.size) + 0.2 * np.sin(2 * np.pi * 50.02 * t + k)
        sf.write(folder / f"take{k}.wav", y, sr, subtype="PCM_16")


@pytest.mark.parametrize("runner", [["--jobs", "2"], ["--dask", "local", "--jobs", "2"]])
def test_batch_processes_folder(tmp_path, runner):
    pytest.importorskip("odnn_sep.audio.command")
    if "--dask" in runner:
        pytest.importorskip("dask.distributed")
    _two_hum_files(tmp_path / "in")
    code = main(["batch", "denoise", str(tmp_path / "in"), "-o", str(tmp_path / "out"), *runner, "--", "--mains", "50"])
    assert code == 0
    summary = json.loads((tmp_path / "out" / "batch_summary.json").read_text())
    assert summary["failed"] == 0 and summary["files"] == 2
    assert (tmp_path / "out" / "take0.wav").exists() and (tmp_path / "out" / "take1.wav").exists()
