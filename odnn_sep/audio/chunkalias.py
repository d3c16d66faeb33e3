"""What a strong hum line leaks into the chunk sums of another harmonic, and where it looks locked.

The chunk sums (track.demodulate) are 10 ms boxcar sums read every 10 ms. A line at ``j f`` seen
at the reference of harmonic ``k`` passes the boxcar with the gain of its offset ``j f - k f_ref``,
and the chunk rate folds it: turned by the track (``k`` times the fundamental's phase), it turns at
``(j - k) f`` folded into the chunk rate. For a steady 50.000 Hz hum read at 100 chunks a second that
is zero for every even ``k - j`` (60.000 Hz: every multiple of 5): the leak sits still, exactly like
a locked line. The boxcar's nulls are there when the reference is the hum's own frequency, so the
leak is small; with a reference 0.09 Hz off (notes near every harmonic pulled the spectrum's
fundamental there) the leak of a strong fundamental reached -45 dB at harmonics 9-75, passed the
lock test and the -50 dB floor, and 34 lines of the music were removed. A line added by a lock test
must therefore stand clear of what the comb's own lines leak there.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import track as _track

STILL_CYCLES = 2.0    # a leak turning less than this over the input counts as standing still


def boxcar_gain(delta_hz: float, m: int, sr: int) -> float:
    """Modulus of the ``m``-sample boxcar sum's response at ``delta_hz``, 1 at 0 Hz.

    Examples
    --------
    >>> boxcar_gain(0.0, 80, 8000), round(boxcar_gain(100.0, 80, 8000), 12), round(boxcar_gain(50.0, 80, 8000), 3)
    (1.0, 0.0, 0.637)
    """
    x = np.pi * delta_hz / sr
    den = m * np.sin(x)
    return 1.0 if abs(den) < 1e-12 else float(abs(np.sin(m * x) / den))


def mean_fundamental(psi: np.ndarray, f_ref: float, sr: int) -> float:
    """Mean fundamental (Hz) of a track: ``f_ref`` plus the least-squares slope of its phase
    ``psi`` (cycles relative to ``f_ref t`` at the chunk centres).

    Examples
    --------
    >>> t = (np.arange(1000) + 0.5) * 0.01
    >>> round(mean_fundamental(0.09 * t, 49.91, 8000), 6)
    50.0
    """
    if len(psi) < 2:
        return float(f_ref)
    return float(f_ref + np.polyfit(_finetrack.chunk_times(len(psi), sr), np.asarray(psi, float), 1)[0])


def alias_amplitude(k: int, amps: dict, f_ref: float, f_mean: float, sr: int, seconds: float) -> float:
    """Upper bound of the standing leak at harmonic ``k`` of the lines ``amps`` (harmonic ->
    amplitude of its tracked chunk sums), in the same units.

    Parameters
    ----------
    k : int
        The harmonic tested.
    amps : dict
        The comb's lines and their amplitudes.
    f_ref : float
        Reference fundamental of the chunk sums (Hz).
    f_mean : float
        The track's mean fundamental (Hz).
    sr : int
        Sample rate (Hz).
    seconds : float
        Length of the input (s).

    Returns
    -------
    float
        The sum of the leaks that turn less than :data:`STILL_CYCLES` over the input.

    Examples
    --------
    >>> round(alias_amplitude(9, {1: 40.0}, 49.91, 50.0, 8000, 30.0), 3)    # 8 x 50 Hz: still
    0.081
    >>> alias_amplitude(9, {1: 40.0}, 50.0, 50.0, 8000, 30.0) < 1e-9          # reference on the hum
    True
    >>> alias_amplitude(10, {1: 40.0}, 49.91, 50.0, 8000, 30.0)              # 9 x 50 Hz: turns
    0.0
    """
    m = _track.chunk_length(sr)
    rate = sr / m
    out = 0.0
    for j, a in amps.items():
        if j == k:
            continue
        turn = ((j - k) * f_mean + rate / 2) % rate - rate / 2
        if abs(turn) * seconds > STILL_CYCLES:
            continue
        own = max(boxcar_gain(j * (f_mean - f_ref), m, sr), 1e-12)
        out += float(a) * boxcar_gain(j * f_mean - k * f_ref, m, sr) / own
    return out
