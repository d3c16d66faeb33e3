"""The passes of ``denoise`` (api.py): remove mains hum (tracked fundamental + harmonics) and named
tones from audio.

Pipeline (all passes stream in blocks, so memory does not grow with the file length):

1. detection on a Welch spectrum: fundamental (50/60 Hz or given), harmonics present, tones;
2. pass 1: demodulated 10 ms chunk sums -> block length (blocklen.py) and per-block fundamental
   track (track.py); gaps in the comb looked at again on the tracked baseband (baseband.py);
   further steady combs near the main one (combs.py); steady content lines within a cell or two
   of a hum line (a drum loop's line at exactly 60 Hz under a 60.045 Hz hum) fitted with the hum,
   taken out of the chunk sums and of pass 2's input, and kept (hostlines.py); whole-input
   amplitudes of the harmonics by generalised least squares on the same chunk sums (amplitude.py);
3. pass 2 (blockfit.py): per 50 %-overlapping block, weighted least squares of the samples on the
   tracked harmonic basis plus the fixed lines (fit.py, fullblock.py), amplitudes pooled across
   blocks where the lines are steady, fitted hum windowed by sin^2 (the windows sum to one, so
   blocks join without clicks), subtracted and written progressively;
4. line levels above the local floor before and after, for the report (result.py).

Where the whole input shows no hum, stretches of it where harmonics stand segment after segment
(a device switched on for part of the take) are analysed and fitted as inputs of their own
(humspans.py, spanrun.py); the rest is written as read.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, replace

import numpy as np

from odnn_sep.audio import amplitude as _amplitude
from odnn_sep.audio import blockfit as _blockfit
from odnn_sep.audio import blocklen as _blocklen
from odnn_sep.audio import combs as _combs
from odnn_sep.audio import detect as _detect
from odnn_sep.audio import envelope as _envelope
from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import hostlines as _hostlines
from odnn_sep.audio import humspans as _humspans
from odnn_sep.audio import inputclip as _inputclip
from odnn_sep.audio import lockcomb as _lockcomb
from odnn_sep.audio import silence as _silence
from odnn_sep.audio import spanrun as _spanrun
from odnn_sep.audio import steadypath as _steadypath
from odnn_sep.audio import track as _track
from odnn_sep.audio.background import Background
from odnn_sep.audio.blockplan import BlockPlan
from odnn_sep.audio.lines import LineSet
from odnn_sep.audio.options import DenoiseOptions, families_in_reach, progress_bar
from odnn_sep.audio.result import DenoiseResult
from odnn_sep.core.threads import one_blas_thread
from odnn_sep.errors import InputError

log = logging.getLogger(__name__)

SMOOTH_BLOCKS = 4   # line amplitudes pooled over up to this many blocks on each side (blockfit.py)
POOL_MAIN = True    # pool the tracked comb too (in the track's common phase reference), not only fixed lines
MAX_COMBS = 3       # the main comb and at most this many less one further combs
MIN_S = 0.2         # shortest input (s)
HOST_LINES = True   # steady content lines right beside a hum line fitted with it and kept (hostlines.py)
HOST_BAND_BLOCKS = 2.0   # ... looked for within this many cells of a block (2 / block_s Hz: the block window's main lobe)


def run(source, sink, opts: DenoiseOptions, *, after_source_fn):
    """All passes over ``source`` (an ArraySource or FileSource); the cleaned samples go through
    ``sink(piece, removed)``. ``opts`` as given by the caller (validated here, once);
    ``after_source_fn()``: the written output as a source, for the line levels after. Returns the
    DenoiseResult.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input, read twice in bounded blocks.
    sink : callable
        ``sink(piece, removed)``: receives each stretch of input and the hum fitted to it, in order.
    opts : DenoiseOptions
        The options as given.
    after_source_fn : callable
        Returns the written output as a source, once every piece went through ``sink``.

    Returns
    -------
    DenoiseResult
        Without ``y`` and ``hum`` (the sink has them).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000); out = []
    >>> r = run(ArraySource(y, sr), lambda piece, removed: out.append(piece - removed), DenoiseOptions(),
    ...         after_source_fn=lambda: ArraySource(np.concatenate(out), sr))
    >>> r.harmonics[:2], sum(len(o) for o in out)
    ([1, 2], 24000)
    """
    # Many small matrix products: BLAS threads only add spin-wait overhead here (and collapse
    # when the machine is busy), so run them single-threaded.
    # pass 2 sees every input sample: it counts the clipped ones on the way
    watch = _inputclip.ClipWatch(sink, _inputclip.full_scale(source))
    with one_blas_thread():
        res = _run_inner(source, watch, opts, after_source_fn)
    clipped = watch.message()
    if clipped:
        log.warning(clipped)
        res.info["input_clipped"] = round(watch.share, 6)
    return res


@dataclass
class _Found:
    """What the analysis passes found: the spectra, the detection, the locked comb's track and
    block plan, the lines, and the whole-input harmonic amplitudes."""

    spec_before: object
    spec_fine: object
    det: object
    plan: BlockPlan
    trk: object
    lines: LineSet
    f_med: float | None
    h_amp: dict
    main_amps: object = None
    envelope: object = None
    hum_spans: list | None = None   # hum over part of the input only (humspans.py)
    second_hum: dict | None = None  # a weaker hum of the other mains family, left in (lockcomb._second_hum)
    host_lines: list | None = None  # steady content lines beside hum lines, kept (hostlines.py)


def _run_inner(source, sink, opts: DenoiseOptions, after_source_fn):
    opts = opts.validated(source.sr)
    sr, N = source.sr, source.frames
    if N < MIN_S * sr:
        raise InputError(f"input is too short ({N} samples = {N / sr:.3f} s at {sr} Hz) to resolve mains hum; "
                         f"pass at least {MIN_S:g} s of audio")
    sink = _silence.KeepSilence(source, sink)
    stretches = _silence.sounding_stretches(source, int(MIN_S * sr))
    if stretches != [(0, N)]:
        # digital silence (exact zeros) holds no hum: the stretches between are the inputs analysed
        return _run_sounding(source, sink, opts, after_source_fn, stretches)
    found, bar = _analyse(source, opts)
    tick = (lambda k: bar.update(k)) if bar is not None else None
    parts = (_spanrun.span_parts(source, opts, found, _analyse) if _nothing_found(found)
             else _spanrun.lone_line_part(source, opts, found, _analyse))
    if parts:
        amps, phs, valid, overall = _spanrun.fit_parts(source, sink, opts, parts, tick, _fit)
        found = _spanrun.with_spans(found, parts)
    else:
        if _nothing_found(found):
            _warn_none(source, opts, found.spec_before)
        amps, phs, valid, overall = _fit(source, sink, opts, found, tick)
    if bar is not None:
        bar.close()
    return _result(found, opts, after_source_fn, amps, phs, valid, overall, source)


def _run_sounding(source, sink, opts: DenoiseOptions, after_source_fn, stretches):
    """The passes on each of ``stretches`` ``[(first frame, frames)]`` (between the input's digital
    silences, silence.py) as an input of its own, the silences written as read; the report's spans
    and track on the input's clock, its levels on the longest stretch."""
    if len(stretches) > 1:
        opts = replace(opts, progress=False)        # one bar per stretch would only confuse
    parts, base, bar = [], None, None
    for a, n in stretches:
        sub = _humspans.SliceSource(source, a, n)
        found, bar = _analyse(sub, opts)
        inner = (_spanrun.span_parts(sub, opts, found, _analyse) if _nothing_found(found)
                 else _spanrun.lone_line_part(sub, opts, found, _analyse))
        parts += [(a + a2, n2, f2) for a2, n2, f2 in inner] or [(a, n, found)]
        if base is None or n > base[1]:
            base = (a, n, found, sub)
    a, n, found, sub = base
    tick = (lambda k: bar.update(k)) if bar is not None else None
    # stretches without hum are written as read, like the silences
    parts = [p for p in parts if not _nothing_found(p[2])]
    if not parts:
        _warn_none(source, opts, found.spec_before)
    amps, phs, valid, overall = _spanrun.fit_parts(source, sink, opts, parts or [(a, n, found)], tick, _fit)
    if parts:
        found = _spanrun.with_spans(found, parts)
    if bar is not None:
        bar.close()
    log.info("digital silence: the input sounds over %s s only; the zeros are written as read",
             ", ".join(f"{a2 / source.sr:.2f}-{(a2 + n2) / source.sr:.2f}" for a2, n2 in stretches))
    return _result(found, opts, lambda: _humspans.SliceSource(after_source_fn(), a, n), amps, phs, valid,
                   overall, sub)


