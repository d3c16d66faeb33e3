"""EEG/MEG input of ``denoise``: channels-first arrays with a float sfreq, MNE Raw, picks, and the
one-line errors (odnn_sep/audio/channels.py)."""
from __future__ import annotations

import numpy as np
import pytest

from odnn_sep.audio import DenoiseResult, denoise
from odnn_sep.audio.channel_picks import resolve_picks
from odnn_sep.errors import InputError

SFREQ = 512.5


def _eeg(n_ch=3, seconds=12.0, sfreq=SFREQ, seed=0, f_line=50.02):
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * sfreq)) / sfreq
    brain = rng.standard_normal((n_ch, t.size))
    gains = np.linspace(1.0, 0.4, n_ch)
    hum = gains[:, None] * (np.cos(2 * np.pi * f_line * t) + 0.5 * np.cos(2 * np.pi * 2 * f_line * t + 1.0))
    return brain + hum, brain, hum


def _line_reduction_db(out, brain, hum, sfreq=SFREQ, line=50.02):
    """Worst channel: hum power within +-0.6 Hz of the line over what is left there (dB)."""
    from scipy import signal

    out, brain, hum = (np.atleast_2d(np.asarray(a, float)) for a in (out, brain, hum))
    f, pe = signal.welch(out - brain, fs=sfreq, nperseg=int(4 * sfreq), axis=-1)
    _, ph = signal.welch(hum, fs=sfreq, nperseg=int(4 * sfreq), axis=-1)
    band = np.abs(f - line) <= 0.6
    return float(np.min(10 * np.log10(ph[:, band].sum(1) / pe[:, band].sum(1))))


def test_fractional_sfreq_array_keeps_shape_dtype_and_input():
    x, brain, hum = _eeg()
    x32 = x.astype(np.float32)
    before = x32.copy()
    out = denoise(x32, sfreq=SFREQ)
    assert isinstance(out, np.ndarray) and out.shape == x32.shape and out.dtype == np.float32
    assert np.array_equal(x32, before)                       # input untouched
    assert _line_reduction_db(out, brain, hum) > 12


def test_one_channel_and_samples_first_layouts():
    x, brain, hum = _eeg(n_ch=2)
    out1 = denoise(x[0], sfreq=SFREQ)
    assert out1.shape == x[0].shape and _line_reduction_db(out1, brain[0], hum[0]) > 12
    out_t = denoise(x.T, sfreq=SFREQ)                      # samples first comes back samples first
    assert out_t.shape == x.T.shape
    np.testing.assert_allclose(out_t.T, denoise(x, sfreq=SFREQ))


def test_picks_clean_only_those_channels_and_report():
    x, brain, hum = _eeg(n_ch=3)
    out, rep = denoise(x, sfreq=SFREQ, picks=[0, 2], return_report=True)
    assert np.array_equal(out[1], x[1])
    assert _line_reduction_db(out[[0, 2]], brain[[0, 2]], hum[[0, 2]]) > 12
    assert rep["picks"] == [0, 2] and len(rep["channels"]) == 2
    assert rep["channels"][0]["nominal_hz"] == 50.0 and 1 in rep["channels"][0]["harmonics"]
    assert abs(rep["channels"][0]["mains_hz"] - 50.02) < 0.01     # scaled back to the true rate


def test_integer_data_rounds_in_its_dtype():
    x, _, _ = _eeg(n_ch=2)
    xi = np.round(x * 1000).astype(np.int32)
    out = denoise(xi, sfreq=SFREQ)
    assert out.dtype == np.int32 and out.shape == xi.shape


def test_audio_call_is_unchanged():
    from odnn_sep.audio.synth import make_hum_demo

    y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    assert isinstance(denoise(y, sr), DenoiseResult)


