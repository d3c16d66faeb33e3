"""Slow wander of the mains frequency on the audio engine's basebands (the ``frequency_wander`` effect).

The grid frequency is never constant: it wanders by a few tens of mHz over tens of seconds. A
constant ``f0`` (or a linear drift) leaves every harmonic ``k`` with a slowly rotating phase
``2 pi k D(t)``, where ``D`` (cycles) is the integral of the frequency deviation. That rotation is
proportional to ``k``, which is what tells it apart from an amplitude modulation (the same real
factor on every harmonic). The effect models the deviation as one slow sinusoid,
``f(t) = f0 + df_w cos(2 pi f_w t + phase_w)``, i.e. ``D(t) = df_w / (2 pi f_w) sin(2 pi f_w t + phase_w)``.

Starts come from the data's own slow phase: each baseband divided by the calibrated model's
phasor, its angle unwrapped and divided by ``2 pi k``, then the periodogram peaks of the
strongest harmonics' average.
"""
from __future__ import annotations

import numpy as np

N_STARTS = 3            # periodogram peaks tried as wander frequencies
MIN_CYCLES = 1.0        # a wander shows at least one full cycle in the record (slower: a drift)
# The grid frequency is held by the inertia of the machines on the grid: it wanders over seconds to
# minutes. A faster 'wander' of 10-50 mHz (3 Hz) would mean a rate of change of 0.2-1 Hz/s all the
# time, which grids show only in faults; faster phase wobble of the lines is what a note partial 1-4 Hz
# from a harmonic makes (development nulls, seeds 20-59, tonal hosts: 3 of 80 were named a wander at
# 2.9-3.5 Hz). Periods down to 2 s are allowed (FM to be followed: down to 5 s).
MAX_WANDER_HZ = 0.5


def wander_cycles(tau, p):
    """Phase added by the wander (cycles of the fundamental) at times ``tau`` (s, from the band origin).

    Examples
    --------
    >>> import numpy as np
    >>> p = {"df_w": 0.02 * np.pi, "f_w": 0.01, "phase_w": 0.0}
    >>> np.round(wander_cycles(np.array([0.0, 25.0]), p), 6).tolist()     # amplitude df_w / (2 pi f_w) = 1
    [0.0, 1.0]
    """
    f_w = max(float(p["f_w"]), 1e-12)
    return p["df_w"] / (2 * np.pi * f_w) * np.sin(2 * np.pi * f_w * tau + p["phase_w"])


def wander_bounds(span_s, step_s, max_steps):
    """Bounds of ``f_w``: at least one cycle over the record, at most ``MAX_WANDER_HZ`` (the grid's
    inertia) and the bands' usable half-width.

    Over less than a cycle a sinusoidal phase is close to a polynomial, i.e. to a drift (its own
    effect); a faster wander is not the grid's, and may lie outside the decimated bands.

    Examples
    --------
    >>> wander_bounds(60.0, 0.1, 0.4)
    {'f_w': (0.016666666666666666, 0.5)}
    >>> wander_bounds(60.0, 1.0, 0.4)                  # coarse bands: their half-width limits it
    {'f_w': (0.016666666666666666, 0.4)}
    """
    return {"f_w": (MIN_CYCLES / span_s, min(MAX_WANDER_HZ, max_steps / step_s))}


def slow_phase(preset, pred, y):
    """The data's phase relative to the model, in cycles of the fundamental: ``(tau, D)`` per step.

    The harmonics whose model phasor is strong are averaged (weights ``|model|^2 k^2``).

    Parameters
    ----------
    preset : HumBands
        The baseband preset (its layout: ``ks``, steps).
    pred, y : ndarray
        Stacked model prediction and data (band noise units).

    Returns
    -------
    tau : ndarray (M,)
        Step times relative to the band origin (s).
    D : ndarray (M,)
        Phase deviation (cycles of the fundamental), or None when no band carries the model.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> preset = SimpleNamespace(ks=[1, 2], step=0.1)
    >>> tau = np.arange(50) * 0.1; D_true = 0.02 * tau                 # the data run ahead of the model
    >>> model = 10.0 * np.ones((50, 2), complex)
    >>> data = model * np.exp(2j * np.pi * np.array([1, 2]) * D_true[:, None])
    >>> stack = lambda z: np.stack([z.real, z.imag], axis=-1).ravel()
    >>> _, D = slow_phase(preset, stack(model), stack(data))
    >>> bool(np.allclose(D, D_true))
    True
    """
    K = len(preset.ks)
    zp = pred.reshape(-1, K, 2)
    zy = y.reshape(-1, K, 2)
    cp = zp[..., 0] + 1j * zp[..., 1]
    cy = zy[..., 0] + 1j * zy[..., 1]
    power = np.mean(np.abs(cp) ** 2, axis=0)
    use = np.flatnonzero(power > 25.0)          # a line at least 5 noise units strong
    if len(use) == 0:
        return None, None
    num = np.zeros(cp.shape[0])
    den = 0.0
    for i in use:
        k = float(preset.ks[i])
        ang = np.unwrap(np.angle(cy[:, i] * np.conj(cp[:, i])))
        w = power[i] * k * k
        num += w * ang / (2 * np.pi * k)
        den += w
    tau = np.arange(cp.shape[0]) * preset.step
    return tau, num / den


def wander_starts(p, r, tt, base, model, t):
    """Starting values of ``frequency_wander`` from the periodogram of the data's slow phase.

    Parameters
    ----------
    p : dict
        Calibrated parameters.
    r, tt : ndarray
        Residual and stacked times (unused: the phase is read from the prediction and the data).
    base : Fit
        Calibrated fit (its prediction; the data are the preset's).
    model : Model
        The model with the effect (its preset must be the baseband one, its bounds limit ``f_w``).
    t : ndarray
        Stacked times.

    Returns
    -------
    list of dict
        Up to three starts (empty when the model is not on the basebands).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> wander_starts({"f0": 50.0}, None, None, None, SimpleNamespace(preset=None), None)   # not on basebands
    []
    """
    preset = getattr(model, "preset", None)
    if model is None or not getattr(preset, "baseband", False):
        return []
    pred = np.asarray(base.prediction, float)
    tau, D = slow_phase(preset, pred, np.asarray(preset.data, float))
    if D is None or len(D) < 8:
        return []
    lo, hi = model.bounds.get("f_w", (0.0, np.inf))
    X = np.column_stack([np.ones_like(tau), tau])
    from odnn_sep.core.linalg import solve
    D = D - X @ solve(X, D, method="lstsq")     # constant and slope: f0 and the harmonics' phases
    n = len(D)
    nfft = int(2 ** np.ceil(np.log2(8 * n)))
    f = np.fft.rfftfreq(nfft, preset.step)
    spec = np.abs(np.fft.rfft(D * np.hanning(n), nfft))
    spec[(f < lo) | (f > min(hi, f[-1]))] = 0.0
    out = []
    for _ in range(N_STARTS):
        i = int(np.argmax(spec))
        if spec[i] <= 0:
            break
        fw = float(f[i])
        F = np.column_stack([np.cos(2 * np.pi * fw * tau), np.sin(2 * np.pi * fw * tau)])
        c, s = solve(F, D, method="lstsq")
        # c cos + s sin = A sin(2 pi f tau + phi) with A = hypot(c, s), phi = atan2(c, s)
        out.append({**p, "f_w": fw, "df_w": float(2 * np.pi * fw * np.hypot(c, s)),
                    "phase_w": float(np.arctan2(c, s))})
        spec[max(0, i - 16): i + 17] = 0.0     # next peak at least two natural resolution cells away
    return out