def _nothing_found(found) -> bool:
    return not found.lines.harmonics and not found.lines.fixed_freqs


def _warn_none(source, opts: DenoiseOptions, spec=None):
    # only the families with a line under the highest one tested at this rate were looked for
    # (at 128 Hz the 60 Hz line is never tested)
    asked = (50.0, 60.0) if opts.mains == "auto" else (opts.mains,)
    fams = families_in_reach(opts.mains, opts.harmonics, opts.max_hz, source.sr)
    tested = " and ".join(f"{f:g}" for f in fams) + " Hz" if fams else "no mains family"
    out = [f"{f:g}" for f in asked if f not in fams]
    if out:
        tested += (f"; {' and '.join(out)} Hz {'lies' if len(out) == 1 else 'lie'} above the highest line tested "
                   f"at sr={source.sr}")
    log.warning("no mains hum found (tested %s; lines must be phase-locked to one fundamental and "
                "persist); the output equals the input%s%s", tested, _short_hint(source.frames / source.sr, opts),
                _other_family_hint(source, spec, opts) if spec is not None else "")


def _analyse(source, opts: DenoiseOptions):
    """Detection, phase-locked comb, block plan and track, further combs: a :class:`_Found` and
    the progress bar (or None)."""
    sr, N = source.sr, source.frames
    top = min(_detect.top_hz(sr, opts.max_hz),
              (_detect.MAX_HARMONICS + 1) * (65.0 if opts.mains == "auto" else opts.mains))
    keep_hz = top + 2 * _detect.FLOOR_WIDTH_HZ
    spec_before = _detect.excerpt_spectrum(source, keep_segments_hz=keep_hz)
    det = _detect.detect_hum(spec_before, sr, mains=opts.mains, harmonics=opts.harmonics, tones=opts.tones,
                             alpha=opts.alpha, max_hz=opts.max_hz)
    ks_spec = list(det.harmonics)
    # the spectrum's work arrays (two threads, two heap arenas) are freed: handed back before the
    # chunk sums, the analysis's largest arrays, are made
    release_freed_memory()
    bar = progress_bar(opts.progress, (2 if det.harmonics else 1) * N, "denoise")
    tick = (lambda k: bar.update(k)) if bar is not None else None
    comb = _lockcomb.choose(source, spec_before, det, mains=opts.mains, harmonics=opts.harmonics,
                            alpha=opts.alpha, max_hz=opts.max_hz, tones=det.tones,
                            progress=tick) if det.harmonics else None
    ks = comb.harmonics if comb is not None else []
    # only when the harmonics are the data's choice: a given count or list is removed as given
    further = bool(ks) and opts.harmonics == "auto" and MAX_COMBS > 1
    with Background() as bg:
        # the finer spectrum of the further-comb search depends on the input only: it is computed
        # (from a second handle on the file) while the track and amplitudes are made
        fine = bg.spectrum(source, keep_hz) if further else None
        plan, trk, h_amp, main_amps, env, host = _plan_and_track(source, opts, det, comb, bg)
        if ks and _off_nominal(trk, comb.nominal_hz, N / sr):
            comb, ks, further = None, [], False
            det.harmonics = []
            plan, trk, h_amp, main_amps, env, host = _plan_and_track(source, opts, det, None, bg)
        # the finest spectrum at hand: the high-resolution one when the comb is looked at again
        combs, f_med, spec_fine = [], det.mains_hz, spec_before
        if further:
            combs, f_med, spec_fine = _further_combs(source, opts, det, trk, plan, ks, ks_spec, fine.result())
    tones = _combs.refine_combs(source, sr, combs, f_med, spec_fine, tones=det.tones)
    lines = LineSet(harmonics=ks, tones=tones, combs=combs)
    second = comb.second_hum if ks else None
    if second:
        log.warning("a second hum locks on the %g Hz grid as well (%.3f Hz; harmonics %s; %.0f dB under the %g Hz "
                    "hum removed); one run removes one hum: run denoise again on the output with --mains %g to "
                    "remove it", second["nominal_hz"], second["fundamental_hz"], ", ".join(map(str, second["harmonics"])),
                    -second["power_db"], comb.nominal_hz, second["nominal_hz"])
    if ks and all(_on_other_grid(k * f_med, opts) for k in ks):
        hint = _other_family_hint(source, spec_before, opts)
        if hint:
            log.warning("every line removed (%s) is a harmonic of %g Hz as well%s",
                        ", ".join(f"h{k} at {k * f_med:.1f} Hz" for k in ks), 110.0 - opts.mains, hint)
    return _Found(spec_before, spec_fine, det, plan, trk, lines, f_med, h_amp, main_amps, env,
                  second_hum=second, host_lines=host or None), bar