@pytest.mark.parametrize("kw, msg", [
    ({"sfreq": 0}, r"sfreq must be a finite, positive sampling frequency in Hz; got 0"),
    ({"sfreq": -250.0}, r"sfreq must be a finite, positive sampling frequency in Hz; got -250.0"),
    ({"sfreq": float("nan")}, r"sfreq must be a finite, positive sampling frequency in Hz; got nan"),
    ({"sfreq": float("inf")}, r"sfreq must be a finite, positive sampling frequency in Hz; got inf"),
    ({"sfreq": "fast"}, r"sfreq must be a sampling frequency in Hz; got 'fast'"),
    ({"picks": [0]}, r"sfreq is missing: an EEG/MEG array needs its sampling frequency"),
    ({"sfreq": SFREQ, "picks": [5]}, r"picks index 5 is out of range for 3 channel\(s\)"),
    ({"sfreq": SFREQ, "picks": "Cz"}, r"picks 'Cz': an array has no channel names or types"),
    ({"sfreq": SFREQ, "picks": []}, r"picks=\[\] selects no channel"),
    ({"sfreq": SFREQ, "channel_axis": 2}, r"channel_axis must be 0 or 1"),
    ({"sfreq": SFREQ, "spatial": True, "picks": [1]}, r"spatial=True needs at least 2 channels"),
    ({"sfreq": SFREQ, "mains": 300}, r"mains=300 Hz is at or above the Nyquist frequency"),
    ({"sfreq": 250.0, "sr": 500}, r"sr=500 and sfreq=250.0 disagree"),
])
def test_errors(kw, msg):
    x, _, _ = _eeg(n_ch=3, seconds=2.0)
    sr = kw.pop("sr", None)
    with pytest.raises(InputError, match=msg):
        denoise(x, sr, **kw)


def test_more_errors(monkeypatch):
    x, _, _ = _eeg(n_ch=3, seconds=2.0)
    with pytest.raises(InputError, match=r"a square array does not say which axis holds the channels; "
                                         r"pass channel_axis=0"):
        denoise(np.zeros((64, 64)), sfreq=SFREQ)
    with pytest.raises(InputError, match=r"y must be a NumPy array or an MNE Raw; got dict"):
        denoise({"data": x}, sfreq=SFREQ)
    with pytest.raises(InputError, match=r"y must be a NumPy array or an MNE Raw; got str"):
        denoise("eeg.fif", 250)
    with pytest.raises(InputError, match=r"denoise needs the sampling rate: sr=\.\.\. for audio"):
        denoise(x)
    with pytest.raises(InputError, match=r"sr=512.5 is not an integer audio rate; .* pass sfreq=512.5"):
        denoise(x[0], 512.5)
    with pytest.raises(InputError, match=r"data must be 1-D \(one channel\) or 2-D"):
        denoise(np.zeros((2, 3, 1000)), sfreq=SFREQ)
    with pytest.raises(InputError, match=r"data must be real numbers"):
        denoise(x.astype(complex), sfreq=SFREQ)
    bad = x.copy()
    bad[1, 17] = np.nan
    with pytest.raises(InputError, match=r"channel 1 contains 1 NaN or inf value\(s\) \(first: NaN at sample 17\)"):
        denoise(bad, sfreq=SFREQ)
    bad[1, 17] = 0.0
    bad[2, 5:7] = np.nan
    denoise(bad, sfreq=SFREQ, picks=[0, 1])                   # NaN outside the picks is not read
    with pytest.raises(TypeError, match=r"unexpected keyword argument\(s\) 'spatail'"):
        denoise(x, sfreq=SFREQ, spatail=True)
    monkeypatch.setenv("ODNN_SEP_MAX_CHANNELS", "2")
    with pytest.raises(InputError, match=r"number of channels to clean is 3, above the limit of 2.*"
                                         r"ODNN_SEP_MAX_CHANNELS"):
        denoise(x, sfreq=SFREQ)


def test_too_short_in_the_users_rate():
    with pytest.raises(InputError, match=r"input is too short \(50 samples = 0.098 s at 512.5 Hz\)"):
        denoise(np.zeros((2, 50)), sfreq=SFREQ)


def _raw(x, sfreq, with_stim=True):
    mne = pytest.importorskip("mne", reason="the Raw tests need MNE (optional dependency)")
    names = [f"EEG{i}" for i in range(x.shape[0])] + (["STI"] if with_stim else [])
    types = ["eeg"] * x.shape[0] + (["stim"] if with_stim else [])
    data = np.vstack([x, np.zeros((1, x.shape[1]))]) if with_stim else x
    info = mne.create_info(names, sfreq, types)
    return mne.io.RawArray(data * 1e-6, info, verbose=False)   # volts, as MNE holds them


