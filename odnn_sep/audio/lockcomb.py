"""Which comb is hum: track the fundamental's phase on the candidate harmonics, keep the
harmonics that are phase-locked to it (lock.py), and track again on those alone until the set
settles; of the families that lock (50 Hz, 60 Hz, a placement by the strongest line), the one
holding the most power along its track wins, and lines that sit on a periodic host's grid of their
own (hostgrid.py) are left when most of the comb's lines do.

A family whose candidate lines are note partials (a melody repeating F4 = 349.2 Hz beside 350 Hz)
yields a "track" that no line follows for long: none of them passes the lock test, and the
family is dropped. Hum-free input then leaves with no line at all.
"""
from __future__ import annotations

import logging
import math
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.audio import chunkalias as _chunkalias
from odnn_sep.audio import combpattern as _combpattern
from odnn_sep.audio import detect as _detect
from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import hostgrid as _hostgrid
from odnn_sep.audio import lock as _lock
from odnn_sep.audio import phasejumps as _phasejumps
from odnn_sep.audio import phaseplace as _phaseplace
from odnn_sep.audio import track as _track
from odnn_sep.audio.blockplan import BlockPlan, hop_samples

log = logging.getLogger(__name__)
TRACK_HOP_S = 4.0     # blocks of the starting (coarse) track: 8 s
NUMERICAL_REL = 3e-3  # new lines weaker than this (-50 dB re the strongest locked line) are not added
SETTLE_ROUNDS = 3     # track / lock-test rounds until the set of locked lines settles
LOWEST_K = 5          # a hum comb has a locked line among harmonics 1..LOWEST_K
# Inputs shorter than this cannot tell a held note 1/duration Hz from a harmonic, and a held organ
# chord locks like hum over 1 s: there the comb needs a locked line among harmonics 1..LOWEST_K_SHORT
SHORT_INPUT_S = 2.0
LOWEST_K_SHORT = 3
WEIGHTED_HIGH = 2     # spectrum lines up to this times LOWEST_K get the weighted test too (Bonferroni)
WEIGHTED_REACH = 2    # the weighted lock test looks at harmonics up to this times the highest locked one
HIGH_REACH = 4        # a comb locked to within this many harmonics of the candidates' top is extended
MAX_SUMS_MB = 120     # chunk sums held for the comb's lines at most (an hour of 44.1 kHz mono: 43 lines)
EXTEND_BATCH = 16     # further harmonics demodulated per pass over the input
RETRY_LINE = 4.0      # least peak over its floor of a line that places the fundamental in the retry
ALIAS_MARGIN = 3.0     # a line added by a lock test stands this far above the comb's own leak there (_leak_floor)
SIDE_PROMINENCE = 20.0  # a host's sideband pair over the baseband's median (noise alone: 3-4)


@dataclass
class Comb:
    """The phase-locked comb chosen by :func:`choose`.

    Attributes
    ----------
    nominal_hz : float
        50, 60 or the requested fundamental.
    f_ref : float
        Reference fundamental of the demodulation (Hz).
    harmonics : list of int
        Locked harmonics (or the requested ones).
    psi : (J,) array or None
        The fundamental's phase (cycles, relative to ``f_ref t``) at the chunk centres.
    D : (J, C, K) complex array or None
        Chunk sums of ``harmonics``.
    weights : (C, K) array or None
        Inverse floor PSD.
    evidence : float
        Sum of ``-log10 p`` of the locked lines.
    lock : dict
        Harmonic -> ``(p, lock index, amplitude)`` of every line tested.
    jumps : list of (int, float)
        Steps of ``psi`` placed to the sample (a splice: phaseplace.to_the_sample).
    lock_w : dict
        Harmonic -> p-value of the weighted lock test, where it was run.
    host_lines : list of int
        Lines the periodic-host test dropped (``_off_host_grid``): never added back.

    Examples
    --------
    >>> c = Comb(nominal_hz=50.0, f_ref=50.0, harmonics=[], psi=None, D=None, weights=None)
    >>> c.evidence, c.lock
    (0.0, {})
    """

    nominal_hz: float
    f_ref: float
    harmonics: list[int]          # locked harmonics (or the requested ones)
    psi: np.ndarray | None        # fundamental's phase (cycles, relative to f_ref t) at chunk centres
    D: np.ndarray | None          # chunk sums of ``harmonics``
    weights: np.ndarray | None    # (C, K) inverse floor PSD
    evidence: float = 0.0         # sum of -log10 p of the locked lines
    lock: dict = field(default_factory=dict)
    jumps: list = field(default_factory=list)
    lock_w: dict = field(default_factory=dict)   # harmonic -> p of the weighted lock test, where run
    host_lines: list = field(default_factory=list)  # lines of a periodic host, dropped: not added back
    second_hum: dict | None = None  # a comb of the other mains family that locks too (_second_hum)


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


