"""Content power right beside a steady line, at a fraction of a second's resolution.

:func:`odnn_sep.audio.amplitude.local_power` measures the content 1.5-6 Hz from a line over 1 s
windows: a note partial 0.5-1.5 Hz from a hum harmonic is slower than its 1 s moving mean of the
line and goes unseen, so the chunks that hold the note keep their full weight in the weighted
means of the line (steadypath.py, the weighted lock test). Here the line itself is taken out
first, and what remains near it is measured whatever its offset:

1. the line: on the tracked baseband (the chunk sums turned by the tracked phase) a hum harmonic
   is a slowly varying phasor; its estimate is a weighted moving mean over ``LINE_S`` (Hann), the
   weights the inverse of the current power estimate (a note that starts and stops does not
   pull it);
2. what remains, band-limited to a few hertz about the line (a Hann moving mean over
   ``NEAR_S``: the neighbouring harmonics 50-60 Hz away and far content are cut by the window);
3. its power, smoothed over ``POWER_S``, scaled to the power per chunk of white content of the
   same level.

Steps 1-3 are repeated ``ROUNDS`` times. They run in single precision: the result is a weight,
whose 1e-7 relative rounding moves no gain, and on an hour of audio the float64 work arrays
were the largest of the analysis (about 30 MB of peak memory). The result is the power near the line at each moment
whatever holds it (noise, a partial 0.5 Hz away, a burst of speech), which is what the weights
of a generalised least-squares mean of the line need: the note is down-weighted where it plays;
the hum, which persists, is read in the pauses.
"""
from __future__ import annotations

import numpy as np
from scipy import fft as _fft

LINE_S = 4.0      # span of the line's own moving mean (s): a partial 0.5 Hz away is 2 window bins off
NEAR_S = 0.25     # band about the line that counts as near: +-4 Hz (Hann main lobe)
POWER_S = 0.5     # smoothing of the power (s)
ROUNDS = 2
FLOOR = 0.05      # powers floored at this x their median (a few quiet chunks must not carry a block)
MAX_WEIGHT = 1e20  # weights past this are rescaled (single-precision sums of them must stay finite)


def _hann(n: int) -> np.ndarray:
    w = np.hanning(max(3, n) + 2)[1:-1]
    return (w / w.sum()).astype(np.float32)


def _smooth(x: np.ndarray, h: np.ndarray) -> np.ndarray:
    """``x`` convolved with ``h`` (centred, same length, zeros beyond the ends), by overlap-add
    FFTs of blocks a few kernels long (as ``scipy.signal.oaconvolve(x, h, "same")``, whose module
    takes most of a second to import on every run of the command line).

    Examples
    --------
    >>> x = np.zeros(9, np.float32); x[4] = 1.0
    >>> (np.round(_smooth(x, np.array([0.25, 0.5, 0.25], np.float32)), 3) + 0.0).tolist()
    [0.0, 0.0, 0.0, 0.25, 0.5, 0.25, 0.0, 0.0, 0.0]
    """
    n, m = x.shape[0], h.shape[0]
    cplx = np.iscomplexobj(x)
    nfft = _fft.next_fast_len(max(8 * m, 64), real=not cplx)
    L = nfft - m + 1                                   # input samples per block
    nb = -(-n // L)
    xp = np.zeros(nb * L, x.dtype)
    xp[:n] = x
    blocks = xp.reshape(nb, L)
    if cplx:
        yb = _fft.ifft(_fft.fft(blocks, nfft, axis=1) * _fft.fft(h, nfft), axis=1)
    else:
        yb = _fft.irfft(_fft.rfft(blocks, nfft, axis=1) * _fft.rfft(h, nfft), nfft, axis=1)
    out = np.zeros((nb + 1) * L, yb.dtype)
    out[: nb * L] = yb[:, :L].ravel()
    out[L:].reshape(nb, L)[:, : m - 1] += yb[:, L:]    # each block's tail onto the next one
    s = (m - 1) // 2
    return out[s: s + n]


def near_power(u: np.ndarray, fs: float) -> np.ndarray:
    """Power per chunk (white-content equivalent) of what lies within a few hertz of the steady
    line in the tracked baseband ``u``, moment by moment (see the module text).

    Parameters
    ----------
    u : (J,) complex array
        Tracked baseband of one line and channel (chunk sums turned by the tracked phase).
    fs : float
        Chunk rate (Hz; 100 for 10 ms chunks).

    Returns
    -------
    (J,) float array
        Floored at ``FLOOR`` times its median.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> J = 3000; t = np.arange(J) / 100.0
    >>> u = 2.0 + rng.standard_normal(J) + 1j * rng.standard_normal(J)     # a line; noise power 2
    >>> note = (t > 10) & (t < 14)                                        # a partial 0.8 Hz away, 4 s
    >>> u[note] += 20.0 * np.exp(2j * np.pi * 0.8 * t[note])
    >>> p = near_power(u, 100.0)
    >>> bool(1.0 < np.median(p) < 4.0), bool(p[1100:1300].min() > 30 * np.median(p))
    (True, True)
    """
    u = np.asarray(u, np.complex64)
    J = u.shape[0]
    h_line = _hann(int(round(LINE_S * fs)))
    h_near = _hann(int(round(NEAR_S * fs)))
    h_pow = _hann(int(round(POWER_S * fs)))
    white_gain = float(np.sum(h_near ** 2))          # power of white content after the near band
    w = np.ones(J, np.float32)
    p = np.ones(J, np.float32)
    for _ in range(ROUNDS):
        den = _smooth(w, h_line)
        # relative floor: the FFT's rounding leaves the smallest sums meaningless where the weights
        # span many decades (only after the rescaling below; the FLOOR keeps them within 20x otherwise)
        line = _smooth(w * u, h_line) / np.maximum(den, max(1e-6 * float(den.max()), np.finfo(np.float32).tiny))
        r = _smooth(u - line, h_near)
        p = np.maximum(_smooth(np.abs(r) ** 2, h_pow), 0.0) / white_gain
        med = float(np.median(p))
        p = np.maximum(p, max(FLOOR * med, np.finfo(np.float32).tiny))
        with np.errstate(over="ignore"):
            w = (1.0 / p).astype(np.float32)
        if not np.all(w <= MAX_WEIGHT):
            # a synthetic line with nothing beside it (near powers of 1e-40): only the weights'
            # ratios count, and their sums must stay finite in single precision
            w = (float(p.min()) / p.astype(np.float64)).astype(np.float32)
    return p.astype(np.float64)
