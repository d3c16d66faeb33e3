"""``odnn-sep denoise`` end to end: files, formats, report/plot, and every user error (exit 1)."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import numpy as np
import pytest
import soundfile as sf

from odnn_sep.audio import make_hum_mix
from odnn_sep.cli import main


@pytest.fixture(scope="module")
def wavs(tmp_path_factory):
    d = tmp_path_factory.mktemp("audio")
    y, sr, truth = make_hum_mix(8.0, 8000, channels=2, snr_db=3.0, random_state=21)
    p16 = d / "stereo16.wav"
    sf.write(p16, y, sr, subtype="PCM_16")
    p24 = d / "mono24.flac"
    sf.write(p24, y[:, 0], sr, subtype="PCM_24")
    pf = d / "float.wav"
    sf.write(pf, y[:, 0].astype(np.float32), sr, subtype="FLOAT")
    return d, {"pcm16": p16, "flac24": p24, "float": pf}


def _only(d, *names):
    """No temporary or partial files left next to the outputs."""
    assert sorted(os.listdir(d)) == sorted(names)


@pytest.mark.parametrize("key, subtype, channels", [("pcm16", "PCM_16", 2), ("flac24", "PCM_24", 1),
                                                    ("float", "FLOAT", 1)])
def test_keeps_rate_channels_subtype(wavs, tmp_path, key, subtype, channels):
    _, files = wavs
    src = files[key]
    out = tmp_path / ("out" + src.suffix)
    assert main(["denoise", str(src), "-o", str(out), "--quiet"]) == 0
    info_in, info_out = sf.info(str(src)), sf.info(str(out))
    assert (info_out.samplerate, info_out.channels, info_out.subtype) == (8000, channels, subtype)
    assert info_out.frames == info_in.frames
    _only(tmp_path, out.name)


def test_report_and_plot(wavs, tmp_path, capsys):
    _, files = wavs
    out, rep, png = tmp_path / "o.wav", tmp_path / "r.json", tmp_path / "p.png"
    rc = main(["denoise", str(files["pcm16"]), "-o", str(out), "--report", str(rep), "--plot", str(png),
               "--mains", "50", "--tone", "1234"])
    assert rc == 0
    assert "removed hum: fundamental" in capsys.readouterr().out
    r = json.loads(rep.read_text())
    assert r["mains"]["nominal_hz"] == 50.0 and r["channels"] == 2 and r["subtype"] == "PCM_16"
    assert len(r["track"]["time_s"]) == len(r["track"]["freq_hz"]) > 0
    h1 = r["lines"][0]
    assert h1["name"] == "h1" and len(h1["amplitude_peak"]["median"]) == 2
    assert len(h1["amplitude_peak"]["per_block"]) == len(r["track"]["time_s"])
    assert len(h1["phase_rad"]["per_block"][0]) == 2
    lb, la = h1["level_above_floor_db"]["before"], h1["level_above_floor_db"]["after"]
    assert min(lb) > 15 and max(la) < 3
    assert r["tones_hz"] and r["lines"][-1]["name"].startswith("tone_")
    assert png.stat().st_size > 10000
    _only(tmp_path, "o.wav", "r.json", "p.png")


def test_clipping_is_reported(tmp_path, capsys):
    sr = 8000
    t = np.arange(6 * sr) / sr
    hum = 0.25 * np.cos(2 * np.pi * 50 * t)
    y = hum.copy()
    # a few clicks that reach full scale once the hum under them (at its minimum) is removed
    for n in (37, 101, 180, 233):
        i = int(round((n + 0.5) / 50 * sr))
        y[i] = 1.05 - 0.25
    src = tmp_path / "clip.wav"
    sf.write(src, y, sr, subtype="PCM_16")
    assert main(["denoise", str(src), "-o", str(tmp_path / "o.wav"), "--quiet"]) == 0
    err = capsys.readouterr().err
    assert "Warning: output clipped: 4 sample(s) exceeded full scale by up to 0.4" in err


def _err(capsys):
    return capsys.readouterr().err.strip()


def test_missing_input(tmp_path, capsys):
    assert main(["denoise", str(tmp_path / "nope.wav"), "-o", str(tmp_path / "o.wav")]) == 1
    assert _err(capsys) == f"Error: input audio file {str(tmp_path / 'nope.wav')!r} does not exist; check the path"
    _only(tmp_path)


def test_empty_input(tmp_path, capsys):
    p = tmp_path / "empty.wav"
    p.write_bytes(b"")
    assert main(["denoise", str(p), "-o", str(tmp_path / "o.wav")]) == 1
    assert _err(capsys) == f"Error: input audio file {str(p)!r} is empty (0 bytes)"
    _only(tmp_path, "empty.wav")


def test_corrupt_and_unsupported_input(tmp_path, capsys):
    p = tmp_path / "bad.wav"
    p.write_bytes(b"RIFF\x00\x00\x00\x00WAVEjunkjunkjunk" * 10)
    assert main(["denoise", str(p), "-o", str(tmp_path / "o.wav")]) == 1
    assert _err(capsys).startswith(f"Error: could not read input audio file {str(p)!r}: ")
    q = tmp_path / "notes.txt"
    q.write_text("not audio at all\n")
    assert main(["denoise", str(q), "-o", str(tmp_path / "o.wav")]) == 1
    e = _err(capsys)
    assert e.startswith(f"Error: could not read input audio file {str(q)!r}: ") and "supported formats: WAV" in e
    _only(tmp_path, "bad.wav", "notes.txt")


def test_truncated_input(wavs, tmp_path, capsys):
    _, files = wavs
    p = tmp_path / "trunc.wav"
    p.write_bytes(files["pcm16"].read_bytes()[: 40000])
    rc = main(["denoise", str(p), "-o", str(tmp_path / "o.wav")])
    e = _err(capsys)
    # libsndfile either reports the short data chunk or reads what is there; never a partial output
    if rc == 1:
        assert e.startswith("Error: ")
        _only(tmp_path, "trunc.wav")
    else:
        assert rc == 0


def test_mains_above_nyquist(wavs, tmp_path, capsys):
    _, files = wavs
    assert main(["denoise", str(files["pcm16"]), "-o", str(tmp_path / "o.wav"), "--mains", "4500"]) == 1
    assert _err(capsys) == ("Error: mains=4500 Hz is at or above the Nyquist frequency (4000 Hz for sr=8000); "
                            "choose a fundamental below 4000 Hz")
    _only(tmp_path)


def test_nan_samples(tmp_path, capsys):
    y = np.zeros(16000, dtype=np.float32)
    y[1234] = np.nan
    p = tmp_path / "nan.wav"
    sf.write(p, y, 8000, subtype="FLOAT")
    assert main(["denoise", str(p), "-o", str(tmp_path / "o.wav")]) == 1
    assert _err(capsys) == (f"Error: input audio file {str(p)!r} contains NaN samples (first at frame 1234, "
                            f"channel 0); repair the file before denoising")
    _only(tmp_path, "nan.wav")


def test_output_equal_to_input(wavs, capsys):
    _, files = wavs
    p = files["pcm16"]
    before = p.read_bytes()
    assert main(["denoise", str(p), "-o", str(p)]) == 1
    assert _err(capsys) == f"Error: output path {str(p)!r} is the input file; choose a different output path"
    assert p.read_bytes() == before


def test_unwritable_output_dir(wavs, tmp_path, capsys):
    _, files = wavs
    ro = tmp_path / "ro"
    ro.mkdir()
    ro.chmod(0o500)
    try:
        if os.access(ro, os.W_OK):
            pytest.skip("running as a user who can write to read-only directories")
        assert main(["denoise", str(files["pcm16"]), "-o", str(ro / "o.wav")]) == 1
        assert _err(capsys) == (f"Error: output directory {str(ro)!r} is not writable; "
                                f"choose another output path")
    finally:
        ro.chmod(0o700)
    assert os.listdir(ro) == []


def test_missing_output_dir(wavs, tmp_path, capsys):
    _, files = wavs
    missing = tmp_path / "missing" / "o.wav"
    assert main(["denoise", str(files["pcm16"]), "-o", str(missing)]) == 1
    assert _err(capsys) == f"Error: output directory {str(missing.parent)!r} does not exist; create it first"
    _only(tmp_path)


def test_unsupported_output_extension(wavs, tmp_path, capsys):
    _, files = wavs
    assert main(["denoise", str(files["pcm16"]), "-o", str(tmp_path / "o.xyz")]) == 1
    assert _err(capsys) == (f"Error: output file {str(tmp_path / 'o.xyz')!r} has an unsupported extension "
                            f"'.xyz'; use .wav, .flac, .ogg, .aiff or .mp3")
    _only(tmp_path)


def test_command_module_is_light():
    code = ("import sys, odnn_sep.audio.command; "
            "assert 'scipy' not in sys.modules and 'torch' not in sys.modules")
    subprocess.run([sys.executable, "-c", code], check=True)


def test_help_lists_options(capsys):
    with pytest.raises(SystemExit) as e:
        main(["denoise", "--help"])
    assert e.value.code == 0
    out = capsys.readouterr().out
    for opt in ("--mains", "--harmonics", "--tone", "--report", "--plot", "--quiet", "--solver"):
        assert opt in out


def test_ogg_vorbis_roundtrip(tmp_path):
    y, sr, _ = make_hum_mix(6.0, 8000, snr_db=3.0, random_state=22)
    src = tmp_path / "in.ogg"
    sf.write(src, y, sr, format="OGG", subtype="VORBIS")
    out = tmp_path / "out.ogg"
    assert main(["denoise", str(src), "-o", str(out), "--quiet"]) == 0
    info = sf.info(str(out))
    assert (info.samplerate, info.channels, info.subtype) == (8000, 1, "VORBIS")


@pytest.mark.parametrize("rate,channels", [(96000, 1), (44100, 6)])
def test_mp3_output_it_cannot_hold_is_refused_before_any_work(tmp_path, capsys, rate, channels):
    import soundfile as sf

    if "MP3" not in sf.available_formats():
        pytest.skip("this libsndfile cannot write MP3")
    wav = tmp_path / "in.wav"
    sf.write(wav, np.zeros((rate // 2, channels)), rate)
    out = tmp_path / "out.mp3"
    assert main(["denoise", str(wav), "-o", str(out)]) != 0
    err = capsys.readouterr().err
    assert "MP3 format cannot hold" in err and ".wav or .flac" in err and "Traceback" not in err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["in.wav"]


def test_tones_limited_and_merged(tmp_path, capsys):
    from odnn_sep.audio.options import parse_tones

    assert parse_tones([440, "440", 1000.0], 8000) == [440.0, 1000.0]
    wav = tmp_path / "in.wav"
    sf.write(wav, np.zeros(8000), 8000)
    args = ["denoise", str(wav), "-o", str(tmp_path / "out.wav")]
    for k in range(101):
        args += ["--tone", str(100 + 10 * k)]
    assert main(args) != 0
    assert "above the limit of 100" in capsys.readouterr().err
    assert not (tmp_path / "out.wav").exists()


def test_8bit_output_has_no_half_step_shift(tmp_path):
    sr = 8000
    t = np.arange(6 * sr) / sr
    y = 0.05 * np.random.default_rng(0).standard_normal(t.size) + 0.1 * np.sin(2 * np.pi * 50 * t)
    wav = tmp_path / "u8.wav"
    sf.write(wav, y, sr, subtype="PCM_U8")
    x, _ = sf.read(wav)
    assert main(["denoise", str(wav), "-o", str(tmp_path / "o.wav"), "--quiet"]) == 0
    o, _ = sf.read(tmp_path / "o.wav")
    assert sf.info(tmp_path / "o.wav").subtype == "PCM_U8"
    assert abs(o.mean() - x.mean()) * 128 < 0.1          # was -0.5 step (libsndfile truncates 8-bit)
