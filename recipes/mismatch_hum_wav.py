"""Write a long hum recording for timing `odnn-sep mismatch --model hum` (and print the truth).

The case the hum preset used to get wrong: a weak fundamental (60 Hz) under strong 2nd and 3rd
harmonics (120 and 180 Hz), the mains frequency drifting slowly, a speech-like host and noise,
60 s at 16 kHz by default. Optionally a second channel whose non-hum content leaks into the first
(``--coupling``).

    python recipes/mismatch_hum_wav.py /tmp/hum60.wav
    python -m odnn_sep.cli mismatch --model hum --param f0=60 /tmp/hum60.wav
"""
from __future__ import annotations

import argparse

import numpy as np


def hum_recording(*, seconds=60.0, sr=16000, mains_hz=60.0, amps=(0.01, 0.1, 0.08), drift_hz=0.04,
                  drift_period_s=0.0, noise=0.02, host=0.05, coupling=None, seed=0):
    """(y, sr, truth): an (n,) float32 hum recording (n, 2 with ``coupling``) and what is in it.

    Examples
    --------
    >>> y, sr, truth = hum_recording(seconds=1.0, sr=4000)
    >>> y.shape, sr, truth["mains_hz"]
    ((4000,), 4000, 60.0)
    """
    rng = np.random.default_rng(seed)
    n = int(round(seconds * sr))
    t = np.arange(n) / sr
    if drift_period_s:
        # slow sinusoidal wander of the grid frequency around the nominal value
        f = mains_hz + drift_hz * np.sin(2 * np.pi * t / drift_period_s + rng.uniform(0, 2 * np.pi))
    else:
        # a slow linear drift by drift_hz over the record
        f = mains_hz + drift_hz * (t / seconds - 0.5)
    phase = 2 * np.pi * np.cumsum(f) / sr
    y = np.zeros(n)
    for k, a in enumerate(amps, start=1):
        y += a * np.cos(k * phase + rng.uniform(0, 2 * np.pi))
    y += noise * rng.normal(size=n) + host * _speech_like(t, sr, rng)
    truth = {"mains_hz": mains_hz, "amps": list(amps), "drift_hz": drift_hz, "drift_period_s": drift_period_s,
             "coupling": coupling}
    if coupling is not None:
        other = _speech_like(t, sr, rng) + 0.5 * np.cos(phase + 1.0) + noise * rng.normal(size=n)
        y = y + coupling * other
        return np.column_stack([y, other]).astype(np.float32), sr, truth
    return y.astype(np.float32), sr, truth


def _speech_like(t, sr, rng):
    from scipy.signal import butter, sosfiltfilt
    s = sosfiltfilt(butter(4, [80, min(3000, 0.4 * sr)], btype="band", fs=sr, output="sos"), rng.normal(size=len(t)))
    s = s * np.clip(np.sin(2 * np.pi * 3.1 * t + rng.uniform(0, 2 * np.pi)), 0, None) ** 2
    return s / np.std(s)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", help="WAV file to write")
    ap.add_argument("--seconds", type=float, default=60.0)
    ap.add_argument("--sr", type=int, default=16000)
    ap.add_argument("--mains", type=float, default=60.0)
    ap.add_argument("--coupling", type=float, default=None,
                    help="write a second channel whose content leaks into channel 1 with this gain (0: a null twin)")
    ap.add_argument("--no-drift", action="store_true")
    ap.add_argument("--wander-period", type=float, default=0.0,
                    help="sinusoidal wander of this period (s) instead of a linear drift")
    ap.add_argument("--seed", type=int, default=0)
    a = ap.parse_args(argv)
    import soundfile as sf
    y, sr, truth = hum_recording(seconds=a.seconds, sr=a.sr, mains_hz=a.mains, coupling=a.coupling,
                                 drift_hz=0.0 if a.no_drift else 0.04, drift_period_s=a.wander_period, seed=a.seed)
    sf.write(a.out, y, sr, subtype="FLOAT")
    print(truth)


if __name__ == "__main__":
    main()
