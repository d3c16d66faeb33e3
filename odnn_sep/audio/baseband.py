"""The tracked baseband: chunk sums of pass 1 with the tracked phase removed.

``D[j, c, k]`` (see :func:`track.demodulate`) holds every hum line as a 100 Hz complex baseband at
``k * f_ref``; multiplying by ``exp(-i k psi_j)``, ``psi`` the integral of the tracked offset
``f0(t) - f_ref``, turns a drifting harmonic that follows the track into a steady phasor. Two uses:

- the block-length choice emulates the block fit on it (:mod:`blocklen`);
- a second look for harmonics the detection spectrum missed: on the tracked baseband a line that
  follows the track is narrow whatever the drift, so it is tested in a band of 1.5 fine bins,
  where host partials with vibrato or a pitch of their own spread out and fail.
"""
from __future__ import annotations

import logging

import numpy as np

from odnn_sep.audio import detect as _detect
from odnn_sep.audio import track as _track

log = logging.getLogger(__name__)


def tracked_phase(D, sr: int, f_ref: float, trk) -> np.ndarray:
    """``psi_j`` (rad) at the chunk centres: 2 pi times the integral of ``f0(t) - f_ref``."""
    m = _track.chunk_length(sr)
    tc = (np.arange(D.shape[0]) * m + (m - 1) / 2) / sr
    ph = getattr(trk, "phase", None)
    if ph is not None and abs(ph.f_ref - f_ref) < 1e-12 and len(ph.psi) == D.shape[0]:
        return 2 * np.pi * ph.psi
    dfreq = np.interp(tc, trk.t, trk.f0) - f_ref
    return 2 * np.pi * np.cumsum(dfreq) * (m / sr)


def derotate(D, ks, psi) -> np.ndarray:
    """``D * exp(-i k psi)`` in complex128, shape (J, C, K)."""
    ks = np.asarray(ks, float)
    # exp(-i k psi) by its real and imaginary parts (the same values as the complex exponential)
    th = (-psi)[:, None] * ks[None, :]
    rot = np.empty(th.shape, np.complex128)
    rot.real = np.cos(th)
    rot.imag = np.sin(th)
    return D.astype(np.complex128) * rot[:, None, :]


def baseband_spectrum(u, sr: int, f_centre: float, seg_s: float) -> _detect.Spectrum:
    """Welch spectrum (Hann, 50 % overlap) of one line's tracked baseband ``u`` (J, C), labelled on
    the absolute frequency axis ``f_centre + offset`` so the detection's line tests apply as is."""
    m = _track.chunk_length(sr)
    fs = sr / m
    nseg = int(round(seg_s * fs))
    J, C = u.shape
    nseg = max(16, min(nseg, J))
    step = nseg - nseg // 2
    n_s = 1 + (J - nseg) // step
    win = np.hanning(nseg + 2)[1:-1]
    idx = np.arange(nseg)[None, :] + step * np.arange(n_s)[:, None]          # (S, nseg)
    seg = u[idx] * win[None, :, None]                                        # (S, nseg, C)
    P = np.abs(np.fft.fftshift(np.fft.fft(seg, axis=1), axes=1)) ** 2 / (fs * (win ** 2).sum())
    f = np.fft.fftshift(np.fft.fftfreq(nseg, 1 / fs)) + f_centre
    segs = P.transpose(1, 2, 0).astype(np.float32)                           # (nf, C, S)
    return _detect.Spectrum(freqs=f, psd=P.mean(axis=0), n_segments=n_s, seconds=J / fs, segments=segs)


def second_look(D, sr: int, f_ref: float, ks, trk, *, alpha: float, n_tests: int, seg_s: float):
    """Test harmonics ``ks`` (columns of ``D``) on the tracked baseband; returns the significant ones
    and their candidate records. ``n_tests``: Bonferroni count over both looks."""
    psi = tracked_phase(D, sr, f_ref, trk)
    u = derotate(D, ks, psi)
    f_med = trk.median_f0(f_ref)
    new, cands = [], []
    for i, k in enumerate(ks):
        fk = k * f_med
        spec = baseband_spectrum(u[:, :, i], sr, fk, seg_s)
        bw = 1.5 * spec.df
        st = _detect.line_test(spec, fk, bw)
        if not np.isfinite(st["floor"]).all():
            continue
        p_adj = min(1.0, st["p_value"] * n_tests)
        cands.append({"family_hz": f_med, "harmonic": int(k), "freq_hz": fk,
                      "level_db": [float(v) for v in st["level_db"]], "p_value_bonferroni": p_adj,
                      "significant": bool(p_adj < alpha), "look": "tracked baseband"})
        if p_adj < alpha:
            new.append(int(k))
    if new:
        log.info("second look on the tracked baseband: harmonics %s also present", new)
    return new, cands
