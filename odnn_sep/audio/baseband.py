"""The tracked baseband: chunk sums of pass 1 with the tracked phase removed.

``D[j, c, k]`` (see :func:`track.demodulate`) holds every hum line as a 100 Hz complex baseband at
``k * f_ref``; multiplying by ``exp(-i k psi_j)``, ``psi`` the integral of the tracked offset
``f0(t) - f_ref``, turns a drifting harmonic that follows the track into a steady phasor. The
block-length choice emulates the block fit on it (:mod:`blocklen`); the lock test (:mod:`lock`)
asks whether it is steady.
"""
from __future__ import annotations

import logging

import numpy as np

from odnn_sep.audio import track as _track

log = logging.getLogger(__name__)


def tracked_phase(D, sr: int, f_ref: float, trk) -> np.ndarray:
    """``psi_j`` (rad) at the chunk centres: 2 pi times the integral of ``f0(t) - f_ref``.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums (only their count is used).
    sr : int
        Sample rate (Hz).
    f_ref : float
        Reference fundamental of ``D`` (Hz).
    trk : track.Track
        The fundamental track; its refined phase is used when it has one at ``f_ref``.

    Returns
    -------
    (J,) float array

    Examples
    --------
    >>> from odnn_sep.audio.track import Track
    >>> D = np.zeros((400, 1, 1), np.complex64)            # 4 s of chunk sums at 8 kHz
    >>> z = np.zeros(3)
    >>> trk = Track(t=np.array([0.0, 2.0, 4.0]), f0=np.full(3, 50.25), rate=z, curv=z,
    ...             confident=np.ones(3, bool), strength=z)
    >>> psi = tracked_phase(D, 8000, 50.0, trk)
    >>> psi.shape, round(float(psi[-1] / (2 * np.pi)), 3)                   # 0.25 Hz over 4 s: one cycle
    ((400,), 1.0)
    """
    m = _track.chunk_length(sr)
    tc = (np.arange(D.shape[0]) * m + (m - 1) / 2) / sr
    ph = getattr(trk, "phase", None)
    if ph is not None and abs(ph.f_ref - f_ref) < 1e-12 and len(ph.psi) == D.shape[0]:
        return 2 * np.pi * ph.psi
    dfreq = np.interp(tc, trk.t, trk.f0) - f_ref
    return 2 * np.pi * np.cumsum(dfreq) * (m / sr)


def derotate(D, ks, psi) -> np.ndarray:
    """``D * exp(-i k psi)`` in complex128, shape (J, C, K).

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums.
    ks : sequence of float
        Harmonic number of each column.
    psi : (J,) float array
        Tracked phase (rad), as :func:`tracked_phase` gives it.

    Returns
    -------
    (J, C, K) complex128 array

    Examples
    --------
    >>> D = np.ones((3, 1, 2), np.complex64)
    >>> derotate(D, [1, 2], np.array([0.0, np.pi / 2, np.pi]))[:, 0].round(6).tolist()
    [[(1+0j), (1+0j)], [-1j, (-1-0j)], [(-1-0j), (1+0j)]]
    """
    ks = np.asarray(ks, float)
    # exp(-i k psi) by its real and imaginary parts (the same values as the complex exponential)
    th = (-psi)[:, None] * ks[None, :]
    rot = np.empty(th.shape, np.complex128)
    rot.real = np.cos(th)
    rot.imag = np.sin(th)
    return D.astype(np.complex128) * rot[:, None, :]