def _on_other_grid(f: float, opts: DenoiseOptions) -> bool:
    """Whether ``f`` (Hz) lies within 0.5 % of a harmonic of the other mains family than the 50 or
    60 Hz asked for (300 Hz is 6 x 50 and 5 x 60); False when mains is not 50 or 60."""
    if opts.mains not in (50.0, 60.0):
        return False
    other = 110.0 - opts.mains
    return abs(f - round(f / other) * other) <= 0.005 * f


def _other_family_hint(source, spec, opts: DenoiseOptions) -> str:
    """Where the mains asked for is 50 or 60 Hz and the spectrum shows two lines or more of the
    other family: what the warnings add (the data's hum is likely the other one). A European take
    given --mains 60 had its 300 Hz line removed as "h5 of 59.99 Hz" and its 50 Hz hum left."""
    if opts.mains not in (50.0, 60.0) or opts.harmonics != "auto":
        return ""
    other = 110.0 - opts.mains
    d2 = _detect.detect_hum(spec, source.sr, mains=other, harmonics="auto", alpha=opts.alpha, max_hz=opts.max_hz)
    if len(d2.harmonics) < 2:
        return ""
    # the lock tests too: the spectrum alone shows lines of either family in held notes
    comb = _lockcomb.choose(source, spec, d2, mains=other, harmonics="auto", alpha=opts.alpha,
                            max_hz=opts.max_hz, tones=[])
    ks = comb.harmonics if comb is not None else []
    if len(ks) < 2:
        return ""
    return (f"; the input holds a hum of {other:g} Hz mains ({', '.join(f'h{k}' for k in ks[:8])}"
            f"{', ...' if len(ks) > 8 else ''} lock to {comb.f_ref:.3f} Hz): run again with --mains {other:g} "
            f"(or leave --mains out)")