@dataclass
class _Family:
    """One family's candidate lines through the lock tests: chunk sums ``D`` (J, C, K) and floor
    weights ``W`` (C, K) of the candidate harmonics ``cand`` at ``f_ref``, the coarse track's hop,
    the Bonferroni count ``n_tests`` and, filled as lines are tested, ``info[k] = (p, lock index,
    amplitude)``."""

    D: np.ndarray
    W: np.ndarray
    cand: list
    sr: int
    N: int
    f_ref: float
    hop: int
    alpha: float
    n_tests: int
    info: dict = field(default_factory=dict)
    winfo: dict = field(default_factory=dict)    # harmonic -> p of the weighted lock test

    def cols(self, lines) -> list[int]:
        return [self.cand.index(k) for k in lines]

    def presence(self, lines, psi):
        """lock.presence of the basebands of ``lines`` tracked by ``psi`` (one line at a time)."""
        return _lock.presence((self.D[:, :, c] * _finetrack.phase_turn(psi, k)[:, None]
                               for k, c in zip(lines, self.cols(lines), strict=True)), self.sr)

    def phase(self, lines):
        """Block-track phase and its refinement (cycles at chunk centres) from harmonics ``lines``."""
        cols = self.cols(lines)
        trk = _track.track_fundamental(self.D[:, :, cols], self.f_ref, lines, self.W[:, cols],
                                       BlockPlan(sr=self.sr, n_frames=self.N, hop=self.hop))
        psi0 = _finetrack.block_track_phase(trk, _finetrack.chunk_times(self.D.shape[0], self.sr), self.f_ref,
                                            self.sr)
        # a large jump of the phase (a splice), estimated on all the lines at once, is part of
        # the starting phase of every test and fit (its harmonics' phases flip and wrap past
        # what the fine track's averaging can follow)
        psi0, cuts = _phasejumps.follow(self.D[:, :, cols], self.sr, np.asarray(lines, float), psi0,
                                        _phasejumps.window(self.sr))
        # smaller steps kept whole here, for the fit and the tests of new lines; the
        # leave-one-out lock tests keep the smooth phase they were calibrated with
        return psi0, _finetrack.refine_phase(self.D[:, :, cols], self.sr, self.f_ref, lines, self.W[:, cols], psi0,
                                             steps=True, cuts=cuts)


def settle(source, spec, det, extra, *, alpha: float, n_tests: int, test: bool = True, progress=None) -> Comb:
    """Track and lock-test the family of ``det`` (harmonics ``det.harmonics`` plus ``extra``
    candidates). ``test=False``: the harmonics were given by the caller; only track them.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input.
    spec : Spectrum
        Its spectrum.
    det : Detection
        The family (fundamental, harmonics, floors).
    extra : sequence of int
        Further candidate harmonics.
    alpha : float
        Significance level.
    n_tests : int
        Bonferroni count.
    test : bool
        Lock-test the lines.
    progress : callable, optional
        Progress callback of the demodulation.

    Returns
    -------
    Comb

    Examples
    --------
    >>> from odnn_sep.audio.detect import detect_hum, excerpt_spectrum
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=2000)
    >>> src = ArraySource(y, sr); spec = excerpt_spectrum(src, keep_segments_hz=1000)
    >>> det = detect_hum(spec, sr)
    >>> comb = settle(src, spec, det, [], alpha=1e-3, n_tests=len(det.candidates))
    >>> comb.harmonics, comb.D.shape, comb.evidence > 10
    ([1, 2, 3, 4, 5], (300, 1, 5), True)
    """
    sr, N = source.sr, source.frames
    cand = sorted(set(det.harmonics) | set(extra))
    fam = _Family(D=_track.demodulate(source, det.mains_hz, cand, progress=progress),
                  W=_weights(spec, det.mains_hz, cand, det.floors), cand=cand, sr=sr, N=N, f_ref=det.mains_hz,
                  hop=hop_samples(2 * TRACK_HOP_S, sr), alpha=alpha, n_tests=n_tests)
    seen = list(det.harmonics) if det.harmonics else list(cand)
    ks = list(seen)
    # the spectrum's lines first: track on them, keep those locked, until the set settles
    psi0, psi = fam.phase(ks)
    for _ in range(SETTLE_ROUNDS if test else 0):
        keep = _locked_leave_one_out(fam, ks, psi0)
        if keep == ks or not keep:
            ks = keep
            break
        ks = keep
        psi0, psi = fam.phase(ks)
    if test and ks:
        ks, psi0, psi = _readmit(fam, seen, ks, psi0, psi)
    if test and ks:
        ks = sorted(ks + _new_lines(fam, seen, ks, psi))
        ks = sorted(ks + _intermittent_lines(fam, ks, psi))
        _weighted_rest(fam, ks, psi)
    host: list[int] = []
    if test and ks:
        kept = _off_host_grid(spec, fam.f_ref, ks, psi, sr)
        host = [k for k in ks if k not in kept]
        if host and kept:
            kept = _off_fine_grid(fam, kept, psi)
            host = [k for k in ks if k not in kept]
        ks = kept
    lowest = LOWEST_K if N >= SHORT_INPUT_S * sr else LOWEST_K_SHORT
    if test and ks and min(ks) > lowest:
        # mains hum lives at the fundamental and the first harmonics (a weak fundamental is
        # normal, a comb with nothing locked below the 6th harmonic is not): locked lines only
        # high up are partials of held notes that happen to keep their phase
        log.info("lines %s locked but none of harmonics 1-%d: not taken for hum", ks, lowest)
        ks = []
    cols = fam.cols(ks)
    info = fam.info
    ev = float(sum(-np.log10(max(info[k][0], 1e-300)) for k in ks)) if test else 0.0
    D = fam.D[:, :, cols] if ks else None
    jumps = []
    if ks:
        psi, jumps = _phaseplace.to_the_sample(source, D, psi, ks, fam.f_ref)
    return Comb(nominal_hz=det.nominal_hz, f_ref=fam.f_ref, harmonics=ks, psi=psi if ks else None,
                D=D, weights=fam.W[:, cols] if ks else None, evidence=ev, lock=info, jumps=jumps,
                lock_w=fam.winfo, host_lines=host)


