"""Discrete Fourier spectra of records whose samples may be irregularly spaced.

A record sampled at uniform times goes through the FFT, with the sample step as the median spacing.
A record sampled irregularly (a logger with jitter, dropped samples, a phone sensor) does not: the
FFT of its samples puts each line at the frequency scaled by the ratio of the mean to the median
spacing (about 1.44 for random times), so the peaks it finds are not the record's. Such records get
the non-uniform DFT at the same frequency grid (the mean spacing gives the grid), which keeps the
scaling of the FFT: under white noise each ordinate's power still has the expectation n sigma^2.
"""
from __future__ import annotations

import numpy as np

# spacings within this share of the median count as uniform (times written with a few digits)
UNIFORM_TOL = 0.01
# the non-uniform DFT costs samples x frequencies; above this it is evaluated on the record
# linearly interpolated to a uniform grid (peak positions stay; the noise statistics do not)
MAX_NUDFT_OPS = 5e7


def is_uniform(t, tol=UNIFORM_TOL) -> bool:
    """Whether the sample times are uniformly spaced (within ``tol`` of the median spacing).

    Parameters
    ----------
    t : array_like
        Increasing sample times.
    tol : float, optional
        Largest relative departure of a spacing from the median spacing.

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> is_uniform(np.arange(10) * 0.1), is_uniform(np.sort(np.random.default_rng(0).uniform(0, 1, 50)))
    (True, False)
    """
    d = np.diff(np.asarray(t, float))
    if len(d) == 0:
        return True
    med = float(np.median(d))
    return bool(med > 0 and np.max(np.abs(d - med)) <= tol * med)


def spectrum(t, r, *, nfft=None, taper=False):
    """One-sided discrete Fourier transform of ``r`` sampled at ``t``: ``(freqs, X)``.

    Uniform times give exactly ``np.fft.rfft(r * w, nfft)`` and ``np.fft.rfftfreq(nfft, dt)`` (``dt`` the
    median spacing, ``w`` a Hann window when ``taper``); irregular times give the non-uniform DFT
    ``X(f) = sum_j w_j r_j exp(-2 pi i f (t_j - t_0))`` on the grid of the mean spacing, with the window
    taken at the sample times.

    Parameters
    ----------
    t : array_like
        Increasing sample times.
    r : array_like
        Samples.
    nfft : int, optional
        Transform length (zero padding); default ``len(r)``.
    taper : bool, optional
        Apply a Hann window.

    Returns
    -------
    freqs : ndarray
        Frequencies (cycles per unit of ``t``).
    X : ndarray of complex
        Transform at ``freqs``.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> t = np.sort(rng.uniform(0, 10, 400)); t[0], t[-1] = 0.0, 10.0
    >>> f, X = spectrum(t, np.cos(2 * np.pi * 3.0 * t), nfft=4096, taper=True)
    >>> round(float(f[np.argmax(np.abs(X))]), 2)     # the FFT of these samples puts it near 4.2
    3.0
    """
    t = np.asarray(t, float)
    r = np.asarray(r, float)
    n = len(r)
    nfft = n if nfft is None else int(nfft)
    if is_uniform(t):
        dt = float(np.median(np.diff(t))) if n > 1 else 1.0
        x = r * np.hanning(n) if taper else r
        return np.fft.rfftfreq(nfft, dt), np.fft.rfft(x, nfft)
    tau = t - t[0]
    span = float(tau[-1])
    dt = span / (n - 1)
    freqs = np.fft.rfftfreq(nfft, dt)
    if n * len(freqs) > MAX_NUDFT_OPS:
        grid = np.linspace(0.0, span, n)
        x = np.interp(grid, tau, r)
        return freqs, np.fft.rfft(x * np.hanning(n) if taper else x, nfft)
    x = r * (0.5 - 0.5 * np.cos(2 * np.pi * tau / span)) if taper else r
    X = np.empty(len(freqs), complex)
    step = max(1, int(2e6 // n))    # frequencies per block: about 32 MB of phasors
    for a in range(0, len(freqs), step):
        X[a:a + step] = np.exp(-2j * np.pi * np.outer(freqs[a:a + step], tau)) @ x
    return freqs, X
