"""The passes of ``denoise`` (api.py): remove mains hum (tracked fundamental + harmonics) and named
tones from audio.

Pipeline (all passes stream in blocks, so memory does not grow with the file length):

1. detection on a Welch spectrum: fundamental (50/60 Hz or given), harmonics present, tones;
2. pass 1: demodulated 10 ms chunk sums -> block length (blocklen.py) and per-block fundamental
   track (track.py); gaps in the comb looked at again on the tracked baseband (baseband.py);
   further steady combs near the main one (combs.py); whole-input amplitudes of the harmonics by
   generalised least squares on the same chunk sums (amplitude.py);
3. pass 2 (blockfit.py): per 50 %-overlapping block, weighted least squares of the samples on the
   tracked harmonic basis plus the fixed lines (fit.py, fullblock.py), amplitudes pooled across
   blocks where the lines are steady, fitted hum windowed by sin^2 (the windows sum to one, so
   blocks join without clicks), subtracted and written progressively;
4. line levels above the local floor before and after, for the report (result.py).
"""
from __future__ import annotations

import logging

import numpy as np

from odnn_sep.audio import amplitude as _amplitude
from odnn_sep.audio import blockfit as _blockfit
from odnn_sep.audio import blocklen as _blocklen
from odnn_sep.audio import combs as _combs
from odnn_sep.audio import detect as _detect
from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import lockcomb as _lockcomb
from odnn_sep.audio import params as _params
from odnn_sep.audio import track as _track
from odnn_sep.audio.result import DenoiseResult
from odnn_sep.errors import InputError, check_option

log = logging.getLogger(__name__)

SMOOTH_BLOCKS = 4   # line amplitudes pooled over up to this many blocks on each side (blockfit.py)
POOL_MAIN = True    # pool the tracked comb too (in the track's common phase reference), not only fixed lines


def run(source, sink, **kw):
    """All passes over ``source`` (an ArraySource or FileSource); the cleaned samples go through
    ``sink(piece, removed)``. Options as in :func:`api.denoise`, plus ``after_source_fn`` (the
    written output as a source, for the line levels after). Returns the DenoiseResult."""
    # Many small matrix products: BLAS threads only add spin-wait overhead here (and collapse
    # when the machine is busy), so run them single-threaded.
    try:
        from threadpoolctl import threadpool_limits  # present through librosa -> scikit-learn
    except ImportError:  # pragma: no cover
        return _run_inner(source, sink, **kw)
    with threadpool_limits(limits=1, user_api="blas"):
        return _run_inner(source, sink, **kw)