SHORT_HINT_S = 1.0   # under this, the lock tests cannot tell hum from a held note (the hint says so)


def _short_hint(seconds: float, opts: DenoiseOptions) -> str:
    """What a short input's "no hum found" adds: under ``SHORT_HINT_S`` the lock tests cannot tell
    hum from a held note (0.25-0.6 s clips with hum 10 dB over white noise found nothing; with the
    lines named, 27-41 dB of it was removed), so the lines must be named; empty when the lines were.

    Examples
    --------
    >>> _short_hint(0.4, DenoiseOptions())[:42]
    '; the input is only 0.40 s long: under 1 s'
    >>> _short_hint(5.0, DenoiseOptions())
    ''
    """
    if seconds >= SHORT_HINT_S or opts.harmonics != "auto":
        return ""
    return (f"; the input is only {seconds:.2f} s long: under {SHORT_HINT_S:g} s the lock tests cannot tell hum from "
            "a held note, so name the lines if the clip holds hum (e.g. --mains 50 --harmonics 1,2,3)")


OFF_NOMINAL = 0.0125   # a track that never comes nearer its nominal than this share is not mains hum
# Under 2 s a spectrum bin is 0.5 Hz or wider, and a held note's partial 1 % off a harmonic passes
# the lock test as well as hum would (the test cannot tell frequencies closer than 1/duration): there
# the fundamental must sit within 0.5 % of the nominal (a grid's deviation and a clock offset are
# far smaller; 3 of 256 hum-free excerpts of 0.7-1.9 s were otherwise taken for hum at 49.5 Hz)
SHORT_OFF_NOMINAL = 0.005


