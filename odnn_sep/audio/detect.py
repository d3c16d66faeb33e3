"""Hum detection: which fundamental (50, 60 Hz or a given one) and which harmonics are present.

A line is "present" when the power in a narrow band around it is significantly above the local
noise floor of a Welch spectrum (chi-square test on the averaged periodogram, Bonferroni-corrected
over every candidate line tested). The same statistic, in dB, is the "line level above the local
floor" reported before and after processing.
"""
from __future__ import annotations

import functools
import logging
from dataclasses import dataclass, field

import numpy as np
from scipy import special

from odnn_sep.audio.spectrum import Spectrum, excerpt_spectrum  # noqa: F401  (re-exported)

log = logging.getLogger(__name__)

DRIFT_TOL_HZ = 0.1      # fundamental wander the detection band allows for (per harmonic: k times this)
MAX_HARMONICS = 40
FLOOR_GAP_HZ = 1.0      # gap between a line band and the floor region
FLOOR_WIDTH_HZ = 8.0    # width of the floor region on each side
# Spectra coarser than this (inputs under about 8 s) place the fundamental by its strongest line's
# interpolated peak (``refine_fundamental``); the vote over every harmonic stands on finer ones.
COARSE_DF_HZ = 0.25
STRONG_LINE = 10.0      # peak power over the local floor of a line that can place the fundamental alone


@dataclass
class Detection:
    """What :func:`detect_hum` decided.

    Attributes
    ----------
    mains_hz : float or None
        Refined fundamental (Hz); None when no hum was found.
    nominal_hz : float or None
        50, 60 or the requested value.
    harmonics : list of int
        Harmonic numbers to remove.
    tones : list of float
        Refined tone frequencies (Hz).
    candidates : list of dict
        Every line tested, with its statistics.
    floors : dict
        ``(kind, k)`` -> per-channel floor PSD of each chosen line (``kind`` 'h' or 'tone').
    alpha : float
        Family-wise significance level used.

    Examples
    --------
    >>> d = Detection(mains_hz=50.01, nominal_hz=50.0, harmonics=[1, 3], tones=[])
    >>> d.harmonics, d.candidates, d.alpha
    ([1, 3], [], 0.001)
    """

    mains_hz: float | None                 # refined fundamental (Hz), None when no hum was found
    nominal_hz: float | None               # 50, 60 or the requested value
    harmonics: list[int]                   # harmonic numbers that will be removed
    tones: list[float]                     # refined tone frequencies (Hz)
    candidates: list[dict] = field(default_factory=list)   # every line tested, with its statistics
    floors: dict = field(default_factory=dict)             # (kind, k) -> per-channel floor PSD
    alpha: float = 1e-3


@functools.lru_cache(maxsize=64)
def _chi2_median(nu: float) -> float:
    # chi2.median(nu) is chi2.ppf(0.5, nu) = 2 gammaincinv(nu / 2, 0.5); scipy.special only, so
    # the command line does not pay for importing scipy.stats
    return float(2 * special.gammaincinv(nu / 2, 0.5))