def _run_inner(source, sink, *, mains, harmonics, tones, block_s, solver, alpha, max_hz, progress, random_state,
               after_source_fn, max_combs=3):
    sr, N, C = source.sr, source.frames, source.channels
    mains = _params.parse_mains(mains, sr)
    harmonics = _params.parse_harmonics(harmonics)
    tones = _params.parse_tones(tones, sr)
    max_hz = _params.parse_max_hz(max_hz, sr)
    check_option("solver", solver, ("exact", "network"))
    auto_block = isinstance(block_s, str) and block_s.strip().lower() == "auto"
    if not auto_block:
        try:
            block_s = float(block_s)
        except (TypeError, ValueError):
            raise InputError(f"block_s must be 'auto' or a duration in seconds; got {block_s!r}") from None
        if not np.isfinite(block_s) or block_s * 10 < 1.0 or block_s > 60:
            raise InputError(f"block_s must be between 0.1 and 60 s; got {block_s!r}")
    min_s = 0.2
    if N < min_s * sr:
        raise InputError(f"input is too short ({N} samples = {N / sr:.3f} s at {sr} Hz) to resolve mains hum; "
                         f"pass at least {min_s:g} s of audio")

    nyq = sr / 2
    top = min(0.95 * nyq, max_hz if max_hz is not None else np.inf,
              (_detect.MAX_HARMONICS + 1) * (65.0 if mains == "auto" else mains))
    spec_before = _detect.excerpt_spectrum(source, keep_segments_hz=top + 2 * _detect.FLOOR_WIDTH_HZ)
    det = _detect.detect_hum(spec_before, sr, mains=mains, harmonics=harmonics, tones=tones, alpha=alpha,
                             max_hz=max_hz)
    ks, tl = det.harmonics, det.tones
    ks_spec = list(ks)
    if auto_block and (not ks or N < 3 * _blocklen.CANDIDATES_S[-1] * sr):
        block_s, auto_block = _blocklen.CANDIDATES_S[0], False
    bar = _params.progress_bar(progress, (2 if ks else 1) * N, "denoise")
    tick = (lambda k: bar.update(k)) if bar is not None else None
    trk = None
    # only when the harmonics are the data's choice: a given count or list is removed as given
    look_again = bool(ks) and harmonics == "auto" and max_combs > 1
    h_amp = {}
    comb = _lockcomb.choose(source, spec_before, det, mains=mains, harmonics=harmonics, alpha=alpha,
                            max_hz=max_hz, tones=tl, progress=tick) if ks else None
    if comb is None:
        ks = []
        if auto_block:
            block_s, auto_block = _blocklen.CANDIDATES_S[0], False
    else:
        ks = comb.harmonics
        det.mains_hz, det.nominal_hz = comb.f_ref, comb.nominal_hz
        det.candidates += [{"family_hz": comb.nominal_hz, "harmonic": k, "freq_hz": k * comb.f_ref,
                            "p_value_bonferroni": p, "lock_index": ix, "significant": k in ks,
                            "look": "phase lock"} for k, (p, ix, _) in sorted(comb.lock.items())]
        if auto_block:
            block_s = _blocklen.choose_block_phase(comb.D, comb.psi, sr, N, comb.f_ref, ks)
        hop = max(1, int(round(block_s * sr / 2)))
        trk = _finetrack.track_from_phase(comb.psi, sr, comb.f_ref, N, hop)
        # whole-input amplitudes of the harmonics, by line (pass 1's chunk sums are at hand here)
        h_amp = dict(zip(ks, _amplitude.steady_amplitudes(comb.D, sr, comb.f_ref, ks, trk, hop, N).T,
                         strict=True))
        comb.D = None
    hop = max(1, int(round(block_s * sr / 2)))
    nb = (N - 1) // hop + 2
    if not ks and not tl:
        log.warning("no mains hum found (tested %s; lines must be phase-locked to one fundamental and "
                    "persist); the output equals the input", "50 and 60 Hz" if mains == "auto" else f"{mains:g} Hz")
    if not ks:
        t = np.arange(nb) * hop / sr
        z = np.zeros(nb)
        trk = _track.Track(t=t, f0=z, rate=z, curv=z, confident=np.zeros(nb, bool), strength=z)

    # the finest spectrum at hand: the high-resolution one when the comb is looked at again
    combs, f_med, spec_fine = [], det.mains_hz, spec_before
    look_again = look_again and bool(ks)
    if look_again:
        # further combs near the same nominal frequency, on a finer spectrum with the tracked
        # comb's lines (widened by how far the track wandered) masked out
        f_med = trk.median_f0(det.mains_hz)
        spread = float(np.ptp(trk.f0)) if len(trk.f0) > 1 else 0.0
        log.debug("track spread %.4f Hz", spread)
        seg_hr = float(np.clip(N / sr / 4, 4.0, 16.0))
        spec_fine = _detect.excerpt_spectrum(source, seg_s=seg_hr,
                                             keep_segments_hz=top + 2 * _detect.FLOOR_WIDTH_HZ)
        df_hr = spec_fine.df
        # as far up as the comb the spectrum showed (a line there that is not locked to the
        # track may belong to a further comb), at most twice the locked comb's reach
        k_top = max([k for k in ks_spec if k <= 2 * max(ks)] + ks)
        known = [(k * f_med, 2 * df_hr + 0.5 * k * spread) for k in ks] + [(t, 2 * df_hr) for t in tl]
        combs = _combs.detect_extra_combs(spec_fine, sr, det.nominal_hz, known, min_sep_hz=1.5 * sr / (2 * hop),
                                          alpha=alpha, max_hz=max_hz, max_combs=max_combs - 1,
                                          max_harmonic=k_top, main_f0=f_med)
    tl = _combs.refine_combs(source, sr, combs, f_med, spec_fine, tones=tl)
    names = [f"h{k}" for k in ks] + [f"tone_{t:g}Hz" for t in tl]
    comb_tones = [k * c.fundamental_hz for c in combs for k in c.harmonics]
    names += [f"c{i + 2}_h{k}" for i, c in enumerate(combs) for k in c.harmonics]
    tl_fit = list(tl) + comb_tones
    fixed_lines = list(tl) + [(c.fundamental_hz, c.harmonics) for c in combs]

    f_top = max([k * (det.mains_hz or 0.0) * 1.01 for k in ks] + [float(t) for t in tl_fit] + [1.0])
    gram_step = max(1, int(sr // (4 * f_top + 1)))
    # local noise floor at every line (for pooling amplitudes across blocks)
    main_psd = fixed_psd = None
    if ks or tl_fit:
        all_f = [k * f_med for k in ks] + tl_fit
        fl_all = [(f, 2 * spec_fine.df) for f in all_f]
        psd = np.stack([_detect.line_level(spec_fine, f, 2 * spec_fine.df,
                                           [e for e in fl_all if abs(e[0] - f) > 1e-9])["floor"] for f in all_f])
        if np.isfinite(psd).all():
            main_psd, fixed_psd = (psd[: len(ks)] if ks else None), (psd[len(ks):] if tl_fit else None)
    amps, phs, valid, overall = _blockfit.fit_pass(source, sink, hop=hop, trk=trk, ks=ks, fixed_lines=fixed_lines,
                                          names=names, solver=solver, random_state=random_state,
                                          gram_step=gram_step, fixed_psd=fixed_psd,
                                          main_psd=main_psd if POOL_MAIN else None,
                                          smooth_blocks=SMOOTH_BLOCKS,
                                          tick=tick)
    if bar is not None:
        bar.close()
    if h_amp:
        # harmonics: the generalised least-squares amplitudes (amplitude.py) replace the pooled ones
        if overall is None:
            overall = np.full((C, len(names)), np.nan)
        overall[:, : len(ks)] = np.stack([h_amp[k] for k in ks], axis=1)

    out_src = after_source_fn()
    spec_after = _detect.excerpt_spectrum(out_src)
    out_src.close()
    # (without hum the track is all zeros and never confident)
    f_med = trk.median_f0(det.mains_hz)
    line_f = [k * f_med for k in ks] + list(tl_fit)
    before = _detect.line_levels(spec_before, line_f)
    after = _detect.line_levels(spec_after, line_f)
    return DenoiseResult(
        y=None, hum=None, sr=sr, mains_hz=f_med, nominal_hz=det.nominal_hz, harmonics=ks, tones=tl,
        extra_combs=[{"fundamental_hz": c.fundamental_hz, "harmonics": c.harmonics} for c in combs],
        line_freqs=line_f,
        track_t=trk.t, track_hz=trk.f0 if ks else np.zeros(0), amplitudes=amps, phases=phs,
        line_names=names, levels_before=before, levels_after=after,
        candidates=det.candidates + [c for comb in combs for c in comb.candidates],
        block_valid=valid, amplitude_overall=overall,
        info={"solver": solver, "block_s": 2 * hop / sr, "channels": C, "frames": N, "duration_s": N / sr},
        spectra={"freqs": spec_before.freqs, "before": spec_before.psd, "after": spec_after.psd},
    )
