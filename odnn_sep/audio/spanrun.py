"""Hum over part of the input only, run through the passes of pipeline.py: the stretches
humspans.py finds (or a lone line's extent) are analysed and fitted as inputs of their own, the
rest of the input goes to the sink as read, and the report is the longest stretch's with every
stretch listed. The pipeline's own analysis and fit are passed in (``analyse``, ``fit``)."""
from __future__ import annotations

import logging
from contextlib import contextmanager
from dataclasses import replace

import numpy as np

from odnn_sep.audio import humspans as _humspans
from odnn_sep.audio.options import DenoiseOptions

log = logging.getLogger(__name__)


def span_parts(source, opts: DenoiseOptions, found, analyse) -> list:
    """Hum over part of the input only (humspans.py): ``[(first frame, frames, _Found)]`` of
    the stretches whose own analysis locks ``humspans.MIN_LINES`` harmonics or more; empty
    where the lines were named (the whole input is then the user's choice) or tones given.
    ``analyse`` is pipeline._analyse.

    Examples
    --------
    >>> from odnn_sep.audio import pipeline
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(24 * sr) / sr
    >>> hum = ((t > 10) & (t < 16)) * (np.cos(2 * np.pi * 50.02 * t) + np.cos(2 * np.pi * 100.04 * t))
    >>> y = hum + 0.3 * np.random.default_rng(0).standard_normal(t.size)
    >>> src, opts = ArraySource(y, sr), DenoiseOptions().validated(sr)
    >>> found, _ = pipeline._analyse(src, opts)              # the whole input: nothing locks
    >>> found.lines.harmonics
    []
    >>> [(round(a / sr, 2), round((a + n) / sr, 2), f.lines.harmonics)
    ...  for a, n, f in span_parts(src, opts, found, pipeline._analyse)]
    [(10.0, 16.0, [1, 2])]
    """
    if opts.harmonics != "auto" or opts.tones:
        return []
    nominals = (50.0, 60.0) if opts.mains == "auto" else (float(opts.mains),)
    stretches = _humspans.find_stretches(found.spec_before, source.sr, source.frames, nominals)
    parts = []
    # a stretch is picked where lines stand: its tests get a stricter level (two held note partials
    # over 7 s of a synthesised voice locked to one fundamental at p = 9e-5)
    quiet = replace(opts, progress=False, alpha=opts.alpha * _humspans.ALPHA_SHARE)
    for a0, n0, nominal in stretches:
        a, n = _humspans.tighten(source, a0, n0, nominal)
        if not _humspans.enough_lines(_humspans.SliceSource(source, a, n), quiet):
            continue            # music proposes stretches too: most go here, before the lock tests
        with _quiet_logs():
            f_sub, _ = analyse(_humspans.SliceSource(source, a, n), quiet)
            ks = f_sub.lines.harmonics
            cut = _humspans.cut_at_switches(source, a, n, f_sub.f_med, ks) if len(ks) >= _humspans.MIN_LINES else (a, n)
            if cut != (a, n):
                # the hum switches on or off inside the stretch: analysed again between the switches,
                # with the lines found named where the data alone lose some (a shorter stretch gives
                # the lock test less to go on)
                f_cut, _ = analyse(_humspans.SliceSource(source, *cut), quiet)
                if not set(f_sub.lines.harmonics) <= set(f_cut.lines.harmonics):
                    f_cut, _ = analyse(_humspans.SliceSource(source, *cut),
                                        replace(quiet, harmonics=list(f_sub.lines.harmonics), mains=f_sub.det.nominal_hz))
                if len(f_cut.lines.harmonics) >= _humspans.MIN_LINES:
                    (a, n), f_sub = cut, f_cut
        if len(f_sub.lines.harmonics) >= _humspans.MIN_LINES:
            log.info("hum over %.1f-%.1f s only: %.4f Hz, harmonics %s", a / source.sr, (a + n) / source.sr,
                     f_sub.f_med, f_sub.lines.harmonics)
            parts.append((a, n, f_sub))
    return parts


def lone_line_part(source, opts: DenoiseOptions, found, analyse) -> list:
    """A lone hum line the whole input's analysis found, absent for seconds at the input's start
    or end (humspans.hum_extent): ``[(first frame, frames, _Found)]`` of where it sounds, cut at
    its switches and analysed there for the same line; empty otherwise, and where the lines were
    named, tones given or other lines found (several lines share a level that follows a switch:
    envelope.py). ``analyse`` is pipeline._analyse.

    Examples
    --------
    >>> from odnn_sep.audio import pipeline
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(26 * sr) / sr
    >>> y = ((t > 7) & (t < 21.5)) * np.cos(2 * np.pi * 60.01 * t) + 0.3 * np.random.default_rng(0).standard_normal(t.size)
    >>> src, opts = ArraySource(y, sr), DenoiseOptions().validated(sr)
    >>> found, _ = pipeline._analyse(src, opts)
    >>> [(round(a / sr, 2), round((a + n) / sr, 2), f.lines.harmonics)
    ...  for a, n, f in lone_line_part(src, opts, found, pipeline._analyse)]
    [(7.01, 21.5, [1])]
    """
    lines = found.lines
    if opts.harmonics != "auto" or opts.tones or lines.fixed_freqs or len(lines.harmonics) != 1:
        return []
    k = lines.harmonics[0]
    ext = _humspans.hum_extent(source, found.f_med, k)
    if ext is None:
        return []
    ext = _humspans.cut_at_switches(source, *ext, found.f_med, [k])
    with _quiet_logs():
        f_ext, _ = analyse(_humspans.SliceSource(source, *ext),
                            replace(opts, progress=False, harmonics=[k], mains=found.det.nominal_hz))
    if f_ext.lines.harmonics != [k]:
        return []
    log.info("hum line h%d over %.1f-%.1f s only (absent before and after)", k, ext[0] / source.sr,
             (ext[0] + ext[1]) / source.sr)
    return [(ext[0], ext[1], f_ext)]


