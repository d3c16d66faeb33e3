"""Disturbance kinds and two-effect cases for ``bench_mismatch.py``.

Every disturbance is drawn per case from its own random generator, with its nuisances (frequency,
phase, colour, spike rate, quantisation step) varied, at about the noise level:

- ``slow``: slow wander, 3 random sinusoids well below the physics (oscillatory systems only, as
  before: for slow physics a slow wander *is* the physics);
- ``periodic``: a pickup ``A cos(2 pi f t + phi)`` at a frequency unrelated to the system, random per
  case (never within 12 % of a harmonic of the system's own frequency); a spatial stripe for 2D fields;
- ``coloured``: AR(1) noise (phi 0.5-0.85) in place of part of the white noise;
- ``spikes``: 1-2 % of the samples get outliers of 6-15 noise levels;
- ``quantisation``: the recording is rounded to a step of 1-3 noise levels.
"""
from __future__ import annotations

import numpy as np

KINDS = ("slow", "periodic", "coloured", "spikes", "quantisation")

# a second effect per system for the two-effect cases: (effect, parameter, reference strength, extra);
# heat2d and freefall have no second effect the data can name: an offset is a disturbance, and a
# release-time offset of a body falling from rest is a drift plus a height offset
SECOND = {
    "oscillator/duffing": ("quadratic_drag", "q_drag", 0.05, {}),
    "oscillator/air_drag": ("cubic_stiffness", "beta", 0.2, {}),
    "pendulum/large_angle": ("quadratic_drag", "q_drag", 0.05, {}),
    "cooling/radiation": ("two_body_heat", "B_2", 1.0, {"lam_2": 0.2}),
    "hum/frequency_drift": ("missing_harmonic", "a_h", 0.05, {"k_h": 3.0, "b_h": 0.0}),
}


def system_frequency(spec):
    """The physics' own frequency (Hz) for oscillatory systems, else None."""
    p = spec["params"]
    if spec["preset"] == "oscillator":
        return np.sqrt(p["k"]) / (2 * np.pi)
    if spec["preset"] == "pendulum":
        return np.sqrt(p["w2"]) / (2 * np.pi)
    if spec["preset"] == "hum":
        return p["f0"]
    return None


def applicable_kinds(spec):
    """Slow wander applies to oscillatory systems only; everything else to every system."""
    return [k for k in KINDS if k != "slow" or spec["slow"]]


def _pickup_frequency(spec, x, rng):
    T = float(x[-1] - x[0])
    nyq = 0.5 / float(np.median(np.diff(x)))
    f_sys = system_frequency(spec)
    for _ in range(200):
        if f_sys is None:
            f = rng.uniform(4.0, 15.0) / T          # 4-15 cycles over the record
        elif spec["preset"] == "hum":
            f = rng.uniform(0.3, 0.9) * nyq
        else:
            f = f_sys * rng.uniform(1.6, 4.6)
        if f_sys is None or abs(f / f_sys - round(f / f_sys)) > 0.12:
            if f < 0.9 * nyq:
                return f
    return f


def add_disturbance(kind, spec, x, clean, rng):
    """Return (observed data, disturbance description) for ``clean`` model output under ``kind``."""
    s = spec["noise"]
    n = len(clean)
    white = s * rng.normal(size=n)
    if kind == "slow":
        if not spec["slow"] or x.ndim != 1:
            return clean + white, {}
        T = x[-1] - x[0]
        out = np.zeros(n)
        for _ in range(3):
            f = rng.uniform(0.3, 2.5) / T
            out += rng.normal() * np.cos(2 * np.pi * f * x + rng.uniform(0, 2 * np.pi))
        return clean + white + out * s / max(np.std(out), 1e-12), {}
    if kind == "periodic":
        amp = rng.uniform(1.0, 2.5) * s
        ph = rng.uniform(0, 2 * np.pi)
        if x.ndim == 2:
            k = rng.uniform(2.0, 5.0) * np.array([np.cos(a := rng.uniform(0, np.pi)), np.sin(a)])
            return clean + white + amp * np.cos(2 * np.pi * (x @ k) + ph), {"amplitude": amp}
        f = _pickup_frequency(spec, x, rng)
        return clean + white + amp * np.cos(2 * np.pi * f * x + ph), {"freq": f, "amplitude": amp}
    if kind == "coloured":
        phi = rng.uniform(0.5, 0.85)
        e = rng.normal(size=n) * np.sqrt(1 - phi ** 2)
        ar = np.empty(n)
        ar[0] = rng.normal()
        for i in range(1, n):
            ar[i] = phi * ar[i - 1] + e[i]
        return clean + 0.5 * white + s * ar, {"phi": phi}
    if kind == "spikes":
        k = max(2, int(round(rng.uniform(0.01, 0.02) * n)))
        idx = rng.choice(n, size=k, replace=False)
        sp = np.zeros(n)
        sp[idx] = rng.choice([-1, 1], size=k) * rng.uniform(6, 15, size=k) * s
        return clean + white + sp, {"spikes": k}
    if kind == "quantisation":
        q = rng.uniform(1.0, 3.0) * s
        return q * np.round((clean + white) / q), {"step": q}
    raise ValueError(kind)