def _off_nominal(trk, nominal: float, duration_s: float) -> bool:
    """True when the tracked fundamental stays more than ``OFF_NOMINAL`` of ``nominal`` away from
    it throughout (with a log line saying so). Step 1 refines the fundamental within 1 % of
    50/60 Hz (a grid's deviation and a sound card's clock offset); the track may then follow a
    line outside that range, and a steady 61 Hz tone was removed as "hum at 60.9989 Hz". A drift
    that passes through the nominal range (a ramp of 50 mHz/s over a minute) is kept."""
    # blocks centred inside the input (one past the end holds no data: the reference there)
    inside = trk.confident & (trk.t <= duration_s)
    f = trk.f0[inside]
    if not len(f):
        return False
    off = float(np.min(np.abs(f - nominal))) / nominal
    limit = SHORT_OFF_NOMINAL if duration_s < _lockcomb.SHORT_INPUT_S else OFF_NOMINAL
    if off > limit:
        log.warning("the line tracked at %.2f-%.2f Hz never comes within %.3g %% of %g Hz (it is %.1f %% off): "
                    "not mains hum, left in; pass --tone to remove it", float(f.min()), float(f.max()),
                    100 * limit, nominal, 100 * off)
        return True
    return False


def _plan_and_track(source, opts: DenoiseOptions, det, comb, bg: Background):
    """Block plan, track (all zeros without hum), whole-input harmonic amplitudes (one of the
    computations from the chunk sums in ``bg``'s thread), amplitude paths, the shared hum
    level (envelope.py) and the steady content lines beside the hum lines (hostlines.py, taken
    out of the chunk sums before the amplitudes); the locked comb's family and lock statistics go
    into ``det``."""
    sr, N = source.sr, source.frames
    block_s = opts.block_s
    if opts.auto_block and (comb is None or N < 3 * _blocklen.CANDIDATES_S[-1] * sr):
        block_s = _blocklen.CANDIDATES_S[0]
    if comb is None:
        plan = BlockPlan.from_block_s(block_s, sr, N)
        z = np.zeros(plan.count)
        trk = _track.Track(t=plan.centres_s, f0=z, rate=z, curv=z, confident=np.zeros(plan.count, bool),
                           strength=z)
        return plan, trk, {}, None, None, []
    ks = comb.harmonics
    det.mains_hz, det.nominal_hz = comb.f_ref, comb.nominal_hz
    # the lock test's own p-value: the bar it passed depends on the family and on what the comb
    # already held (combpattern.py, lockcomb._test_count), so it is not reported as corrected
    det.candidates += [{"family_hz": comb.nominal_hz, "harmonic": k, "freq_hz": k * comb.f_ref,
                        "p_value": p, "lock_index": ix, "significant": k in ks,
                        "look": "phase lock"} for k, (p, ix, _) in sorted(comb.lock.items())]
    if block_s == "auto":
        block_s = _blocklen.choose_block_phase(comb.D, comb.psi, sr, N, comb.f_ref, ks)
    plan = BlockPlan.from_block_s(block_s, sr, N)
    trk = _finetrack.track_from_phase(comb.psi, comb.f_ref, plan, comb.jumps)
    amps = _comb_amplitudes(comb, sr, ks, trk, plan, bg)
    # steady content lines beside the hum lines, where the hum's level holds (the joint fit takes
    # one hum amplitude for the whole input: a level that steps leaves sidebands like lines)
    host = (_hostlines.find(comb.D, sr, comb.f_ref, ks, comb.psi, HOST_BAND_BLOCKS / plan.block_s,
                            weighted=plan.count >= _steadypath.MIN_BLOCKS)
            if HOST_LINES and not comb.jumps and amps[2] is None else [])
    if host:
        log.info("content lines beside the hum kept: %s", ", ".join(f"{h.freq_hz:.3f} Hz (by h{h.harmonic})"
                                                                   for h in host))
        comb.D = comb.D - _hostlines.chunk_sums(host, comb.D.shape[0], sr, comb.f_ref, ks)
        amps = _comb_amplitudes(comb, sr, ks, trk, plan, bg)
    h_amp, main_amps, env = amps
    if env is not None:
        log.info("the hum level changes within the blocks: followed at %.1f s (gain %.2f-%.2f)",
                 env.width_s, float(env.gain.min()), float(env.gain.max()))
    comb.D = None
    return plan, trk, h_amp, main_amps, env, host