def choose(source, spec, det, *, mains, harmonics, alpha: float, max_hz, tones, progress=None) -> Comb | None:
    """The locked comb that holds the most power along its track among the detected family, the
    other nominal family and the placements by a strongest line (:func:`coherent_power`); None
    when no line is locked. Options as in :func:`~odnn_sep.audio.denoise`
    (validated); keyword-only, which is why there are nine (why long).

    Parameters
    ----------
    source : ArraySource or FileSource
        The input.
    spec : Spectrum
        Its spectrum.
    det : Detection
        What the spectrum showed.
    mains, harmonics, alpha, max_hz, tones
        As in :func:`~odnn_sep.audio.denoise` (validated).
    progress : callable, optional
        Progress callback.

    Returns
    -------
    Comb or None

    Examples
    --------
    >>> from odnn_sep.audio.detect import detect_hum, excerpt_spectrum
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=2000)
    >>> src = ArraySource(y, sr); spec = excerpt_spectrum(src, keep_segments_hz=1000)
    >>> comb = choose(src, spec, detect_hum(spec, sr), mains="auto", harmonics="auto", alpha=1e-3,
    ...               max_hz=None, tones=[])
    >>> comb.nominal_hz, comb.harmonics, round(comb.f_ref, 1)
    (50.0, [1, 2, 3, 4, 5], 50.0)
    """
    test = harmonics == "auto"
    n_first = max(1, sum(1 for c in det.candidates if c["harmonic"] is not None))
    fams = []
    if det.harmonics:
        # every harmonic in range is tested for lock, not only those the spectrum showed: weak
        # harmonics of a hum (the even ones of odd-dominant hum, the 11th under music) are
        # clear on the tracked baseband
        extra = [k for k in _detect.candidate_harmonics(det.mains_hz, source.sr, "auto", max_hz)
                 if k not in det.harmonics] if test else []
        fams.append(settle(source, spec, det, extra, alpha=alpha, n_tests=n_first + len(extra), test=test,
                           progress=progress))
    if test and mains == "auto":
        for nom in (50.0, 60.0):
            if nom == det.nominal_hz:
                continue
            other = [c["harmonic"] for c in det.candidates if c["family_hz"] == nom and c["significant"]]
            # a line both families share (300 Hz is 5 x 60 and 6 x 50) is evidence for neither:
            # a family whose lines are all shared with the detected one is not demodulated
            shared = [k for k in other if det.harmonics and min(
                abs(k * nom - j * det.mains_hz) for j in det.harmonics) <= _detect.band_halfwidth(spec, k)]
            if len(shared) == len(other):
                continue
            d2 = _detect.detect_hum(spec, source.sr, mains=nom, harmonics="auto", tones=tones, alpha=alpha,
                                    max_hz=max_hz)
            d2.harmonics = sorted(set(d2.harmonics) | set(other))
            extra = [k for k in _detect.candidate_harmonics(d2.mains_hz, source.sr, "auto", max_hz)
                     if k not in d2.harmonics]
            fams.append(settle(source, spec, d2, extra, alpha=alpha, n_tests=n_first + len(extra), test=True))
    if test:
        fams += _strongest_line_families(source, spec, fams, tones=tones, alpha=alpha, max_hz=max_hz,
                                         n_first=n_first)
    fams = [f for f in fams if f.harmonics]
    if not fams and test and det.harmonics:
        retry = _low_harmonics_retry(source, spec, det, alpha=alpha, max_hz=max_hz, n_first=n_first)
        fams = [retry] if retry is not None else []
    if not fams and test and source.channels > 1:
        one = _one_channel_retry(source, spec, mains=mains, alpha=alpha, max_hz=max_hz, tones=tones)
        fams = [one] if one is not None else []
    if not fams:
        return None
    # of the combs that passed the lock tests, the one that holds the most power along its track:
    # hum is the strongest steady periodic thing in a recording, and the lines of a steady beat or
    # a regular vibrato that happen to lock on another grid are weak (a p-value counts how sure a
    # line is, not how much of the input it holds: seven weak lines of a drum loop on the 60 Hz
    # grid outvoted a 50 Hz hum louder than the music)
    best = max(fams, key=coherent_power)
    best.second_hum = _second_hum(fams, best, spec)
    if test:
        _extend_high(source, spec, best, alpha=alpha, max_hz=max_hz, n_first=n_first)
        _add_pattern_lines(source, spec, best, alpha=alpha)
        _keep_columns(best, _off_host_grid(spec, best.f_ref, best.harmonics, best.psi, source.sr,
                                           known=best.host_lines))
        _keep_columns(best, _off_pattern_host_lines(best, source.sr))
        if not best.harmonics:
            return None
    log.info("phase-locked comb: %.4f Hz, harmonics %s (evidence %s)", best.f_ref, best.harmonics,
             [round(f.evidence, 1) for f in fams])
    return best


def _off_host_grid(spec, f_ref: float, ks, psi, sr: int, known=()) -> list[int]:
    """``ks`` without the lines of a periodic host (``hostgrid.grid_lines``) when they are at least
    half of them, with a log line; ``psi`` the tracked phase (cycles at the chunk centres), whose
    range of frequencies widens each line's own band. ``known``: lines this test dropped before
    (the comb's first lines); they count among the host's, so lines added to the comb later
    (above the 40th harmonic, the second family of tests) cannot outvote them."""
    grid = _hostgrid.grid_lines(spec, f_ref, ks, spread_hz=_spread_hz(psi, sr))
    if 2 * (len(grid) + len(known)) < len(ks) + len(known):
        # a few lines of a hum comb inside a loop's field look like the loop's (a weak fundamental
        # of a second-dominant hum among a drum loop's lines): the comb is the loop's only when
        # most of its lines are
        return list(ks)
    if grid:
        log.info("lines %s have lines of their own kind at equal distances on both sides (a drum loop or a "
                 "sequenced pattern placed to the sample): not taken for hum", grid)
    return [k for k in ks if k not in grid]


def _off_fine_grid(fam, ks, psi) -> list[int]:
    """``ks`` without the lines whose tracked baseband holds a host's finer grid
    (``hostgrid.baseband_sidebands``), for a comb whose other lines the spectrum's test already gave
    to a periodic host: the pattern's lines that the spectrum could not resolve from their
    neighbours (a period of 4 s: lines every 0.25 Hz) would otherwise stay and be removed as hum."""
    nd = fam.D.shape[0] // _finetrack.DECIM
    if nd < 16:
        return list(ks)
    cols = fam.cols(ks)
    v = _finetrack.decimated_baseband(fam.D[:, :, cols], psi, np.asarray(ks, float), np.ones(len(ks), bool), nd)
    fs_d = _finetrack.decimated_rate(fam.sr)
    side = _hostgrid.baseband_sidebands(v.sum(axis=1), fs_d)
    fine = [k for k, r in zip(ks, side, strict=True) if r >= _hostgrid.BASEBAND_SIDE]
    if fine:
        log.info("lines %s hold a finer grid of the same host in their baseband (sidebands at least %g of "
                 "the line): not taken for hum", fine, _hostgrid.BASEBAND_SIDE)
    return [k for k in ks if k not in fine]