def test_raw_in_raw_out_info_untouched():
    x, brain, hum = _eeg(n_ch=3)
    raw = _raw(x, SFREQ)
    before = raw.get_data().copy()
    out = denoise(raw, picks=["EEG0", "EEG2"])
    assert type(out) is type(raw) and out is not raw
    assert out.info["sfreq"] == SFREQ and out.ch_names == raw.ch_names
    assert np.array_equal(raw.get_data(), before)                  # input untouched
    got = out.get_data() * 1e6
    assert np.array_equal(got[1], x[1] * 1e-6 * 1e6)                # not picked
    assert _line_reduction_db(got[[0, 2]], brain[[0, 2]], hum[[0, 2]]) > 12
    with pytest.raises(InputError, match=r"sfreq=250 differs from the Raw's own \(512.5 Hz\)"):
        denoise(raw, sfreq=250)
    raw._data[2, 40] = np.inf   # noqa: SLF001 - a broken recording
    with pytest.raises(InputError, match=r"channel 'EEG2' contains 1 NaN or inf value\(s\) \(first: inf at "
                                         r"sample 40\)"):
        denoise(raw, picks="eeg")
    with pytest.raises(InputError, match=r"picks 'misc' is neither a channel name .* nor a channel type present "
                                         r"\(eeg, stim\)"):
        denoise(raw, picks="misc")


def test_picks_match_mne():
    x, _, _ = _eeg(n_ch=3, seconds=1.0)
    raw = _raw(x, SFREQ)
    from mne._fiff.pick import _picks_to_idx

    for picks in (None, "eeg", "data", ["EEG2", "EEG0"], [3, 1], "all", slice(0, 2), "stim"):
        ours = resolve_picks(picks, len(raw.ch_names), raw.ch_names, raw.get_channel_types())
        theirs = np.sort(_picks_to_idx(raw.info, picks, exclude=()))
        assert ours.tolist() == theirs.tolist(), picks
    with pytest.raises(InputError, match=r"picks 'Fpz' is neither a channel name \(e.g. EEG0, EEG1"):
        resolve_picks("Fpz", 4, raw.ch_names, raw.get_channel_types())


def test_epochs_get_a_hint():
    mne = pytest.importorskip("mne", reason="needs MNE")
    x, _, _ = _eeg(n_ch=2, seconds=2.0)
    raw = _raw(x, SFREQ, with_stim=False)
    epochs = mne.make_fixed_length_epochs(raw, duration=0.5, verbose=False)
    with pytest.raises(InputError, match=r"got Epochs \(for MNE Epochs or Evoked, remove the hum from the "
                                         r"continuous Raw before epoching\)"):
        denoise(epochs)


def test_readme_eeg_example_runs():
    pytest.importorskip("mne", reason="the README's EEG example builds an MNE Raw")
    from pathlib import Path

    text = (Path(__file__).resolve().parents[2] / "README.md").read_text(encoding="utf-8")
    section = text[text.index("#### EEG / MEG (Python)"):]
    code = section[section.index("```python") + len("```python"): section.index("```", section.index("```python") + 9)]
    ns: dict = {}
    exec(compile(code, "README.md", "exec"), ns)   # noqa: S102 - our own README
    assert ns["report"]["spatial"]["components"]["harmonics"] == [1]
    assert type(ns["clean_raw"]) is type(ns["raw"]) and ns["clean"].shape == (8, 15_375)


def test_channel_axis_settles_a_square_array():
    sfreq = 250.0
    t = np.arange(300) / sfreq
    x = np.random.default_rng(3).standard_normal((300, 300)) + np.cos(2 * np.pi * 50 * t)[:, None]
    out = denoise(x, sfreq=sfreq, channel_axis=1, picks=[0], mains=50, harmonics=1)   # samples along axis 0
    assert out.shape == x.shape and np.array_equal(out[:, 1:], x[:, 1:])
    assert np.std(out[:, 0] - (x[:, 0] - np.cos(2 * np.pi * 50 * t))) < 0.5 * np.std(np.cos(2 * np.pi * 50 * t))