def _comb_amplitudes(comb, sr: int, ks, trk, plan: BlockPlan, bg: Background):
    """From the comb's chunk sums: the whole-input amplitudes of the harmonics (by line, in ``bg``'s
    thread), the amplitude paths and the shared hum level (envelope.py, or None)."""
    steady = bg.submit(_amplitude.steady_amplitudes, comb.D, comb.f_ref, ks, trk, plan)
    means = _steadypath.block_means(comb.D, sr, ks, comb.psi, plan, keep_power=True)
    main_amps = _steadypath.comb_block_amplitudes(comb.D, sr, comb.f_ref, ks, comb.psi, plan, means=means,
                                                  jumps=comb.jumps)
    env = _envelope.shared_envelope(comb.D, sr, comb.f_ref, ks, comb.psi, plan, main_amps, means[4],
                                    jumps=comb.jumps)
    return dict(zip(ks, steady.result().T, strict=True)), main_amps, env


def _further_combs(source, opts: DenoiseOptions, det, trk, plan: BlockPlan, ks, ks_spec, spec_fine):
    """Further combs near the same nominal frequency, on the finer spectrum ``spec_fine``
    (:func:`background.fine_spectrum`) with the tracked comb's lines (widened by how far the track wandered)
    masked out: ``(combs, f_med, spec_fine)``."""
    sr = source.sr
    f_med = trk.median_f0(det.mains_hz)
    spread = float(np.ptp(trk.f0)) if len(trk.f0) > 1 else 0.0
    log.debug("track spread %.4f Hz", spread)
    df_hr = spec_fine.df
    # as far up as the comb the spectrum showed (a line there that is not locked to the
    # track may belong to a further comb), at most twice the locked comb's reach
    k_top = max([k for k in ks_spec if k <= 2 * max(ks)] + ks)
    known = [(k * f_med, 2 * df_hr + 0.5 * k * spread) for k in ks] + [(t, 2 * df_hr) for t in det.tones]
    combs = _combs.detect_extra_combs(spec_fine, sr, det.nominal_hz, known,
                                      _combs.CombSearch(min_sep_hz=1.5 * sr / (2 * plan.hop), alpha=opts.alpha,
                                                        max_hz=opts.max_hz, max_combs=MAX_COMBS - 1,
                                                        max_harmonic=k_top, main_f0=f_med))
    return combs, f_med, spec_fine


