"""Further hum combs near the main one: the same grid seen through a second sample clock, or a
second device. Found on a fine spectrum with the tracked comb's lines masked out, refined on the
demodulated signal, then removed as fixed-frequency lines (pooled across blocks where steady).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.audio import detect as _detect
from odnn_sep.audio import track as _track

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class CombSearch:
    """Settings of :func:`detect_extra_combs` (see there).

    Attributes
    ----------
    min_sep_hz : float
        Harmonics closer than this to a line already removed are left to that line.
    alpha : float
        Family-wise significance level.
    max_hz : float or None
        Highest frequency considered.
    max_combs : int
        Most further combs.
    rel_search : float
        Relative range of the floors' bands.
    max_harmonic : int or None
        Highest harmonic searched (the main comb's reach).
    main_f0 : float or None
        The main comb's fundamental (centre of the search).
    near_rel : float
        Relative search range around ``main_f0``.

    Examples
    --------
    >>> s = CombSearch(min_sep_hz=0.1, main_f0=50.02)
    >>> s.alpha, s.max_combs, s.near_rel
    (0.001, 2, 0.003)
    """

    min_sep_hz: float
    alpha: float = 1e-3
    max_hz: float | None = None
    max_combs: int = 2
    rel_search: float = 0.01
    max_harmonic: int | None = None
    main_f0: float | None = None
    near_rel: float = 0.003


@dataclass
class Comb:
    """A further comb: its fundamental (Hz), the harmonics found and every candidate's statistics.

    Examples
    --------
    >>> Comb(50.1, [2, 3, 4])
    Comb(fundamental_hz=50.1, harmonics=[2, 3, 4], candidates=[])
    """

    fundamental_hz: float
    harmonics: list[int]
    candidates: list[dict] = field(default_factory=list)


def detect_extra_combs(spec: _detect.Spectrum, sr: int, nominal: float, main: list, search: CombSearch) -> list[Comb]:
    """Further hum combs near the same nominal fundamental (a second device, or the grid seen
    through another sample clock), found on a high-resolution spectrum with the lines already
    explained masked out.

    ``main``: (frequency, half-width) of every line already removed. Further combs are searched
    within ``search.near_rel`` (0.3 %) of ``search.main_f0``: a clock offset or a second device,
    not a musical note series that happens to lie within 1 % of 50/60 Hz. A comb is kept when at least
    three of its harmonics pass the line test at ``alpha`` after a Bonferroni correction over all
    harmonics and all resolvable fundamentals in the search range (the look-elsewhere effect);
    harmonics closer than ``min_sep_hz`` to a line already removed are left to that line's fit
    (the two would be collinear over one block).

    Parameters
    ----------
    spec : Spectrum
        A fine spectrum of the input (with per-segment periodograms).
    sr : int
        Sample rate (Hz).
    nominal : float
        Nominal fundamental (Hz).
    main : list of (float, float)
        Lines already removed: frequency and half-width (Hz).
    search : CombSearch
        Settings.

    Returns
    -------
    list of Comb

    Examples
    --------
    >>> from odnn_sep.audio.detect import excerpt_spectrum
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(32 * sr) / sr
    >>> x = 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> for k in (1, 2, 3, 4):
    ...     x += 0.3 * np.cos(2 * np.pi * k * 50.1 * t + 2 * k)      # a comb at 50.1 Hz
    >>> spec = excerpt_spectrum(ArraySource(x, sr), seg_s=16.0, keep_segments_hz=500)
    >>> main = [(k * 50.0, 0.2) for k in (1, 2, 3, 4)]             # the main comb at 50 Hz
    >>> combs = detect_extra_combs(spec, sr, 50.0, main, CombSearch(0.05, main_f0=50.0, max_harmonic=4))
    >>> [(round(float(c.fundamental_hz), 2), c.harmonics) for c in combs]
    [(50.1, [2, 3, 4])]
    """
    ks_all = _detect.candidate_harmonics(nominal, sr, "auto", search.max_hz)
    # a further comb is searched only as far up as the main comb reaches: isolated high lines
    # are more likely tonal content than hum
    k_top = search.max_harmonic if search.max_harmonic is not None else _detect.MAX_HARMONICS
    ks_all = [k for k in ks_all if k <= k_top]
    if not ks_all:
        return []
    known = list(main)
    combs = []
    # the same grid seen through another clock, or a second device: close to the main comb
    centre = search.main_f0 if search.main_f0 is not None else nominal
    lo, hi = centre * (1 - search.near_rel), centre * (1 + search.near_rel)
    step = spec.df / (4 * max(ks_all))
    grid = np.arange(lo, hi, step)
    n_tests = len(ks_all) * max(1.0, (hi - lo) * max(ks_all) / spec.df)
    floors = _comb_floors(spec, nominal, ks_all, known, search.rel_search)
    for _ in range(search.max_combs):
        fc = _best_fundamental(spec, grid, step, ks_all, floors, known, search.min_sep_hz)
        sig, cands = _comb_lines(spec, fc, ks_all, known, search, n_tests)
        if len(sig) < 3:   # a note and its octave (k, 2k) must not pass for a comb
            break
        combs.append(Comb(fundamental_hz=fc, harmonics=sig, candidates=cands))
        known += [(k * fc, 1.5 * spec.df) for k in sig]
        log.info("further hum comb at %.4f Hz, harmonics %s", fc, sig)
    return combs


def _comb_floors(spec, nominal, ks_all, known, rel_search) -> dict:
    """Pooled local floor at each harmonic of the nominal family (inf where unknown)."""
    pooled = _detect.pooled_psd(spec)
    df = spec.df
    floors = {}
    spec_pooled = _detect.Spectrum(spec.freqs, pooled[:, None], spec.n_segments, spec.seconds)
    for k in ks_all:
        st = _detect.line_level(spec_pooled, k * nominal, k * nominal * rel_search + 2 * df, known)
        floors[k] = float(st["floor"][0]) if np.isfinite(st["floor"][0]) else np.inf
    return floors


def _best_fundamental(spec, grid, step, ks_all, floors, known, min_sep_hz) -> float:
    """The grid fundamental whose harmonics (away from the known lines) stand highest over their
    floors (sum of log(1 + level)), refined by a parabola."""
    pooled = _detect.pooled_psd(spec)
    df = spec.df
    score = np.zeros_like(grid)
    for k in ks_all:
        val = np.interp(k * grid, spec.freqs, pooled) / floors[k]
        for f, bw in known:
            val[np.abs(k * grid - f) - max(bw - 2 * df, 0.0) < max(min_sep_hz, 2 * df)] = 0.0
        score += np.log1p(val)
    i = int(np.argmax(score))
    fc = float(grid[i])
    if 0 < i < len(grid) - 1:
        a, b, c = score[i - 1: i + 2]
        den = a - 2 * b + c
        if den < 0:
            fc += 0.5 * (a - c) / den * step
    return fc


def _comb_lines(spec, fc, ks_all, known, search: CombSearch, n_tests):
    """The harmonics of ``fc`` that pass the line test (Bonferroni over ``n_tests``), and every
    candidate's statistics."""
    df = spec.df
    sig, cands = [], []
    bw = 1.5 * df
    for k in ks_all:
        fk = k * fc
        # centre-to-centre distance, less only the drift part of a known line's width
        if min((abs(fk - f) - max(b - 2 * df, 0.0) for f, b in known), default=np.inf) < max(search.min_sep_hz, 2 * df):
            continue
        st = _detect.line_test(spec, fk, bw, known + [(j * fc, bw) for j in ks_all if j != k])
        if not np.isfinite(st["floor"]).all():
            continue
        p_adj = min(1.0, st["p_value"] * n_tests)
        cands.append({"family_hz": fc, "harmonic": k, "freq_hz": fk, "level_db": [float(v) for v in st["level_db"]],
                      "p_value_bonferroni": p_adj, "significant": bool(p_adj < search.alpha)})
        if p_adj < search.alpha:
            sig.append(k)
    return sig, cands


def refine_combs(source, sr: int, combs: list[Comb], main_f0: float | None, spec, tones=()) -> list[float]:
    """Refine each comb's fundamental in place, and each tone, on the demodulated signal (one long
    window); returns the refined tones.

    The spectrum locates a fixed line only to a fraction of a bin; a fixed-frequency fit over
    16 s blocks needs it to about 1e-3 Hz at the tenth harmonic, and amplitudes pooled over
    several blocks need it still finer (a 5 mHz error turns the phase by 0.13 rad per 4 s).
    One demodulation pass serves every comb and tone.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input.
    sr : int
        Sample rate (Hz).
    combs : list of Comb
        Modified in place (fundamental refined; lines that are not phase-locked dropped, and
        combs left with fewer than 3 lines removed from the list).
    main_f0 : float or None
        The main comb's fundamental (Hz).
    spec : Spectrum
        The spectrum the combs were found on.
    tones : sequence of float
        Tones (Hz) to refine.

    Returns
    -------
    list of float
        The refined tones.

    Examples
    --------
    >>> from odnn_sep.audio.detect import excerpt_spectrum
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(32 * sr) / sr
    >>> x = 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> for k in (2, 3, 4):
    ...     x += 0.3 * np.cos(2 * np.pi * k * 50.1 * t + 2 * k)
    >>> src = ArraySource(x, sr)
    >>> spec = excerpt_spectrum(src, seg_s=16.0)
    >>> combs = [Comb(50.102, [2, 3, 4])]
    >>> refine_combs(src, sr, combs, 50.0, spec), [(round(c.fundamental_hz, 4), c.harmonics) for c in combs]
    ([], [(50.1, [2, 3, 4])])
    """
    tones = [float(t) for t in tones]
    if not combs and not tones:
        return tones
    freqs = [k * c.fundamental_hz for c in combs for k in c.harmonics] + tones
    D2 = _track.demodulate(source, 1.0, freqs)
    fixed = [c.fundamental_hz for c in combs] + tones
    near = [main_f0] if main_f0 else []

    def weights(fs):
        return np.stack([1.0 / np.maximum(spec.psd[np.argmin(np.abs(spec.freqs - f))], 1e-300) for f in fs], axis=1)

    col = 0
    for ci, c in enumerate(combs):
        others = near + [o.fundamental_hz for j, o in enumerate(combs) if j != ci]
        half = 2 * spec.df / min(c.harmonics)
        if others:
            half = min(half, 0.45 * min(abs(o - c.fundamental_hz) for o in others))
        kc = len(c.harmonics)
        c.fundamental_hz = _track.refine_fixed_comb(D2[:, :, col: col + kc], sr, c.fundamental_hz, c.harmonics,
                                                    weights([k * c.fundamental_hz for k in c.harmonics]),
                                                    half_hz=half)
        col += kc
    _keep_locked(D2, sr, combs, freqs)
    out = []
    for i, t in enumerate(tones):
        others = [f for f in fixed if f != t] + ([k * main_f0 for k in range(1, int(t / main_f0) + 2)]
                                                 if main_f0 else [])
        half = 2 * spec.df
        if others:
            half = min(half, 0.45 * min(abs(o - t) for o in others))
        out.append(_track.refine_fixed_comb(D2[:, :, col + i: col + i + 1], sr, t, [1], weights([t]),
                                            half_hz=half))
    return out


def _keep_locked(D2, sr: int, combs: list[Comb], freqs_before, alpha: float = 1e-3, min_lines: int = 3) -> None:
    """Keep only the comb lines that are phase-locked to their (refined) fixed frequency, and only
    combs with at least ``min_lines`` of them (lock.py): partials of repeated notes near the
    harmonics can pass the spectrum's test as a comb, but not the lock test. ``D2``: chunk sums at
    ``freqs_before`` (the comb lines before refinement, then the tones)."""
    from odnn_sep.audio import finetrack as _finetrack
    from odnn_sep.audio import lock as _lock

    tc = _finetrack.chunk_times(D2.shape[0], sr)
    col, kept = 0, []
    for c in combs:
        good, side = [], []
        for k in c.harmonics:
            u = D2[:, :, col: col + 1] * np.exp(-2j * np.pi * (k * c.fundamental_hz - freqs_before[col]) * tc)[:, None, None]
            p, _ = _lock.lock_p_values(u, sr)
            if p[0] < alpha:
                good.append(k)
                side.append(_fixed_line_sidebands(u[:, :, 0], sr))
            col += 1
        good = _off_host_grid(c, good, side)
        if len(good) >= min_lines:
            c.harmonics = good
            kept.append(c)
        else:
            log.info("comb at %.4f Hz dropped: lines %s are not phase-locked", c.fundamental_hz,
                     [k for k in c.harmonics if k not in good])
    combs[:] = kept


def _fixed_line_sidebands(u: np.ndarray, sr: int) -> float:
    """The strongest symmetric pair of sidebands (0.15-4 Hz) in the baseband of one fixed line, against
    the line's own power (``hostgrid.baseband_sidebands``); ``u``: its (J, C) chunk sums, already turned
    to the line's frequency. NaN when the input is too short to resolve them."""
    from odnn_sep.audio import finetrack as _finetrack
    from odnn_sep.audio import hostgrid as _hostgrid

    nd = u.shape[0] // _finetrack.DECIM
    if nd < 16:
        return float("nan")
    v = u[: nd * _finetrack.DECIM].reshape(nd, _finetrack.DECIM, -1).mean(axis=1).sum(axis=1)
    return float(_hostgrid.baseband_sidebands(v[:, None], _finetrack.decimated_rate(sr))[0])


def _off_host_grid(c: Comb, ks: list[int], side: list[float]) -> list[int]:
    """``ks`` (the locked lines of further comb ``c``) without the lines of a periodic host, when they
    are at least half of them. A drum loop placed to the sample has lines at every multiple of 1/P
    (P its period: 1-4 s), so every multiple of 50 and 60 Hz holds one, exactly steady and locked to
    its fixed frequency: such a "comb" at exactly 50.000 or 60.000 Hz passed beside the real hum
    (60.045 Hz) and its removal cost more than the hum left (24 instead of 41 dB). Its lines hold
    the loop's neighbouring lines as sidebands of their baseband (``side``: each at least
    ``hostgrid.BASEBAND_SIDE`` of the line; development loops 0.36-1.1), a hum line none (the room
    recording's further combs: 0.01-0.11). As in lockcomb, a few such lines decide nothing: a
    hum comb's weak lines among a loop's can show them too."""
    from odnn_sep.audio import hostgrid as _hostgrid

    host = [k for k, r in zip(ks, side, strict=True) if r >= _hostgrid.BASEBAND_SIDE]
    if not host or 2 * len(host) < len(ks):
        return list(ks)
    log.info("comb at %.4f Hz: lines %s hold the neighbouring lines of a periodic host as sidebands "
             "(a drum loop or a sequenced pattern placed to the sample): not taken for hum", c.fundamental_hz, host)
    return [k for k in ks if k not in host]
