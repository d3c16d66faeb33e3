"""Explicit-orthogonality cases (paper App. C.1): physics and disturbance in close but distinct
frequency bands."""
from __future__ import annotations

from functools import partial

import numpy as np

from odnn_sep.core import Band, Basis, Orthogonal
from odnn_sep.signals.dataset import Dataset, check_n, check_theta, make, pick, rng_from

#: Known physics frequencies (Hz) of :func:`explicit_1d`: deliberately *off* the DFT bins of the
#: default 10 s record, so their spectra leak and plain least squares is not exactly orthogonal.
FREQS_1D = (4.03, 4.87, 5.61)
#: Known physics wave vectors (cycles per unit side) of :func:`explicit_2d`.
WAVES_2D = ((3, 1), (1, 4), (2, 3))


def _cos_wave(t, w):
    return np.cos(w * t)


def _sin_wave(t, w):
    return np.sin(w * t)


def _plane_wave(x, kind, kv):
    return np.cos(2 * np.pi * x @ kv) if kind == "cos" else np.sin(2 * np.pi * x @ kv)


def _sinusoid(kind, f):
    # module functions bound by partial, not closures: a Dataset pickles (multiprocessing, joblib)
    return partial(_cos_wave if kind == "cos" else _sin_wave, w=2 * np.pi * f)


def explicit_1d(*, n: int = 1000, sr: float = 100.0, band_hz: tuple = (6.5, 9.0),
                disturbance_rms: float = 2.0, snr_db: float = 30.0, theta: dict | None = None,
                random_state: int | None = None) -> Dataset:
    """1-D sinusoids at known frequencies plus a band-limited disturbance in a nearby band.

    Physics: ``sum_k a_k cos(2 pi f_k t) + b_k sin(2 pi f_k t)`` with ``f_k`` in :data:`FREQS_1D`
    (4-5.6 Hz) and unknown amplitudes ``a_k, b_k`` (|value| in [0.5, 1.5], random sign).
    Disturbance: a random multi-sine on the DFT bins strictly inside ``band_hz`` (default
    6.5-9 Hz, close to but distinct from the physics band), RMS ``disturbance_rms`` times the
    physics RMS. Disturbance class: ``Band(*band_hz)``, exact because the disturbance sits on DFT
    bins inside the band. The physics frequencies are off-bin, so their leakage makes plain
    least squares (``Orthogonal``) slightly biased while the band projection is exact.

    Parameters
    ----------
    n : int
        Number of samples (record length ``n / sr`` seconds).
    sr : float
        Sample rate in Hz.
    band_hz : (float, float)
        Disturbance band in Hz.
    disturbance_rms : float
        Disturbance RMS relative to the physics RMS.
    snr_db : float
        Physics-to-noise power ratio in dB (``inf``: no noise).
    theta : dict, optional
        Fix some amplitudes (``a0, b0, a1, ...``); the others are drawn at random.
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = explicit_1d(random_state=0)
    >>> ds.x.shape, ds.basis.names[:2]
    ((1000,), ('a0', 'b0'))
    """
    n = check_n(n, 64)
    rng = rng_from(random_state)
    names = [f"{c}{k}" for k in range(len(FREQS_1D)) for c in ("a", "b")]
    check_theta(theta, names)
    t = np.arange(n) / float(sr)
    funcs = [_sinusoid("cos" if nm[0] == "a" else "sin", FREQS_1D[int(nm[1:])]) for nm in names]
    basis = Basis(funcs, names=names)
    th = {nm: pick(rng, theta, nm, 0.5, 1.5, signed=True) for nm in names}
    physics = basis.evaluate(t) @ np.array([th[k] for k in names])
    freqs = np.fft.rfftfreq(n, 1 / sr)
    lo, hi = band_hz
    df = sr / n
    bins = np.flatnonzero((freqs > lo + 0.5 * df) & (freqs < hi - 0.5 * df))
    spec = np.zeros(freqs.size, complex)
    spec[bins] = rng.standard_normal(bins.size) + 1j * rng.standard_normal(bins.size)
    g = np.fft.irfft(spec, n=n)
    g *= disturbance_rms * np.sqrt(np.mean(physics**2)) / np.sqrt(np.mean(g**2))
    desc = (f"explicit 1-D: 3 sinusoids at {FREQS_1D} Hz (off-bin) + random multi-sine in "
            f"{lo:g}-{hi:g} Hz (RMS {disturbance_rms:g}x physics); class Band({lo:g}, {hi:g})")
    return make("explicit_1d", t, basis, Band(float(lo), float(hi)), th, physics, g, snr_db, rng, desc)


def explicit_2d(*, side: int = 48, band: tuple = (6.0, 10.0), disturbance_rms: float = 2.0,
                snr_db: float = 30.0, theta: dict | None = None, random_state: int | None = None) -> Dataset:
    """2-D plane waves at known wave vectors plus a random field in a distinct wavenumber band.

    Samples: a ``side x side`` grid on [0, 1)^2, flattened; ``x`` has shape (side**2, 2).
    Physics: ``sum_k a_k cos(2 pi k.x) + b_k sin(2 pi k.x)`` for the wave vectors in
    :data:`WAVES_2D` (|k| <= 4.2 cycles). Disturbance: random Fourier coefficients on the grid's
    DFT modes with |k| strictly inside ``band`` (default 6-10 cycles). Both sit on DFT modes of the
    grid, so they are exactly orthogonal in the empirical inner product (Parseval), and the sound
    class is ``Orthogonal()``; here ODNN's exact solver coincides with least squares.

    Parameters
    ----------
    side : int
        Grid points per side.
    band : (float, float)
        Disturbance wavenumber band (cycles per unit length).
    disturbance_rms, snr_db, theta, random_state : as in :func:`explicit_1d`.

    Returns
    -------
    Dataset

    Examples
    --------
    >>> explicit_2d(side=32, random_state=0).x.shape
    (1024, 2)
    """
    side = check_n(side, 24, "side")
    rng = rng_from(random_state)
    names = [f"{c}{k}" for k in range(len(WAVES_2D)) for c in ("a", "b")]
    check_theta(theta, names)
    g1 = np.arange(side) / side
    X = np.stack(np.meshgrid(g1, g1, indexing="ij"), -1).reshape(-1, 2)

    def wave(kind, kv):
        return partial(_plane_wave, kind=kind, kv=np.asarray(kv, float))

    funcs = [wave("cos" if nm[0] == "a" else "sin", WAVES_2D[int(nm[1:])]) for nm in names]
    basis = Basis(funcs, names=names)
    th = {nm: pick(rng, theta, nm, 0.5, 1.5, signed=True) for nm in names}
    physics = basis.evaluate(X) @ np.array([th[k] for k in names])
    k1 = np.fft.fftfreq(side, 1 / side)
    kk = np.sqrt(k1[:, None] ** 2 + k1[None, :] ** 2)
    mask = (kk > band[0]) & (kk < band[1])
    spec = (rng.standard_normal(kk.shape) + 1j * rng.standard_normal(kk.shape)) * mask
    g = np.real(np.fft.ifft2(spec)).reshape(-1)  # real part of a band-limited field stays in the band
    g *= disturbance_rms * np.sqrt(np.mean(physics**2)) / np.sqrt(np.mean(g**2))
    desc = (f"explicit 2-D: plane waves at wave vectors {WAVES_2D} + random field with |k| in "
            f"({band[0]:g}, {band[1]:g}) cycles; exactly orthogonal on the grid; class Orthogonal()")
    return make("explicit_2d", X, basis, Orthogonal(), th, physics, g, snr_db, rng, desc)