def _off_pattern_host_lines(comb: Comb, sr: int) -> list[int]:
    """The comb's harmonics without each line that both breaks the pattern of all the others
    (``combpattern.pattern``: an even line in a comb whose other lines, four or more, are odd) and
    holds a periodic host's neighbouring lines as sidebands of its tracked baseband
    (``hostgrid.baseband_sidebands``). A loop placed to the sample has a line at every multiple of
    50 Hz: under a rectifier's odd comb its loud 100 Hz line locked as harmonic 2 and was removed,
    the largest error left on that input (-24 dB re the hum). Either sign alone decides nothing (a
    real hum has weak even harmonics too, and a weak hum line among a loop's lines shows sidebands),
    and a line that breaks the pattern is a weak part of the hum when it is one."""
    ks = list(comb.harmonics)
    if len(ks) <= _combpattern.PATTERN_MIN or comb.D is None or comb.psi is None:
        return ks
    odd_one = []
    for k in ks:
        pat = _combpattern.pattern([j for j in ks if j != k])
        if pat is not None and pat[0] > 1 and k % pat[0] != pat[1]:
            odd_one.append(k)
    nd = comb.D.shape[0] // _finetrack.DECIM
    if len(odd_one) != 1 or nd < 16:
        return ks
    k = odd_one[0]
    i = ks.index(k)
    v = _finetrack.decimated_baseband(comb.D[:, :, i: i + 1], comb.psi, np.asarray([k], float), np.ones(1, bool), nd)
    fs_d = _finetrack.decimated_rate(sr)
    side = float(_hostgrid.baseband_sidebands(v.sum(axis=1), fs_d)[0])
    # a weak hum line's baseband is mostly the content's noise, whose strongest pair of bins can
    # reach the line's own power: the pair must be lines (a hum h2 under pink noise: 0.53 of the
    # line but 3.7 times the baseband's median; the loop's 100 Hz line: 16 and 17000 times)
    if side < _hostgrid.BASEBAND_SIDE or _hostgrid.sideband_prominence(v.sum(axis=1), fs_d)[0] < SIDE_PROMINENCE:
        return ks
    log.info("line %d breaks the comb's pattern and holds a periodic host's neighbouring lines as sidebands "
             "(%.2f of the line): not taken for hum", k, side)
    return [j for j in ks if j != k]


def _spread_hz(psi, sr: int) -> float:
    """Range (Hz) of the fundamental given by ``psi`` over 4 s steps (1st to 99th percentile; the
    steps are long so that the track's noise does not widen it).

    Examples
    --------
    >>> sr = 8000; J = 2000                              # 20 s of 10 ms chunks
    >>> t = (np.arange(J) + 0.5) * 80 / sr
    >>> round(_spread_hz(0.5 * 0.02 * t ** 2, sr), 2)     # a ramp of 20 mHz/s
    0.31
    """
    if psi is None:
        return 0.0
    m = max(1, int(round(4 * sr / _track.chunk_length(sr))))    # chunks in 4 s
    if len(psi) <= m:
        return 0.0
    f = (psi[m:] - psi[:-m]) * sr / (m * _track.chunk_length(sr))
    lo, hi = np.percentile(f, [1, 99])
    return float(hi - lo)


def _keep_columns(comb: Comb, ks) -> None:
    """Keep only harmonics ``ks`` of ``comb`` (its chunk sums and weights with them)."""
    if list(ks) == list(comb.harmonics):
        return
    cols = [comb.harmonics.index(k) for k in ks]
    comb.D = comb.D[:, :, cols] if cols else None
    comb.weights = comb.weights[:, cols] if cols else None
    comb.harmonics = list(ks)


SECOND_HUM_LINES = 3   # lines of the other family's comb, none shared with the hum removed, that tell a second hum


def _second_hum(fams, best: Comb, spec) -> dict | None:
    """The strongest comb of the other mains family among the locked ``fams`` when it holds
    :data:`SECOND_HUM_LINES` or more lines that no line of ``best`` shares (300 Hz is 5 x 60 and
    6 x 50), not all multiples of one number: a second hum (50 and 60 Hz sources in one take), which one run does not remove
    (``denoise`` names it in a warning with the run that removes it).

    Examples
    --------
    >>> from odnn_sep.audio.detect import Spectrum
    >>> spec = Spectrum(np.arange(4000) * 0.25, np.ones((4000, 1)), 4, 10.0)
    >>> hum50 = Comb(50.0, 49.99, [1, 2, 3, 4, 5, 6], None, None, None, lock={k: (1e-9, 0.9, 9.0) for k in range(1, 7)})
    >>> hum60 = Comb(60.0, 60.01, [1, 2, 5, 7], None, None, None, lock={k: (1e-9, 0.9, 3.0) for k in (1, 2, 5, 7)})
    >>> _second_hum([hum50, hum60], hum50, spec)
    {'nominal_hz': 60.0, 'fundamental_hz': 60.01, 'harmonics': [1, 2, 7], 'power_db': -11.3}
    >>> hum60.harmonics = [1, 5]                      # one line of its own
    >>> _second_hum([hum50, hum60], hum50, spec) is None
    True
    >>> hum60.harmonics, hum60.lock = [10, 15, 20], {k: (1e-9, 0.9, 3.0) for k in (10, 15, 20)}
    >>> _second_hum([hum50, hum60], hum50, spec) is None  # the partials of a 300 Hz note
    True
    """
    found = None
    for fam in fams:
        if fam.nominal_hz == best.nominal_hz or not fam.harmonics:
            continue
        own = [k for k in fam.harmonics if min(abs(k * fam.f_ref - j * best.f_ref) for j in best.harmonics)
               > _detect.band_halfwidth(spec, k)]
        # lines that are all multiples of one number (10, 15, 20, ... of 59.94 Hz) are the partials
        # of a note at that multiple (299.7 Hz), not a hum of this family
        if len(own) < SECOND_HUM_LINES or math.gcd(*own) > 1:
            continue
        if found is None or coherent_power(fam) > found[1]:
            found = (fam, coherent_power(fam), own)
    if found is None:
        return None
    fam, power, own = found
    ratio = max(power / max(coherent_power(best), 1e-300), 1e-30)
    return {"nominal_hz": float(fam.nominal_hz), "fundamental_hz": float(fam.f_ref), "harmonics": own,
            "power_db": round(float(10 * np.log10(ratio)), 1)}


