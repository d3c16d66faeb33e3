"""Which comb is hum: track the fundamental's phase on the candidate harmonics, keep the
harmonics that are phase-locked to it (lock.py), and track again on those alone until the set
settles; between the 50 and 60 Hz families, the one with more locked evidence wins.

A family whose candidate lines are note partials (a melody repeating F4 = 349.2 Hz beside 350 Hz)
yields a "track" that no line follows for long: none of them passes the lock test, and the
family is dropped. Hum-free input then leaves with no line at all.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.audio import baseband as _baseband
from odnn_sep.audio import detect as _detect
from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import lock as _lock
from odnn_sep.audio import track as _track

log = logging.getLogger(__name__)
TRACK_HOP_S = 4.0     # blocks of the starting (coarse) track: 8 s
LOWEST_K = 5          # a hum comb has a locked line among harmonics 1..LOWEST_K


@dataclass
class Comb:
    nominal_hz: float
    f_ref: float
    harmonics: list[int]          # locked harmonics (or the requested ones)
    psi: np.ndarray | None        # fundamental's phase (cycles, relative to f_ref t) at chunk centres
    D: np.ndarray | None          # chunk sums of ``harmonics``
    weights: np.ndarray | None    # (C, K) inverse floor PSD
    evidence: float = 0.0         # sum of -log10 p of the locked lines
    lock: dict = field(default_factory=dict)


def _weights(spec, f_ref, ks, det_floors):
    cols, typical = [], None
    for k in ks:
        fl = det_floors.get(("h", k))
        if fl is None or not np.isfinite(fl).all():
            fl = _detect.line_level(spec, k * f_ref, _detect.band_halfwidth(spec, k))["floor"]
        if not np.isfinite(fl).all():
            typical = np.median(spec.psd, axis=0) if typical is None else typical
            fl = np.where(np.isfinite(fl), fl, typical)
        cols.append(1.0 / np.maximum(fl, 1e-300))
    return np.stack(cols, axis=1)


def settle(source, spec, det, extra, *, alpha: float, n_tests: int, test: bool = True, rounds: int = 3,
           progress=None) -> Comb:
    """Track and lock-test the family of ``det`` (harmonics ``det.harmonics`` plus ``extra``
    candidates). ``test=False``: the harmonics were given by the caller; only track them."""
    sr, N = source.sr, source.frames
    f_ref = det.mains_hz
    cand = sorted(set(det.harmonics) | set(extra))
    D_all = _track.demodulate(source, f_ref, cand, progress=progress)
    W_all = _weights(spec, f_ref, cand, det.floors)
    ks = list(det.harmonics) if det.harmonics else list(cand)
    hop = max(1, int(round(TRACK_HOP_S * sr)))
    info, psi = {}, None
    for _ in range(rounds):
        cols = [cand.index(k) for k in ks]
        trk = _track.track_fundamental(D_all[:, :, cols], sr, N, f_ref, ks, W_all[:, cols], hop=hop)
        tc = _finetrack.chunk_times(D_all.shape[0], sr)
        psi0 = _finetrack.block_track_phase(trk, tc, f_ref, sr)
        psi = _finetrack.refine_phase(D_all[:, :, cols], sr, f_ref, ks, W_all[:, cols], psi0)
        if not test:
            break
        keep, info = _lock.locked(D_all, sr, cand, psi, alpha=alpha)
        # the lines that steer the track are tested against a track made without them
        # (leave one out): a phase that follows one line is trivially locked to it, a note
        # partial included; a lone line is tested against the block track (8 s blocks cannot
        # follow a note's phase from one onset to the next)
        for i, k in enumerate(ks):
            if len(ks) > 1:
                rest = [j for j in range(len(ks)) if j != i]
                ks_r = [ks[j] for j in rest]
                psi_k = _finetrack.refine_phase(D_all[:, :, [cols[j] for j in rest]], sr, f_ref, ks_r,
                                                W_all[:, [cols[j] for j in rest]], psi0)
            else:
                psi_k = psi0
            kk, inf_k = _lock.locked(D_all[:, :, [cols[i]]], sr, [k], psi_k, alpha=alpha)
            info[k] = inf_k[k]
            if not kk and k in keep:
                keep.remove(k)
        # a line must be significant and phase-locked. A line of the spectrum's comb needs only
        # the one lock test (hum or note partial?); any other harmonic is a new line, and both
        # its lock test and its line test on the tracked baseband (a band of 1.5 fine bins) are
        # Bonferroni-corrected over every line tested. (The 10 ms chunk sums carry copies of the
        # strong harmonics ~60 dB down at even harmonic distances: they follow the drift, so
        # only the corrected tests keep them out.)
        new = [k for k in keep if k not in det.harmonics and info[k][0] * n_tests < alpha]
        if new:
            trk_p = _finetrack.track_from_phase(psi, sr, f_ref, N, hop)
            seg_hr = float(np.clip(N / sr / 4, 4.0, 16.0))
            sig, _ = _baseband.second_look(D_all[:, :, [cand.index(k) for k in new]], sr, f_ref, new, trk_p,
                                           alpha=alpha, n_tests=n_tests, seg_s=seg_hr)
            keep = [k for k in keep if k in det.harmonics or k in sig]
        else:
            keep = [k for k in keep if k in det.harmonics]
        if not keep or keep == ks:
            ks = keep
            break
        ks = keep
    if test and ks and min(ks) > LOWEST_K:
        # mains hum lives at the fundamental and the first harmonics (a weak fundamental is
        # normal, a comb with nothing locked below the 6th harmonic is not): locked lines only
        # high up are partials of held notes that happen to keep their phase
        log.info("lines %s locked but none of harmonics 1-%d: not taken for hum", ks, LOWEST_K)
        ks = []
    cols = [cand.index(k) for k in ks]
    ev = float(sum(-np.log10(max(info[k][0], 1e-300)) for k in ks)) if test else 0.0
    return Comb(nominal_hz=det.nominal_hz, f_ref=f_ref, harmonics=ks, psi=psi if ks else None,
                D=D_all[:, :, cols] if ks else None, weights=W_all[:, cols] if ks else None, evidence=ev,
                lock=info)


def choose(source, spec, det, *, mains, harmonics, alpha: float, max_hz, tones, progress=None) -> Comb | None:
    """The locked comb of the detected family, or of the other nominal family when it has more
    locked evidence; None when no line is locked."""
    test = harmonics == "auto"
    n_first = max(1, sum(1 for c in det.candidates if c["harmonic"] is not None))
    fams = []
    if det.harmonics:
        # every harmonic in range is tested for lock, not only those the spectrum showed: weak
        # harmonics of a hum (the even ones of odd-dominant hum, the 11th under music) are
        # clear on the tracked baseband
        extra = [k for k in _detect._candidate_harmonics(det.mains_hz, source.sr, "auto", max_hz)
                 if k not in det.harmonics] if test else []
        fams.append(settle(source, spec, det, extra, alpha=alpha, n_tests=n_first + len(extra), test=test,
                           progress=progress))
    if test and mains == "auto":
        for nom in (50.0, 60.0):
            if nom == det.nominal_hz:
                continue
            other = [c["harmonic"] for c in det.candidates if c["family_hz"] == nom and c["significant"]]
            if not other:
                continue
            d2 = _detect.detect_hum(spec, source.sr, mains=nom, harmonics="auto", tones=tones, alpha=alpha,
                                    max_hz=max_hz)
            d2.harmonics = sorted(set(d2.harmonics) | set(other))
            extra = [k for k in _detect._candidate_harmonics(d2.mains_hz, source.sr, "auto", max_hz)
                     if k not in d2.harmonics]
            fams.append(settle(source, spec, d2, extra, alpha=alpha, n_tests=n_first + len(extra), test=True))
    fams = [f for f in fams if f.harmonics]
    if not fams:
        return None
    best = max(fams, key=lambda f: f.evidence)
    log.info("phase-locked comb: %.4f Hz, harmonics %s (evidence %s)", best.f_ref, best.harmonics,
             [round(f.evidence, 1) for f in fams])
    return best