def fit_parts(source, sink, opts: DenoiseOptions, parts, tick, fit):
    """Pass 2 on each stretch of ``parts``; the input between them goes to ``sink`` as read.
    The blocks' numbers of the longest stretch are returned (the report's lines are its lines);
    ``fit`` is pipeline._fit.

    Examples
    --------
    >>> from odnn_sep.audio import pipeline
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(24 * sr) / sr
    >>> hum = ((t > 10) & (t < 16)) * (np.cos(2 * np.pi * 50.02 * t) + np.cos(2 * np.pi * 100.04 * t))
    >>> y = hum + 0.3 * np.random.default_rng(0).standard_normal(t.size)
    >>> src, opts = ArraySource(y, sr), DenoiseOptions().validated(sr)
    >>> found, _ = pipeline._analyse(src, opts)
    >>> parts = span_parts(src, opts, found, pipeline._analyse); out = []
    >>> _ = fit_parts(src, lambda piece, removed: out.append(piece - removed), opts, parts, None, pipeline._fit)
    >>> clean = np.concatenate(out)[:, 0]
    >>> clean.shape, bool(np.array_equal(clean[: 9 * sr], y[: 9 * sr])), round(float(np.std(clean[11 * sr: 15 * sr])), 2)
    ((96000,), True, 0.3)
    >>> with_spans(found, parts).hum_spans[0]["harmonics"]
    [1, 2]
    """
    pos, longest = 0, max(range(len(parts)), key=lambda i: parts[i][1])
    out = None
    for i, (a, n, f_sub) in enumerate(parts):
        _pass_through(source, sink, pos, a, tick)
        fitted = fit(_humspans.SliceSource(source, a, n), sink, opts, f_sub, tick)
        if i == longest:
            out = fitted
        pos = a + n
    _pass_through(source, sink, pos, source.frames, tick)
    return out


def _pass_through(source, sink, a: int, b: int, tick, step: int = 1 << 16):
    for s in range(a, b, step):
        piece = source.read(s, min(step, b - s))
        sink(piece, np.zeros_like(piece))
        if tick is not None:
            tick(piece.shape[0])


def with_spans(found, parts):
    """The whole input's :class:`_Found` for the report: the longest stretch's lines, track (its
    times on the input's clock) and amplitudes, with the whole input's spectrum; every stretch in
    ``hum_spans``.

    Examples
    --------
    >>> from odnn_sep.audio import pipeline
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 4000; t = np.arange(24 * sr) / sr
    >>> hum = ((t > 10) & (t < 16)) * (np.cos(2 * np.pi * 50.02 * t) + np.cos(2 * np.pi * 100.04 * t))
    >>> y = hum + 0.3 * np.random.default_rng(0).standard_normal(t.size)
    >>> src, opts = ArraySource(y, sr), DenoiseOptions().validated(sr)
    >>> found, _ = pipeline._analyse(src, opts)
    >>> w = with_spans(found, span_parts(src, opts, found, pipeline._analyse))
    >>> w.lines.harmonics, [round(w.hum_spans[0][k], 1) for k in ("start_s", "end_s")]
    ([1, 2], [10.0, 16.0])
    """
    a, _, f_sub = max(parts, key=lambda p: p[1])
    sr = f_sub.plan.sr
    det = f_sub.det
    det.candidates = found.det.candidates + det.candidates
    env = f_sub.envelope
    if env is not None:
        env = replace(env, steps_s=tuple(t + a / sr for t in env.steps_s))
    return replace(f_sub, spec_before=found.spec_before, trk=replace(f_sub.trk, t=f_sub.trk.t + a / sr), det=det,
                   envelope=env,
                   hum_spans=[{"start_s": a2 / sr, "end_s": (a2 + n2) / sr, "mains_hz": f.f_med,
                               "harmonics": list(f.lines.harmonics)} for a2, n2, f in parts])


@contextmanager
def _quiet_logs():
    """A stretch's own analysis says nothing: what it finds is logged once, by the caller."""
    audio_log = logging.getLogger("odnn_sep.audio")
    old = audio_log.level
    audio_log.setLevel(logging.ERROR)
    try:
        yield
    finally:
        audio_log.setLevel(old)