def _fit(source, sink, opts: DenoiseOptions, found: _Found, tick):
    """Pass 2 (blockfit.py) with the local noise floor at every line (for pooling amplitudes
    across blocks); the harmonics' whole-input amplitudes replace the pooled ones."""
    lines, spec_fine, f_med, det = found.lines, found.spec_fine, found.f_med, found.det
    ks, fixed_freqs = lines.harmonics, lines.fixed_freqs
    f_top = max([k * (det.mains_hz or 0.0) * 1.01 for k in ks] + [float(t) for t in fixed_freqs] + [1.0])
    main_psd = fixed_psd = None
    if ks or fixed_freqs:
        all_f = [k * f_med for k in ks] + fixed_freqs
        fl_all = [(f, 2 * spec_fine.df) for f in all_f]
        psd = np.stack([_detect.line_level(spec_fine, f, 2 * spec_fine.df,
                                           [e for e in fl_all if abs(e[0] - f) > 1e-9])["floor"] for f in all_f])
        if np.isfinite(psd).all():
            main_psd, fixed_psd = (psd[: len(ks)] if ks else None), (psd[len(ks):] if fixed_freqs else None)
    settings = _blockfit.FitSettings(solver=opts.solver, random_state=opts.random_state,
                                     gram_step=max(1, int(source.sr // (4 * f_top + 1))), fixed_psd=fixed_psd,
                                     main_psd=main_psd if POOL_MAIN else None, smooth_blocks=SMOOTH_BLOCKS,
                                     main_amps=found.main_amps, envelope=found.envelope)
    release_freed_memory()
    if found.host_lines:
        # the hum is fitted on the input less the content lines beside it; the output keeps them
        source, sink = _hostlines.WithoutLines(source, found.host_lines), _read_again(source, sink)
    amps, phs, valid, overall = _blockfit.fit_pass(source, sink, found.plan, found.trk, lines, settings, tick=tick)
    if found.h_amp:
        # harmonics: the generalised least-squares amplitudes (amplitude.py) replace the pooled ones
        if overall is None:
            overall = np.full((source.channels, len(lines.names)), np.nan)
        overall[:, : len(ks)] = np.stack([found.h_amp[k] for k in ks], axis=1)
    return amps, phs, valid, overall


def _read_again(source, sink):
    """A sink that hands ``sink`` the input's own samples (read again from ``source``, in order)
    with the hum removed: the pieces pass 2 read had the content lines taken out."""
    pos = [0]

    def back(piece, removed):
        n = piece.shape[0]
        sink(source.read(pos[0], n), removed)
        pos[0] += n

    return back


def release_freed_memory():
    """Give the heap memory the analysis freed back to the system before pass 2 (glibc keeps
    freed chunks of the chunk sums' size for reuse: tens of MB on an hour of audio, which
    pass 2's own arrays would then add to). Does nothing where the C library has no
    ``malloc_trim``.

    Examples
    --------
    >>> release_freed_memory()
    """
    import ctypes
    import ctypes.util

    try:
        libc = ctypes.CDLL(ctypes.util.find_library("c") or "libc.so.6")
        libc.malloc_trim(0)
    except (OSError, AttributeError):  # pragma: no cover - not glibc
        pass


def _result(found: _Found, opts: DenoiseOptions, after_source_fn, amps, phs, valid, overall, source):
    """Line levels before and after, and the DenoiseResult."""
    out_src = after_source_fn()
    spec_after = _detect.excerpt_spectrum(out_src)
    out_src.close()
    det, trk, lines = found.det, found.trk, found.lines
    ks = lines.harmonics
    # (without hum the track is all zeros and never confident)
    f_med = trk.median_f0(det.mains_hz)
    line_f = [k * f_med for k in ks] + lines.fixed_freqs
    sr, N, C = source.sr, source.frames, source.channels
    isolated = isolated_lines(_peak_amplitudes(found.spec_before, ks, f_med))
    for k, db in isolated:
        others = ",".join(str(j) for j in ks if j != k)
        log.warning("line h%d (%.1f Hz) stands %.0f dB above every other line of the hum, with no harmonic beside "
                    "it: a steady tone at a multiple of the mains frequency cannot be told from hum, and it was "
                    "removed; if it is content (a test tone, a note), keep it with --harmonics %s",
                    k, k * f_med, db, others or "(none)")
    res = DenoiseResult(
        y=None, hum=None, sr=sr, mains_hz=f_med, nominal_hz=det.nominal_hz, harmonics=ks, tones=lines.tones,
        extra_combs=[{"fundamental_hz": c.fundamental_hz, "harmonics": c.harmonics} for c in lines.combs],
        line_freqs=line_f,
        track_t=trk.t, track_hz=trk.f0 if ks else np.zeros(0), amplitudes=amps, phases=phs,
        line_names=lines.names, levels_before=_detect.line_levels(found.spec_before, line_f),
        levels_after=_detect.line_levels(spec_after, line_f),
        candidates=det.candidates + [c for comb in lines.combs for c in comb.candidates],
        block_valid=valid, amplitude_overall=overall,
        info={"solver": opts.solver, "block_s": found.plan.block_s, "channels": C, "frames": N,
              "duration_s": N / sr, "isolated_lines": [k for k, _ in isolated], "level_followed_s": found.envelope.width_s if found.envelope else None,
              # where that level steps (a load switched, a device turned on or off: envelope.level_steps)
              "level_steps_s": list(found.envelope.steps_s) if found.envelope else [],
              # hum over part of the input only (humspans.py): where, and what each stretch held
              "hum_spans": found.hum_spans or [],
              # steps of the hum's phase kept whole (a splice, a source switched over: phasejumps.py)
              "phase_steps": [{"time_s": a / sr, "cycles": d}
                              for a, d in getattr(getattr(trk, "phase", None), "jumps", None) or []]},
        spectra={"freqs": found.spec_before.freqs, "before": found.spec_before.psd, "after": spec_after.psd},
    )
    if found.second_hum:
        # a weaker hum of the other mains family, locked too and left in (a second run removes it)
        res.info["second_hum"] = found.second_hum
    return res


def _peak_amplitudes(spec, ks, f0) -> dict:
    """Harmonic -> the square root of its peak PSD (channels pooled) within its band: proportional
    to a steady line's amplitude, whatever the input's length (the whole-input fit needs 3 blocks)."""
    out = {}
    for k in ks:
        sel = np.abs(spec.freqs - k * f0) <= _detect.band_halfwidth(spec, k)
        if sel.any():
            out[k] = np.sqrt(np.array([spec.psd[sel].sum(axis=1).max()]))
    return out


ISOLATED_ABOVE_K = 5    # lines above this harmonic may be content that happens to sit on the comb
ISOLATED_DB = 12.0      # ... when they stand this far above every other line


def isolated_lines(h_amp: dict) -> list[tuple[int, float]]:
    """Harmonics above ``ISOLATED_ABOVE_K`` that stand ``ISOLATED_DB`` or more above every other
    line of the comb and have no other harmonic within two of them: ``[(k, dB above the next
    strongest line)]``. Mains hum is strongest low down or spread over many harmonics (a dimmer,
    a rectifier); one loud line far up with nothing beside it is more often a test tone or a held
    note at a multiple of 50/60 Hz, which a steady hum cannot be told from (both are locked).

    Parameters
    ----------
    h_amp : dict
        Harmonic -> amplitude per channel (or any measure proportional to it).

    Returns
    -------
    list of (int, float)

    Examples
    --------
    >>> isolated_lines({1: np.array([0.05]), 20: np.array([0.3])})
    [(20, 15.6)]
    >>> isolated_lines({1: np.array([0.05]), 2: np.array([0.3])})        # low down: hum
    []
    """
    amp = {int(k): float(np.max(np.abs(v))) for k, v in h_amp.items()}
    out = []
    for k, a in amp.items():
        rest = [b for j, b in amp.items() if j != k]
        if k <= ISOLATED_ABOVE_K or not rest or any(abs(j - k) <= 2 for j in amp if j != k):
            continue
        db = 20 * np.log10(a / max(max(rest), 1e-300))
        if db >= ISOLATED_DB:
            out.append((k, round(float(db), 1)))
    return out