def coherent_power(comb: Comb) -> float:
    """Power of the comb's locked lines along its track (squared modulus of each line's mean
    tracked baseband, chunk-sum units, summed): what removing the comb takes out.

    Examples
    --------
    >>> c = Comb(nominal_hz=50.0, f_ref=50.0, harmonics=[1, 3], psi=None, D=None, weights=None,
    ...          lock={1: (1e-9, 0.9, 2.0), 2: (0.5, 0.1, 0.1), 3: (1e-6, 0.8, 1.0)})
    >>> coherent_power(c)
    5.0
    """
    return float(sum(comb.lock[k][2] ** 2 for k in comb.harmonics if k in comb.lock))


def _strongest_line_families(source, spec, fams, *, tones, alpha: float, max_hz, n_first: int) -> list[Comb]:
    """The families placed by their strongest line where that disagrees with the vote of every
    harmonic (``detect.refine_fundamental``). The vote's log scale lets many weak lines outvote a
    few strong ones: the sidebands of a regular vibrato or the lines of a drum loop, which fall on
    a grid of their own, placed a 60 Hz hum with a loud third harmonic at 60.5 Hz. Each such
    placement is settled as a family of its own, and the locked power decides (:func:`choose`)."""
    out = []
    for fam in list(fams):
        ks = _detect.candidate_harmonics(fam.nominal_hz, source.sr, "auto", max_hz)
        f_line = _detect.strongest_line_fundamental(spec, fam.nominal_hz, ks)
        # placements closer than the drift the detection allows for (or half a bin) are the same
        # family; a detection band is wider than that and would hide a 0.5 Hz disagreement
        if f_line is None or abs(f_line - fam.f_ref) <= max(_detect.DRIFT_TOL_HZ, 0.5 * spec.df):
            continue
        d3 = _detect.detect_hum(spec, source.sr, mains=fam.nominal_hz, harmonics="auto", tones=tones, alpha=alpha,
                                max_hz=max_hz, f0=f_line)
        if not d3.harmonics:
            continue
        extra = [k for k in _detect.candidate_harmonics(f_line, source.sr, "auto", max_hz) if k not in d3.harmonics]
        log.info("strongest line places the %g Hz family at %.4f Hz (vote: %.4f Hz): tested too",
                 fam.nominal_hz, f_line, fam.f_ref)
        out.append(settle(source, spec, d3, extra, alpha=alpha, n_tests=n_first + len(extra), test=True))
    return out


def _extend_high(source, spec, comb: Comb, *, alpha: float, max_hz, n_first: int) -> None:
    """Harmonics above the candidates (``detect.MAX_HARMONICS``) for a comb locked to near
    their top, in place: a phase-cut dimmer's or a rectifier's current keeps strong harmonics
    far up (1/k), and stopping at the 40th leaves about -20 dB of its hum. Each further range
    (up to twice the last) is demodulated and every line in it lock-tested against the settled
    phase, as the harmonics the spectrum missed (Bonferroni over every harmonic tested, -50 dB
    of the strongest locked line); it goes on while the comb keeps reaching the top, below
    Nyquist, with at most ``MAX_SUMS_MB`` of chunk sums held for the comb (the range is read
    ``EXTEND_BATCH`` lines at a time and only the locked lines' sums are kept)."""
    sr = source.sr
    ks = list(comb.harmonics)
    top = _detect.MAX_HARMONICS
    J, C = comb.D.shape[:2]
    while ks and max(ks) > top - HIGH_REACH:
        room = _sums_room(J, C) - len(ks)
        new_top = min(2 * top, top + max(room, 0))
        cand = [k for k in _detect.candidate_harmonics(comb.f_ref, sr, new_top, max_hz) if k > top]
        if not cand:
            break
        strongest = max(comb.lock[k][2] for k in ks if k in comb.lock)
        leak = _leak_floor(comb.lock, ks, comb.psi, comb.f_ref, sr)
        new, cols = [], []
        # a few lines per pass over the input, keeping only the locked ones' chunk sums: the
        # range's sums at once, beside the comb's, would double what is held
        for i in range(0, len(cand), EXTEND_BATCH):
            batch = cand[i: i + EXTEND_BATCH]
            D = _track.demodulate(source, comb.f_ref, batch)
            _, info = _lock.locked(D, sr, batch, comb.psi, alpha=alpha)
            comb.lock.update(info)
            ok = [k for k in batch if info[k][0] * (n_first + new_top) < alpha and info[k][2] > NUMERICAL_REL * strongest
                  and info[k][2] > leak(k)]
            new += ok
            # the weighted test's p-value of the others, for the second family (combpattern.py)
            others = [k for k in batch if k not in ok]
            w_inf = _lock.weighted_locked(D[:, :, [batch.index(k) for k in others]], sr, others, comb.psi)
            comb.lock_w.update({k: v[0] for k, v in w_inf.items()})
            cols += [D[:, :, batch.index(k)].copy() for k in ok]     # (a view would keep all of D)
            del D
        top = new_top
        if not new:
            break
        comb.D = np.concatenate([comb.D, np.stack(cols, axis=2)], axis=2)
        del cols
        comb.weights = np.concatenate([comb.weights, _weights(spec, comb.f_ref, new, {})], axis=1)
        comb.evidence += float(sum(-np.log10(max(comb.lock[k][0], 1e-300)) for k in new))
        ks += new
        log.info("harmonics %d-%d locked above the first %d: %s", min(new), max(new), _detect.MAX_HARMONICS, new)
    comb.harmonics = ks