def _median0(a: np.ndarray) -> np.ndarray:
    """``np.median(a, axis=0)`` for finite data, without its generic wrapping (called hundreds of
    times per input on a few dozen bins): the middle value, or the mean of the two middle ones."""
    n = a.shape[0]
    s = np.sort(a, axis=0)
    return s[n // 2] if n % 2 else (s[n // 2 - 1] + s[n // 2]) / 2


def pooled_psd(spec: Spectrum) -> np.ndarray:
    """The channels' PSDs summed; channels of uneven levels each over its own level
    (:attr:`Spectrum.channel_weights`). Its uses are ratios to a floor of the same pooled spectrum.

    Examples
    --------
    >>> s = Spectrum(np.arange(8) * 0.5, np.array([[1.0, 100.0]] * 8), 4, 10.0)
    >>> pooled_psd(s).tolist()[:2]
    [2.0, 2.0]
    """
    w = spec.channel_weights
    return spec.psd.sum(axis=1) if w is None else (spec.psd * w).sum(axis=1)


def band_halfwidth(spec: Spectrum, k: float) -> float:
    """Half-width (Hz) of the band tested for harmonic ``k``: two bins plus ``k`` times the drift
    tolerance :data:`DRIFT_TOL_HZ`.

    Parameters
    ----------
    spec : Spectrum
        The spectrum tested (gives the bin width).
    k : float
        Harmonic number (0 for a fixed tone).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> spec = Spectrum(np.arange(10) * 0.25, np.ones((10, 1)), 4, 10.0)
    >>> band_halfwidth(spec, 0), round(band_halfwidth(spec, 3), 2)
    (0.5, 0.8)
    """
    return 2.0 * spec.df + DRIFT_TOL_HZ * k


def persistence_p_value(spec: Spectrum, f: float, bw: float, floor: np.ndarray) -> float:
    """P-value that the line is present throughout, not only in a few segments.

    Statistic: the median over segments of the band-mean periodogram over the floor. Under
    "no line" each segment's band mean is Gamma(M, 1/M) (M effective bins), and the median of L
    of them exceeds x with probability binom.sf(ceil(L/2) - 1, L, q(x)). A transient host note
    that sits on a harmonic raises the mean spectrum but not this median, so it is not taken for
    hum.

    Parameters
    ----------
    spec : Spectrum
        With per-segment periodograms (``segments``); without them the p-value is 1.
    f : float
        Line frequency (Hz).
    bw : float
        Band half-width (Hz).
    floor : (channels,) array
        Local floor PSD per channel (from :func:`line_level`).

    Returns
    -------
    float

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> spec = excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=1000)
    >>> floor = line_level(spec, 50.0, 0.5)["floor"]
    >>> persistence_p_value(spec, 50.0, 0.5, floor) < 1e-6
    True
    """
    S = spec.segments
    if S is None:
        return 1.0
    fr = spec.freqs[: S.shape[0]]
    band = np.abs(fr - f) <= bw
    if not band.any():
        return 1.0
    if spec.channel_weights is None:
        bm = S[band].mean(axis=0).sum(axis=0).astype(np.float64) / max(float(np.sum(floor)), 1e-300)
    else:   # channels of uneven levels: each over its own floor (as line_level pools them)
        bm = (S[band].mean(axis=0).astype(np.float64)
              / np.maximum(np.asarray(floor, float), 1e-300)[:, None]).mean(axis=0)
    L = bm.shape[0]
    x = float(_median0(bm))
    m_eff = max(1.0, band.sum() / 1.5) * S.shape[1]
    q = float(special.gammaincc(m_eff, x * m_eff))     # gamma.sf, without scipy.stats' overhead
    # overlapping segments are not independent: count them as 0.9 each
    L_eff = max(1, int(round(0.9 * L)))
    return float(special.bdtrc(int(np.ceil(L_eff / 2)) - 1, L_eff, q))   # binom.sf


def line_level(spec: Spectrum, f: float, bw: float, exclude=()) -> dict:
    """Power in ``f +- bw`` relative to the local floor, per channel and pooled, with a p-value.

    ``exclude``: (frequency, half-width) of other lines kept out of the floor estimate.

    Parameters
    ----------
    spec : Spectrum
        The spectrum.
    f : float
        Line frequency (Hz).
    bw : float
        Band half-width (Hz).
    exclude : sequence of (float, float)
        Other lines' frequency and half-width (Hz).

    Returns
    -------
    dict
        ``level_db`` (per channel), ``pooled_db``, ``p_value`` (chi-square, one line) and
        ``floor`` (per-channel floor PSD); NaN levels and p-value 1 when the floor region has
        fewer than 4 bins.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> st = line_level(excerpt_spectrum(ArraySource(y, sr)), 50.0, 1.5)
    >>> round(st["pooled_db"]), st["p_value"] < 1e-6
    (23, True)
    """
    # work on the few bins around the line only (long spectra have ~10^5 bins)
    reach = bw + FLOOR_GAP_HZ + FLOOR_WIDTH_HZ + spec.df
    i0, i1 = np.searchsorted(spec.freqs, [f - reach, f + reach])
    i1 = max(i1, i0 + 1)
    fr = spec.freqs[i0:i1]
    psd = spec.psd[i0:i1]
    d = np.abs(fr - f)
    band = d <= bw
    if not band.any():
        band = d == d.min()
    near = (d >= bw + FLOOR_GAP_HZ) & (d <= bw + FLOOR_GAP_HZ + FLOOR_WIDTH_HZ) & (fr > 0.5)
    if len(exclude):
        # the other lines within reach, all at once
        ex = np.asarray(exclude, dtype=float).reshape(-1, 2)
        ex = ex[np.abs(ex[:, 0] - f) <= reach + ex[:, 1]]
        if len(ex):
            near &= (np.abs(fr[None, :] - ex[:, :1]) > ex[:, 1:] + 0.5 * FLOOR_GAP_HZ).all(axis=0)
    if near.sum() < 4:
        return {"level_db": np.full(spec.psd.shape[1], np.nan), "pooled_db": np.nan, "p_value": 1.0,
                "floor": np.full(spec.psd.shape[1], np.nan)}
    nu = spec.dof_per_bin
    # the median of a chi2(nu)/nu variable sits below its mean; correct so the floor is a mean
    med_corr = _chi2_median(nu) / nu
    # numerical floor 120 dB under the mean PSD: lines in float rounding noise of a synthetic
    # or digitally silent signal are not hum
    floor = np.maximum(_median0(psd[near]) / med_corr, spec.numerical_floor)
    level = psd[band].mean(axis=0)
    ratio = level / np.maximum(floor, 1e-300)
    if spec.channel_weights is None:
        pooled = level.sum() / max(floor.sum(), 1e-300)
    else:
        # channels of uneven levels: each over its own floor, then the mean (a channel whose floor
        # is far above the others', an EEG electrode that saturated, hid every other channel's line)
        pooled = float(np.mean(ratio))
    m = int(band.sum())
    dof = nu * spec.psd.shape[1] * max(1.0, m / 1.5)   # neighbouring Hann bins are correlated
    p = float(special.chdtrc(dof, pooled * dof))       # chi2.sf
    with np.errstate(divide="ignore"):
        return {"level_db": 10 * np.log10(ratio), "pooled_db": float(10 * np.log10(pooled)),
                "p_value": p, "floor": floor}


def line_test(spec: Spectrum, f: float, bw: float, exclude=()) -> dict:
    """:func:`line_level`, its p-value raised to that of :func:`persistence_p_value` where the
    local floor is known (a line must stand out on average and in most segments).

    Parameters
    ----------
    spec, f, bw, exclude
        As in :func:`line_level`.

    Returns
    -------
    dict
        As :func:`line_level`.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> spec = excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=1000)
    >>> line_test(spec, 50.0, 1.5)["p_value"] < 1e-6
    True
    """
    st = line_level(spec, f, bw, exclude)
    if np.isfinite(st["floor"]).all():
        st["p_value"] = max(st["p_value"], persistence_p_value(spec, f, bw, st["floor"]))
    return st


def refine_fundamental(spec: Spectrum, nominal: float, ks, *, rel_search: float = 0.01) -> float:
    """Fundamental maximising the floor-normalised power summed over harmonics (SNR weighting).

    Parameters
    ----------
    spec : Spectrum
        The spectrum (channels pooled).
    nominal : float
        Nominal fundamental (Hz).
    ks : sequence of int
        Harmonics that vote.
    rel_search : float
        Relative search range around ``nominal``.

    Returns
    -------
    float

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> round(refine_fundamental(excerpt_spectrum(ArraySource(y, sr)), 50.0, [1, 2, 3]), 1)
    50.0
    """
    pooled = pooled_psd(spec)
    lo, hi = nominal * (1 - rel_search), nominal * (1 + rel_search)
    grid = np.arange(lo, hi, min(0.002, spec.df / 20))
    score = np.zeros_like(grid)
    spec_pooled = Spectrum(spec.freqs, pooled[:, None], spec.n_segments, spec.seconds)
    for k in ks:
        st = line_level(spec_pooled, k * nominal, band_halfwidth(spec, k) + k * nominal * rel_search)
        fl = float(st["floor"][0]) if np.isfinite(st["floor"][0]) else 1.0
        # log scale: every harmonic votes, not just the strongest one (whose broad peak alone
        # cannot pin the fundamental to better than its bin width)
        score += np.log1p(np.interp(k * grid, spec.freqs, pooled) / max(fl, 1e-300))
    i = int(np.argmax(score))
    if 0 < i < len(grid) - 1:
        a, b, c = score[i - 1: i + 2]
        den = a - 2 * b + c
        off = 0.5 * (a - c) / den if den < 0 else 0.0
        f0 = float(grid[i] + off * (grid[1] - grid[0]))
    else:
        f0 = float(grid[i])
    if spec.df > COARSE_DF_HZ:
        # few bins per hertz: the interpolated spectrum peaks at a bin, up to half a bin (0.4 Hz at
        # 2.5 s) from the line, and the noise of 40 harmonics' bins outvotes one clear line; the
        # strongest line's own peak, interpolated on its three bins, places it to a small part of a bin
        f_line = _strongest_line(spec_pooled, nominal, ks, rel_search)
        if f_line is not None:
            return f_line
    return f0


def strongest_line_fundamental(spec: Spectrum, nominal: float, ks, *, min_ratio: float = STRONG_LINE,
                               rel_search: float = 0.01) -> float | None:
    """The fundamental placed by the strongest of harmonics ``ks`` alone (its interpolated peak in
    the channels-pooled spectrum), or None when none stands ``min_ratio`` times over its floor.

    :func:`refine_fundamental`'s vote counts every harmonic; where the spectrum has a shape of its
    own (an EEG's 1/f slope and an anti-alias or notch filter's dips), harmonics without a line
    vote for bumps of that shape and can outvote the one clear line: a 50.00 Hz EEG line was placed
    at 49.63 Hz by a bump beside a dip at 100 Hz.

    Parameters
    ----------
    spec : Spectrum
        The spectrum.
    nominal : float
        Nominal fundamental (Hz).
    ks : sequence of int
        Harmonics that may place it.
    min_ratio : float
        Least peak power over the local floor.
    rel_search : float
        Relative search range around ``nominal``.

    Returns
    -------
    float or None

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 500; t = np.arange(60 * sr) / sr
    >>> y = 0.3 * np.cos(2 * np.pi * 50.0 * t) + np.random.default_rng(0).standard_normal(t.size)
    >>> round(strongest_line_fundamental(excerpt_spectrum(ArraySource(y, sr)), 50.0, [1, 2]), 2)
    50.0
    """
    pooled = pooled_psd(spec)
    return _strongest_line(Spectrum(spec.freqs, pooled[:, None], spec.n_segments, spec.seconds), nominal, ks,
                           rel_search, min_ratio=min_ratio)


def _strongest_line(spec: Spectrum, nominal: float, ks, rel_search: float,
                    min_ratio: float = STRONG_LINE) -> float | None:
    """The fundamental given by the strongest harmonic's peak in the channels-pooled ``spec``
    (quadratic interpolation of the log power on the peak bin and its neighbours, exact to a few
    hundredths of a bin for a Hann window), or None when no harmonic stands ``min_ratio`` times
    over its floor."""
    pooled = spec.psd[:, 0]
    best = None
    for k in ks:
        lo, hi = k * nominal * (1 - rel_search), k * nominal * (1 + rel_search)
        sel = np.flatnonzero((spec.freqs >= lo - spec.df) & (spec.freqs <= hi + spec.df))
        if len(sel) == 0:
            continue
        j = int(sel[np.argmax(pooled[sel])])
        if j == 0 or j >= len(pooled) - 1:
            continue
        st = line_level(spec, k * nominal, band_halfwidth(spec, k) + k * nominal * rel_search)
        fl = float(st["floor"][0])
        ratio = float(pooled[j]) / fl if np.isfinite(fl) and fl > 0 else 0.0
        if ratio >= min_ratio and (best is None or ratio > best[0]):
            best = (ratio, k, j)
    if best is None:
        return None
    _, k, j = best
    a, b, c = np.log(np.maximum(pooled[j - 1: j + 2], 1e-300))
    den = a - 2 * b + c
    off = float(np.clip(0.5 * (a - c) / den, -0.5, 0.5)) if den < 0 else 0.0
    f = (spec.freqs[j] + off * spec.df) / k
    return float(f) if abs(f - nominal) <= nominal * rel_search else None


LOW_RATE_HZ = 1000.0    # at or below this sample rate (EEG, ECG) lines are looked for up to ...
NYQ_MARGIN_HZ = 5.0     # ... this far below the Nyquist frequency (5 % of it when that is less)


def top_hz(sr: float, max_hz: float | None = None) -> float:
    """Highest line frequency looked at: 0.95 x Nyquist (an anti-alias filter's roll-off), or at
    EEG and ECG rates (``LOW_RATE_HZ`` and under) ``NYQ_MARGIN_HZ`` below Nyquist, where 5 % of it
    is 6-25 Hz, far more than a line and its floor need: at 256 Hz the 120 Hz harmonic of 60 Hz
    mains (8 Hz under Nyquist) was never tested, and a recording whose hum sat half there gained
    7 dB instead of 36 dB. ``max_hz`` caps it.

    Parameters
    ----------
    sr : float
        Sample rate (Hz).
    max_hz : float, optional
        The caller's cap (Hz).

    Returns
    -------
    float

    Examples
    --------
    >>> top_hz(8000), top_hz(256), top_hz(150), top_hz(8000, 1000.0)
    (3800.0, 123.0, 71.25, 1000.0)
    """
    nyq = sr / 2
    top = nyq - min(0.05 * nyq, NYQ_MARGIN_HZ) if sr <= LOW_RATE_HZ else 0.95 * nyq
    return top if max_hz is None else min(top, max_hz)


def candidate_harmonics(f0: float, sr: int, harmonics, max_hz: float | None) -> list[int]:
    """Harmonic numbers to test: ``'auto'`` (up to MAX_HARMONICS), a count or a list, each below
    :func:`top_hz` (or ``max_hz``) with room for drift.

    Parameters
    ----------
    f0 : float
        Fundamental (Hz).
    sr : int
        Sample rate (Hz).
    harmonics : 'auto', int or list of int
        As normalised by :func:`~odnn_sep.audio.options.parse_harmonics`.
    max_hz : float or None
        Highest frequency considered (Hz).

    Returns
    -------
    list of int

    Examples
    --------
    >>> candidate_harmonics(60.0, 400, "auto", None), candidate_harmonics(50.0, 8000, [1, 3, 5], 200)
    ([1, 2, 3], [1, 3])
    >>> candidate_harmonics(60.0, 256, "auto", None)             # 120 Hz lies 8 Hz under Nyquist
    [1, 2]
    >>> len(candidate_harmonics(50.0, 8000, "auto", None)), candidate_harmonics(50.0, 8000, 3, None)
    (40, [1, 2, 3])
    """
    top = top_hz(sr, max_hz)
    if isinstance(harmonics, list):
        cand = harmonics
    else:
        cand = range(1, (MAX_HARMONICS if harmonics == "auto" else int(harmonics)) + 1)
    return [k for k in cand if k * f0 * (1 + 0.002) + 2.0 < top]


def detect_hum(spec: Spectrum, sr: int, *, mains="auto", harmonics="auto", tones=(),
               alpha: float = 1e-3, max_hz: float | None = None, f0: float | None = None) -> Detection:
    """Decide the fundamental and the harmonics to remove (see the module docstring).

    Parameters
    ----------
    spec : Spectrum
        Spectrum of the input (with per-segment periodograms for the persistence test).
    sr : int
        Sample rate (Hz).
    mains, harmonics, tones, alpha, max_hz
        As validated by :class:`~odnn_sep.audio.options.DenoiseOptions`.
    f0 : float, optional
        Test the lines of this fundamental as it is (not refined) in the family of the numeric
        ``mains``, which stays the nominal.

    Returns
    -------
    Detection

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> det = detect_hum(excerpt_spectrum(ArraySource(y, sr), keep_segments_hz=1000), sr)
    >>> det.nominal_hz, det.harmonics[:3], round(det.mains_hz, 1)
    (50.0, [1, 2, 3], 50.0)
    """
    nominals = [50.0, 60.0] if mains == "auto" else [float(mains)]
    fams = {}
    n_tests = 0
    for nom in nominals:
        ks = candidate_harmonics(nom, sr, "auto" if harmonics == "auto" else harmonics, max_hz)
        if not ks:
            continue
        fams[nom] = (refine_fundamental(spec, nom, ks) if f0 is None else float(f0), ks)
        n_tests += len(ks)
    n_tests = max(n_tests, 1)
    candidates, best, best_ev = [], None, 0.0
    floors = {}
    for nom, (f0, ks) in fams.items():
        excl = [(k * f0, band_halfwidth(spec, k)) for k in ks] + [(t, band_halfwidth(spec, 1)) for t in tones]
        ev, sig = 0.0, []
        for k in ks:
            bw = band_halfwidth(spec, k)
            st = line_test(spec, k * f0, bw, [e for e in excl if abs(e[0] - k * f0) > 1e-9])
            p_adj = min(1.0, st["p_value"] * n_tests)
            significant = p_adj < alpha
            if significant:
                sig.append(k)
                ev += -np.log10(max(p_adj, 1e-300))
            candidates.append({"family_hz": nom, "harmonic": k, "freq_hz": k * f0,
                               "level_db": [float(v) for v in st["level_db"]], "pooled_db": st["pooled_db"],
                               "p_value_bonferroni": p_adj, "significant": bool(significant)})
            floors[(nom, k)] = st["floor"]
        if ev > best_ev:
            best, best_ev = nom, ev
    if harmonics != "auto" and fams:
        # the caller fixed the harmonic count: use the requested (or best) family and every harmonic
        nom = best if best is not None else nominals[0]
        f0, ks = fams[nom]
        chosen = ks
    elif best is None:
        nom, f0, chosen = None, None, []
    else:
        nom = best
        f0, ks = fams[nom]
        chosen = [c["harmonic"] for c in candidates if c["family_hz"] == nom and c["significant"]]
    tone_list = refine_tones(spec, tones)
    for t in tone_list:
        st = line_level(spec, t, band_halfwidth(spec, 0), [])
        # a tone the user named is tested on its own: its p-value is not corrected for other lines
        candidates.append({"family_hz": None, "harmonic": None, "freq_hz": t,
                           "level_db": [float(v) for v in st["level_db"]], "pooled_db": st["pooled_db"],
                           "p_value": st["p_value"], "significant": bool(st["p_value"] < alpha)})
        floors[("tone", t)] = st["floor"]
    det = Detection(mains_hz=f0 if chosen else None, nominal_hz=nom if chosen else None, harmonics=chosen,
                    tones=tone_list, candidates=candidates, floors=floors, alpha=alpha)
    det.floors = {("h", k): floors[(nom, k)] for k in chosen} | {("tone", t): floors[("tone", t)]
                                                                 for t in tone_list}
    log.info("hum detection: fundamental %s Hz (nominal %s), harmonics %s, tones %s",
             None if det.mains_hz is None else round(det.mains_hz, 4), det.nominal_hz, chosen, tone_list)
    return det


def refine_tones(spec: Spectrum, tones) -> list[float]:
    """Each tone at the spectrum's peak within +-0.5 Hz (parabolic on log power), or as given.

    Parameters
    ----------
    spec : Spectrum
        The spectrum (channels pooled).
    tones : sequence of float
        Tone frequencies (Hz).

    Returns
    -------
    list of float
        A tone is returned as given when fewer than 3 bins lie within +-0.5 Hz of it.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.audio.io import ArraySource
    >>> t = np.arange(24000) / 2000
    >>> x = 0.1 * np.random.default_rng(0).standard_normal(t.size) + np.sin(2 * np.pi * 300.1 * t)
    >>> [round(f, 2) for f in refine_tones(excerpt_spectrum(ArraySource(x, 2000)), [300.0])]
    [300.1]
    """
    tone_list = []
    pooled = pooled_psd(spec)
    for t in tones:
        m = np.abs(spec.freqs - t) <= 0.5
        if m.sum() >= 3:
            idx = np.flatnonzero(m)
            i = idx[int(np.argmax(pooled[idx]))]
            if 0 < i < len(pooled) - 1:
                a, b, c = np.log(pooled[i - 1: i + 2] + 1e-300)
                den = a - 2 * b + c
                off = 0.5 * (a - c) / den if den < 0 else 0.0
                tone_list.append(float(spec.freqs[i] + off * spec.df))
                continue
        tone_list.append(float(t))
    return tone_list


def line_levels(spec: Spectrum, freqs, *, half_width_hz=None) -> list[dict]:
    """Level of each given line above its local floor (dB, per channel), for the report.

    Parameters
    ----------
    spec : Spectrum
        The spectrum.
    freqs : sequence of float
        Line frequencies (Hz); each is kept out of the others' floors.
    half_width_hz : float, optional
        Band half-width (Hz); default :func:`band_halfwidth` at ``f / 60``.

    Returns
    -------
    list of dict
        ``freq_hz`` and ``level_db`` (list, per channel) per line.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> lv = line_levels(excerpt_spectrum(ArraySource(y, sr)), [50.0, 100.0])
    >>> [(d["freq_hz"], round(d["level_db"][0])) for d in lv]
    [(50.0, 23), (100.0, 25)]
    """
    out = []
    all_lines = list(freqs)
    for i, f in enumerate(all_lines):
        bw = half_width_hz if half_width_hz is not None else band_halfwidth(spec, max(1.0, f / 60.0))
        excl = [(g, bw) for j, g in enumerate(all_lines) if j != i]
        st = line_level(spec, f, bw, excl)
        out.append({"freq_hz": float(f), "level_db": [float(v) for v in st["level_db"]]})
    return out