def _sums_room(J: int, C: int) -> int:
    """Lines whose chunk sums (``J`` chunks, ``C`` channels, complex64) fit in ``MAX_SUMS_MB``."""
    return int(MAX_SUMS_MB * 2 ** 20 // (J * C * 8))


def _add_pattern_lines(source, spec, comb: Comb, *, alpha: float) -> None:
    """The comb's unlocked lines in its own pattern that pass the second family's test
    (combpattern.py), added in place: demodulated once more, in harmonic order."""
    new = _combpattern.pattern_lines(comb.harmonics, comb.lock, comb.lock_w, alpha=alpha, floor_rel=NUMERICAL_REL)
    # the lines the periodic-host test took out stay out: locked as they are, they are the host's
    new = [k for k in new if k not in comb.host_lines]
    leak = _leak_floor(comb.lock, comb.harmonics, comb.psi, comb.f_ref, source.sr)
    new = [k for k in new if comb.lock[k][2] > leak(k)]
    J, C, K = comb.D.shape
    # the strongest first, within the chunk sums' bound of the whole comb (_extend_high's)
    new = sorted(sorted(new, key=lambda k: -comb.lock[k][2])[: max(_sums_room(J, C) - K, 0)])
    if not new:
        return
    ks = sorted(list(comb.harmonics) + new)
    D_new = _track.demodulate(source, comb.f_ref, new)
    D = np.empty((J, C, len(ks)), comb.D.dtype)       # filled column by column: one copy of the sums
    for i, k in enumerate(ks):
        D[:, :, i] = D_new[:, :, new.index(k)] if k in new else comb.D[:, :, comb.harmonics.index(k)]
    src = list(comb.harmonics) + new                    # the weights' columns, in this order
    W = np.concatenate([comb.weights, _weights(spec, comb.f_ref, new, {})], axis=1)
    comb.weights = W[:, [src.index(k) for k in ks]]
    comb.D, comb.harmonics = D, ks
    log.info("lines %s of the comb's pattern locked in the second family of tests", new)


def _low_harmonics_retry(source, spec, det, *, alpha: float, max_hz, n_first: int) -> Comb | None:
    """The detected family once more, from its fundamental refined on harmonics 1-``LOWEST_K``
    alone, when nothing locked at the first try; None when nothing locks then either.

    The spectrum's fundamental is refined with every harmonic voting; strong note partials high up
    (E5 = 659.3 Hz is 11 x 59.93 Hz) can then pull it off the hum by a few hundredths of a hertz,
    most of all when the hum's own lines are split by a jump of its phase (a splice), and the track
    started there locks nothing. Mains hum lives at the first harmonics, so they alone place the
    fundamental here; the lock tests are the same, so a comb of partials fails them as before."""
    import copy

    low = [k for k in det.harmonics if k <= LOWEST_K]
    if not low:
        return None
    tried = [(det.mains_hz, tuple(det.harmonics))]
    # the strongest low line: where the others the spectrum took for harmonics are the bumps of its
    # shape (an EEG's slope and filter dips), each is tested against a track made of the others
    # (settle's leave-one-out) and a clear 50 Hz line fails against a track of noise
    levels = {c["harmonic"]: c["pooled_db"] for c in det.candidates
              if c["family_hz"] == det.nominal_hz and c["harmonic"] in low and np.isfinite(c["pooled_db"])}
    strong = [max(levels, key=levels.get)] if len(levels) > 1 else []
    f_line = _detect.strongest_line_fundamental(spec, det.nominal_hz, low, min_ratio=RETRY_LINE)
    # the low harmonics' vote, then the strongest low line's own peak (the vote of a harmonic
    # without a line follows the spectrum's shape: detect.strongest_line_fundamental), each with
    # the low lines together and with the strongest alone
    for how, f0 in (("harmonics 1-%d" % LOWEST_K, _detect.refine_fundamental(spec, det.nominal_hz, low)),
                    ("the strongest of harmonics 1-%d" % LOWEST_K, f_line)):
        for ks in (low, strong):
            # a retry within a tenth of a bin of one already tried would lock (or not) the same
            if f0 is None or not ks or any(abs(f0 - f) < 0.1 * spec.df and tuple(ks) == h for f, h in tried):
                continue
            tried.append((f0, tuple(ks)))
            d2 = copy.copy(det)
            d2.mains_hz, d2.harmonics = f0, list(ks)
            extra = [k for k in _detect.candidate_harmonics(f0, source.sr, "auto", max_hz) if k not in ks]
            comb = settle(source, spec, d2, extra, alpha=alpha, n_tests=n_first + len(extra), test=True)
            if comb.harmonics:
                log.info("locked only with the fundamental placed by %s: %.4f Hz (the spectrum said %.4f; "
                         "tracked on harmonics %s)", how, f0, det.mains_hz, list(ks))
                return comb
    return None


def _one_channel_retry(source, spec, *, mains, alpha: float, max_hz, tones) -> Comb | None:
    """A comb found on one channel alone, tracked on all of them; None when no channel has one.

    The tests pool the channels: hum on one channel of a stereo file has its level halved and the
    other channel's noise added to its track, and a line the channel alone shows clearly (a 50 Hz
    line 0.003 under 0.05 of noise, p = 1e-7 by itself) fails. Each channel is tested on its own
    at ``alpha`` over the channel count (Bonferroni), by the same detection and lock tests; the
    first whose comb locks gives the fundamental, harmonics and phase track, and every channel is
    fitted along that track (the fit's amplitudes are per channel: where a channel has no hum they
    come out near zero)."""
    import copy

    from odnn_sep.audio.channel_view import ChannelView

    C = source.channels
    a = alpha / C
    for c in range(C):
        spec_c = copy.copy(spec)
        spec_c.psd = spec.psd[:, [c]]
        spec_c.segments = None if spec.segments is None else spec.segments[:, [c]]
        spec_c.__dict__.pop("numerical_floor", None)
        det_c = _detect.detect_hum(spec_c, source.sr, mains=mains, harmonics="auto", tones=tones, alpha=a,
                                   max_hz=max_hz)
        if not det_c.harmonics:
            continue
        view = ChannelView(source, c)
        try:
            comb = choose(view, spec_c, det_c, mains=mains, harmonics="auto", alpha=a, max_hz=max_hz, tones=tones)
        finally:
            view.close()
        if comb is None:
            continue
        # the channel's phase track (the others' noise would only blur it); every channel's sums
        ks = list(comb.harmonics)
        out = Comb(nominal_hz=comb.nominal_hz, f_ref=comb.f_ref, harmonics=ks, psi=comb.psi,
                   D=_track.demodulate(source, comb.f_ref, ks), weights=_weights(spec, comb.f_ref, ks, {}),
                   evidence=comb.evidence, lock=comb.lock, jumps=comb.jumps, lock_w=comb.lock_w,
                   host_lines=comb.host_lines)
        log.info("phase-locked comb on channel %d alone: %.4f Hz, harmonics %s (the channels pooled showed "
                 "none)", c, comb.f_ref, comb.harmonics)
        return out
    return None


def _locked_leave_one_out(fam: _Family, ks, psi0) -> list[int]:
    """The lines of ``ks`` that are phase-locked to a track made without them (leave one out): a
    phase that follows one line is trivially locked to it, a note partial included. A lone line
    is tested against the block track (8 s blocks cannot follow a note's phase from one onset to
    the next). Fills ``fam.info[k] = (p, lock index, amplitude)``."""
    cols = fam.cols(ks)
    keep = []
    for i, k in enumerate(ks):
        if len(ks) > 1:
            rest = [cols[j] for j in range(len(ks)) if j != i]
            psi_k = _finetrack.refine_phase(fam.D[:, :, rest], fam.sr, fam.f_ref,
                                            [ks[j] for j in range(len(ks)) if j != i], fam.W[:, rest], psi0)
        else:
            psi_k = psi0
        kk, inf_k = _lock.locked(fam.D[:, :, [cols[i]]], fam.sr, [k], psi_k, alpha=fam.alpha)
        fam.info[k] = inf_k[k]
        if not kk and len(ks) > 1 and k <= WEIGHTED_HIGH * LOWEST_K:
            # under bursty content (ECG beats, speech, notes) the weighted test sees what the
            # equal-weight one cannot (lock.weighted_lock_p_values); against a track made without
            # the line, as above. At its own level where hum lives for sure (harmonics 1-LOWEST_K),
            # Bonferroni-corrected up to WEIGHTED_HIGH x LOWEST_K (a weak harmonic under a loud note
            # partial 0.8 Hz away, read in the rests); higher up, lines the spectrum took for
            # harmonics are mostly note partials, and some of them pass it
            p_w = _lock.weighted_locked(fam.D[:, :, [cols[i]]], fam.sr, [k], psi_k)[k][0]
            kk = [k] if p_w * (1 if k <= LOWEST_K else fam.n_tests) < fam.alpha else []
        if not kk and len(ks) > 1 and k <= LOWEST_K:
            kk = _locked_where_on(fam, ks, i, psi_k)
        if kk:
            keep.append(k)
    return keep


def _locked_where_on(fam: _Family, ks, i: int, psi_k) -> list[int]:
    """``[ks[i]]`` when it is locked to ``psi_k`` where the other lines of ``ks`` show the hum on,
    else ``[]``: a hum on for half the input has a mean half its level over all the segments and
    a scatter as large, and both tests above fail it (12 s of strong 50 + 100 Hz hum switched on
    at 6 s was left in whole). The presence comes from the other lines only (lock.presence), never
    from the tested one, so its test stays calibrated; None for a hum that stays, and then
    nothing is tested again. Harmonics 1-``LOWEST_K`` only, at their own level, as the weighted
    test."""
    k = ks[i]
    others = [j for j in range(len(ks)) if j != i]
    g = fam.presence([ks[j] for j in others], psi_k)
    if g is None:
        return []
    p_g = _lock.weighted_locked(fam.D[:, :, fam.cols([k])], fam.sr, [k], psi_k, presence=g)[k][0]
    return [k] if p_g < fam.alpha else []


def _new_lines(fam: _Family, seen, ks, psi) -> list[int]:
    """Harmonics the spectrum did not show, tested once against the settled track (they never
    steer it). Each must be phase-locked (a steady non-zero mean on the tracked baseband, which is
    itself a significance test; Bonferroni-corrected over every line tested) and reach -50 dB of
    the strongest locked line: below that, the sharp onsets of a host with no noise floor
    (broadband, so in phase across harmonics, and followed a little by the track) read as weak
    locked lines, and removing such lines would gain nothing (40 of them sum to -34 dB). A further
    line test on the tracked baseband's spectrum is not asked for: it missed weak harmonics whose
    lock was clear (-27 dB under the fundamental), and those are what limits the gain."""
    others = [k for k in fam.cand if k not in seen]
    if not others:
        return []
    info, sr = fam.info, fam.sr
    # one line at a time through a view of its column (the test treats the columns one by one):
    # a copy of all the others' chunk sums at once was the run's largest array (100 MB per hour)
    for k, col in zip(others, fam.cols(others), strict=True):
        info.update(_lock.locked(fam.D[:, :, col: col + 1], sr, [k], psi, alpha=fam.alpha)[1])
    top_amp = max(info[k][2] for k in ks)
    leak = _leak_floor(info, ks, psi, fam.f_ref, sr)
    out = [int(k) for k in others if info[k][0] * fam.n_tests < fam.alpha and info[k][2] > NUMERICAL_REL * top_amp
           and info[k][2] > leak(k)]
    # the rest up to twice the locked comb's reach once more, every moment weighted by the content
    # near the line (lock.py): a weak harmonic under speech or notes shows in their pauses (same
    # Bonferroni count, -50 dB of the strongest locked line by the same weighted mean)
    rest = [k for k in others if k not in out and k <= WEIGHTED_REACH * max(ks)]
    return sorted(out + _weighted_pass(fam, ks, rest, psi))


def _weighted_pass(fam: _Family, ks, rest, psi, presence=None) -> list[int]:
    """The lines of ``rest`` that pass the weighted lock test (lock.weighted_locked, with the
    ``presence`` factor where given) against ``psi``: Bonferroni over ``fam.n_tests`` and at least
    -50 dB of the strongest locked line of ``ks`` by the same weighted mean."""
    if not rest:
        return []
    w_inf = _weighted_info(fam, rest, psi, presence)
    if presence is None:
        fam.winfo.update({k: v[0] for k, v in w_inf.items()})
    top = max(ks, key=lambda k: fam.info.get(k, (1.0, 0.0, 0.0))[2])
    top_w = _weighted_info(fam, [top], psi, presence)[top][1]
    # the leak in the weighted mean's units: scaled by the strongest line's two amplitudes
    leak = _leak_floor(fam.info, ks, psi, fam.f_ref, fam.sr)
    scale = top_w / max(fam.info[top][2], 1e-300) if top in fam.info else 0.0
    return [int(k) for k in rest if w_inf[k][0] * fam.n_tests < fam.alpha and w_inf[k][1] > NUMERICAL_REL * top_w
            and w_inf[k][1] > scale * leak(k)]


def _weighted_rest(fam: _Family, ks, psi) -> None:
    """The weighted lock test's p-value (in ``fam.winfo``) for the unlocked candidates of the
    comb's pattern up to ``combpattern.REACH`` times its reach that have none yet (spectrum lines
    dropped by the leave-one-out rounds): the second family of tests (combpattern.py) reads
    them. Nothing is decided here."""
    rest = [k for k in _combpattern.candidates(ks, fam.cand) if k not in fam.winfo]
    fam.winfo.update({k: v[0] for k, v in _weighted_info(fam, rest, psi).items()})


def _weighted_info(fam: _Family, lines, psi, presence=None) -> dict:
    """lock.weighted_locked's ``(p, amplitude)`` of each of ``lines`` (candidates of ``fam``)
    against ``psi``, one line at a time through a view of its column (as _new_lines' plain
    test: a copy of all their chunk sums at once would be the analysis's largest array)."""
    out = {}
    for k, col in zip(lines, fam.cols(lines), strict=True):
        out.update(_lock.weighted_locked(fam.D[:, :, col: col + 1], fam.sr, [k], psi, presence=presence))
    return out


def _leak_floor(lock: dict, ks, psi, f_ref: float, sr: int):
    """``k -> ALIAS_MARGIN`` times the standing leak of the lines ``ks`` (amplitudes ``lock[j][2]``)
    at harmonic ``k`` of chunk sums at ``f_ref`` tracked by ``psi`` (chunkalias.py): a line added by
    a lock test must stand above it. Zero where the reference is the track's mean fundamental."""
    f_mean = _chunkalias.mean_fundamental(psi, f_ref, sr)
    amps = {j: lock[j][2] for j in ks if j in lock}
    seconds = len(psi) * _track.chunk_length(sr) / sr
    return lambda k: ALIAS_MARGIN * _chunkalias.alias_amplitude(k, amps, f_ref, f_mean, sr, seconds)


def _intermittent_lines(fam: _Family, ks, psi) -> list[int]:
    """Lines of a hum that is switched on and off, tested where it is on. Where the locked lines
    show the hum off for a good part of the input (lock.presence), every harmonic not locked up
    to twice the comb's reach is tested once more by the weighted test with the off seconds left
    out: a weak harmonic on for half the input has half its power spread over all the units of
    the other tests, and under speech it failed them. The presence comes from the locked lines
    only, never from the tested one, so the test stays calibrated (same Bonferroni count, -50 dB
    of the strongest locked line); a steady hum is not tested again."""
    g = fam.presence(ks, psi)
    if g is None:
        return []
    rest = [k for k in fam.cand if k not in ks and k <= WEIGHTED_REACH * max(ks)]
    out = _weighted_pass(fam, ks, rest, psi, presence=g)
    if out:
        log.info("hum on for %.0f%% of the input: lines %s locked where it is on", 100 * g.mean(), out)
    return out


def _readmit(fam: _Family, seen, ks, psi0, psi):
    """Spectrum lines dropped in an early round, tested again against the settled track (made
    without them, so this is still a leave-one-out test). An early track can be steered by note
    partials the spectrum took for harmonics (a fast ramp smears the true lines, so more partials
    pass for them); a strong fundamental tested against it fails, and once dropped it would never
    come back. Lines that pass are added and the track is made again with them."""
    dropped = [k for k in seen if k not in ks]
    if not dropped:
        return ks, psi0, psi
    back, inf_d = _lock.locked(fam.D[:, :, fam.cols(dropped)], fam.sr, dropped, psi, alpha=fam.alpha)
    if not back:
        return ks, psi0, psi
    fam.info.update({k: inf_d[k] for k in back})
    log.info("lines %s locked to the settled track: taken back", back)
    ks = sorted(ks + back)
    psi0, psi = fam.phase(ks)
    return ks, psi0, psi
