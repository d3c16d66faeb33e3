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
from scipy import signal, special, stats

log = logging.getLogger(__name__)

DRIFT_TOL_HZ = 0.1      # fundamental wander the detection band allows for (per harmonic: k times this)
MAX_HARMONICS = 40
FLOOR_GAP_HZ = 1.0      # gap between a line band and the floor region
FLOOR_WIDTH_HZ = 8.0    # width of the floor region on each side


@dataclass
class Spectrum:
    freqs: np.ndarray        # (nf,)
    psd: np.ndarray          # (nf, channels), mean power per Hz over segments
    n_segments: int          # Welch segments averaged (per channel)
    seconds: float           # signal duration analysed
    segments: np.ndarray | None = None   # (nf, channels, n_segments) per-segment PSD (for detection)

    @property
    def df(self) -> float:
        return float(self.freqs[1] - self.freqs[0])

    @property
    def numerical_floor(self) -> float:
        return 1e-12 * float(np.mean(self.psd)) + 1e-300

    @property
    def dof_per_bin(self) -> float:
        # Hann, 50 % overlap: each extra segment adds about 0.9 of an independent one
        return 2.0 * max(1.0, 0.9 * self.n_segments)


@dataclass
class Detection:
    mains_hz: float | None                 # refined fundamental (Hz), None when no hum was found
    nominal_hz: float | None               # 50, 60 or the requested value
    harmonics: list[int]                   # harmonic numbers that will be removed
    tones: list[float]                     # refined tone frequencies (Hz)
    candidates: list[dict] = field(default_factory=list)   # every line tested, with its statistics
    floors: dict = field(default_factory=dict)             # (kind, k) -> per-channel floor PSD
    alpha: float = 1e-3


def excerpt_spectrum(source, *, seg_s: float = 4.0, max_total_s: float = 240.0,
                     n_excerpts: int = 8, keep_segments_hz: float | None = None) -> Spectrum:
    """Welch PSD of the whole input, or of evenly spaced excerpts when it is longer than
    ``max_total_s`` (bounded time and memory on long files).

    ``keep_segments_hz``: also keep the per-segment periodograms below this frequency (used by
    the persistence test in :func:`detect_hum`).
    """
    sr, n = source.sr, source.frames
    nper = int(min(seg_s * sr, max(n // 2, 16)))
    nper = max(nper, min(n, 16))
    total = int(max_total_s * sr)
    if n <= total:
        spans = [(0, n)]
    else:
        length = total // n_excerpts
        starts = np.linspace(0, n - length, n_excerpts).astype(int)
        spans = [(int(s), length) for s in starts]
    acc, nseg, segs = None, 0, []
    for s, length in spans:
        x = source.read(s, length)
        if x.shape[0] < nper:
            continue
        f, P_sum, k, P_keep = _periodograms(x, sr, nper, keep_segments_hz)
        acc = P_sum if acc is None else acc + P_sum
        nseg += k
        if P_keep is not None:
            segs.append(P_keep)
    return Spectrum(freqs=f, psd=acc / nseg, n_segments=nseg, seconds=sum(s[1] for s in spans) / sr,
                    segments=np.concatenate(segs, axis=-1) if segs else None)


def _periodograms(x, sr, nper, keep_hz, batch: int = 16):
    """Hann-windowed, mean-removed periodograms of 50 %-overlapping segments (one-sided PSD, the
    scaling of ``scipy.signal.spectrogram(mode='psd')``), computed a few segments at a time so
    memory stays bounded. Returns freqs, the sum over segments (nf, C), the segment count and,
    when ``keep_hz`` is given, the per-segment PSD below it (nf_keep, C, segments) in float32."""
    from numpy.lib.stride_tricks import sliding_window_view
    from scipy import fft

    step = nper - nper // 2
    n, C = x.shape
    nseg = 1 + (n - nper) // step
    win = _hann(nper)
    scale = 1.0 / (sr * float((win.astype(np.float64) ** 2).sum()))
    f = fft.rfftfreq(nper, 1.0 / sr)
    onesided = np.full(len(f), 2.0)
    onesided[0] = 1.0
    if nper % 2 == 0:
        onesided[-1] = 1.0
    nkeep = int(np.searchsorted(f, keep_hz, side="right")) if keep_hz is not None else 0
    P_sum = np.zeros((len(f), C))
    keep = np.empty((nkeep, C, nseg), np.float32) if keep_hz is not None else None
    for c in range(C):
        view = sliding_window_view(x[:, c], nper)[::step][:nseg]
        for b0 in range(0, nseg, batch):
            seg = view[b0: b0 + batch]
            # mean removed in float64, then float32 for the window and the FFT: its rounding
            # noise (~1e-7 of the segment's RMS) sits far below the 120 dB numerical floor used
            # by the line tests, at half the cost of a float64 transform
            seg = ((seg - seg.mean(axis=1, keepdims=True)).astype(np.float32)) * win
            X = fft.rfft(seg, axis=1)
            P = X.real ** 2 + X.imag ** 2                       # float32: no cancellation here
            P *= (scale * onesided).astype(np.float32)
            P_sum[:, c] += P.sum(axis=0, dtype=np.float64)
            if keep is not None:
                keep[:, c, b0: b0 + P.shape[0]] = P[:, :nkeep].T
    return f, P_sum, nseg, keep


@functools.lru_cache(maxsize=64)
def _chi2_median(nu: float) -> float:
    return float(stats.chi2.median(nu))


@functools.lru_cache(maxsize=8)
def _hann(nper: int) -> np.ndarray:
    w = signal.get_window("hann", nper).astype(np.float32)
    w.flags.writeable = False
    return w


def band_halfwidth(spec: Spectrum, k: float) -> float:
    return 2.0 * spec.df + DRIFT_TOL_HZ * k


def persistence_p_value(spec: Spectrum, f: float, bw: float, floor: np.ndarray) -> float:
    """P-value that the line is present throughout, not only in a few segments.

    Statistic: the median over segments of the band-mean periodogram over the floor. Under
    "no line" each segment's band mean is Gamma(M, 1/M) (M effective bins), and the median of L
    of them exceeds x with probability binom.sf(ceil(L/2) - 1, L, q(x)). A transient host note
    that sits on a harmonic raises the mean spectrum but not this median, so it is not taken for
    hum.
    """
    S = spec.segments
    if S is None:
        return 1.0
    fr = spec.freqs[: S.shape[0]]
    band = np.abs(fr - f) <= bw
    if not band.any():
        return 1.0
    bm = S[band].mean(axis=0).sum(axis=0).astype(np.float64) / max(float(np.sum(floor)), 1e-300)
    L = bm.shape[0]
    x = float(np.median(bm))
    m_eff = max(1.0, band.sum() / 1.5) * S.shape[1]
    q = float(special.gammaincc(m_eff, x * m_eff))     # gamma.sf, without scipy.stats' overhead
    # overlapping segments are not independent: count them as 0.9 each
    L_eff = max(1, int(round(0.9 * L)))
    return float(special.bdtrc(int(np.ceil(L_eff / 2)) - 1, L_eff, q))   # binom.sf


def line_level(spec: Spectrum, f: float, bw: float, exclude=()) -> dict:
    """Power in ``f +- bw`` relative to the local floor, per channel and pooled, with a p-value.

    ``exclude``: (frequency, half-width) of other lines kept out of the floor estimate.
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
    for fo, bo in exclude:
        if abs(fo - f) <= reach + bo:
            near &= np.abs(fr - fo) > bo + 0.5 * FLOOR_GAP_HZ
    if near.sum() < 4:
        return {"level_db": np.full(spec.psd.shape[1], np.nan), "pooled_db": np.nan, "p_value": 1.0,
                "floor": np.full(spec.psd.shape[1], np.nan)}
    nu = spec.dof_per_bin
    # the median of a chi2(nu)/nu variable sits below its mean; correct so the floor is a mean
    med_corr = _chi2_median(nu) / nu
    # numerical floor 120 dB under the mean PSD: lines in float rounding noise of a synthetic
    # or digitally silent signal are not hum
    floor = np.maximum(np.median(psd[near], axis=0) / med_corr, spec.numerical_floor)
    level = psd[band].mean(axis=0)
    ratio = level / np.maximum(floor, 1e-300)
    pooled = level.sum() / max(floor.sum(), 1e-300)
    m = int(band.sum())
    dof = nu * spec.psd.shape[1] * max(1.0, m / 1.5)   # neighbouring Hann bins are correlated
    p = float(special.chdtrc(dof, pooled * dof))       # chi2.sf
    with np.errstate(divide="ignore"):
        return {"level_db": 10 * np.log10(ratio), "pooled_db": float(10 * np.log10(pooled)),
                "p_value": p, "floor": floor}


def refine_fundamental(spec: Spectrum, nominal: float, ks, *, rel_search: float = 0.01) -> float:
    """Fundamental maximising the floor-normalised power summed over harmonics (SNR weighting)."""
    pooled = spec.psd.sum(axis=1)
    lo, hi = nominal * (1 - rel_search), nominal * (1 + rel_search)
    grid = np.arange(lo, hi, min(0.002, spec.df / 20))
    score = np.zeros_like(grid)
    for k in ks:
        st = line_level(Spectrum(spec.freqs, pooled[:, None], spec.n_segments, spec.seconds),
                        k * nominal, band_halfwidth(spec, k) + k * nominal * rel_search)
        fl = float(st["floor"][0]) if np.isfinite(st["floor"][0]) else 1.0
        # log scale: every harmonic votes, not just the strongest one (whose broad peak alone
        # cannot pin the fundamental to better than its bin width)
        score += np.log1p(np.interp(k * grid, spec.freqs, pooled) / max(fl, 1e-300))
    i = int(np.argmax(score))
    if 0 < i < len(grid) - 1:
        a, b, c = score[i - 1: i + 2]
        den = a - 2 * b + c
        off = 0.5 * (a - c) / den if den < 0 else 0.0
        return float(grid[i] + off * (grid[1] - grid[0]))
    return float(grid[i])


def _candidate_harmonics(f0: float, sr: int, harmonics, max_hz: float | None) -> list[int]:
    nyq = sr / 2
    top = 0.95 * nyq if max_hz is None else min(0.95 * nyq, max_hz)
    if isinstance(harmonics, list):
        cand = harmonics
    else:
        cand = range(1, (MAX_HARMONICS if harmonics == "auto" else int(harmonics)) + 1)
    return [k for k in cand if k * f0 * (1 + 0.002) + 2.0 < top]


def detect_hum(spec: Spectrum, sr: int, *, mains="auto", harmonics="auto", tones=(),
               alpha: float = 1e-3, max_hz: float | None = None) -> Detection:
    """Decide the fundamental and the harmonics to remove (see the module docstring)."""
    nominals = [50.0, 60.0] if mains == "auto" else [float(mains)]
    fams = {}
    n_tests = 0
    for nom in nominals:
        ks = _candidate_harmonics(nom, sr, "auto" if harmonics == "auto" else harmonics, max_hz)
        if not ks:
            continue
        f0 = refine_fundamental(spec, nom, ks)
        fams[nom] = (f0, ks)
        n_tests += len(ks)
    n_tests = max(n_tests, 1)
    candidates, best, best_ev = [], None, 0.0
    floors = {}
    for nom, (f0, ks) in fams.items():
        excl = [(k * f0, band_halfwidth(spec, k)) for k in ks] + [(t, band_halfwidth(spec, 1)) for t in tones]
        ev, sig = 0.0, []
        for k in ks:
            bw = band_halfwidth(spec, k)
            st = line_level(spec, k * f0, bw, [e for e in excl if abs(e[0] - k * f0) > 1e-9])
            if np.isfinite(st["floor"]).all():
                st["p_value"] = max(st["p_value"], persistence_p_value(spec, k * f0, bw, st["floor"]))
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
    tone_list = []
    pooled = spec.psd.sum(axis=1)
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
    for t in tone_list:
        st = line_level(spec, t, band_halfwidth(spec, 0), [])
        candidates.append({"family_hz": None, "harmonic": None, "freq_hz": t,
                           "level_db": [float(v) for v in st["level_db"]], "pooled_db": st["pooled_db"],
                           "p_value_bonferroni": st["p_value"], "significant": bool(st["p_value"] < alpha)})
        floors[("tone", t)] = st["floor"]
    det = Detection(mains_hz=f0 if chosen else None, nominal_hz=nom if chosen else None, harmonics=chosen,
                    tones=tone_list, candidates=candidates, floors=floors, alpha=alpha)
    det.floors = {("h", k): floors[(nom, k)] for k in chosen} | {("tone", t): floors[("tone", t)]
                                                                 for t in tone_list}
    log.info("hum detection: fundamental %s Hz (nominal %s), harmonics %s, tones %s",
             None if det.mains_hz is None else round(det.mains_hz, 4), det.nominal_hz, chosen, tone_list)
    return det


def line_levels(spec: Spectrum, freqs, *, half_width_hz=None) -> list[dict]:
    """Level of each given line above its local floor (dB, per channel), for the report."""
    out = []
    all_lines = list(freqs)
    for i, f in enumerate(all_lines):
        bw = half_width_hz if half_width_hz is not None else band_halfwidth(spec, max(1.0, f / 60.0))
        excl = [(g, bw) for j, g in enumerate(all_lines) if j != i]
        st = line_level(spec, f, bw, excl)
        out.append({"freq_hz": float(f), "level_db": [float(v) for v in st["level_db"]]})
    return out


@dataclass
class Comb:
    fundamental_hz: float
    harmonics: list[int]
    candidates: list[dict] = field(default_factory=list)


def detect_extra_combs(spec: Spectrum, sr: int, nominal: float, main: list, *, min_sep_hz: float,
                       alpha: float = 1e-3, max_hz: float | None = None, max_combs: int = 2,
                       rel_search: float = 0.01, max_harmonic: int | None = None,
                       main_f0: float | None = None, near_rel: float = 0.003) -> list[Comb]:
    """Further hum combs near the same nominal fundamental (a second device, or the grid seen
    through another sample clock), found on a high-resolution spectrum with the lines already
    explained masked out.

    ``main``: (frequency, half-width) of every line already removed. Further combs are searched
    within ``near_rel`` (0.3 %) of ``main_f0``: a clock offset or a second device, not a musical
    note series that happens to lie within 1 % of 50/60 Hz. A comb is kept when at least
    three of its harmonics pass the line test at ``alpha`` after a Bonferroni correction over all
    harmonics and all resolvable fundamentals in the search range (the look-elsewhere effect);
    harmonics closer than ``min_sep_hz`` to a line already removed are left to that line's fit
    (the two would be collinear over one block).
    """
    pooled = spec.psd.sum(axis=1)
    df = spec.df
    ks_all = _candidate_harmonics(nominal, sr, "auto", max_hz)
    # a further comb is searched only as far up as the main comb reaches: isolated high lines
    # are more likely tonal content than hum
    k_top = max_harmonic if max_harmonic is not None else MAX_HARMONICS
    ks_all = [k for k in ks_all if k <= k_top]
    if not ks_all:
        return []
    known = list(main)
    combs = []
    # the same grid seen through another clock, or a second device: close to the main comb
    centre = main_f0 if main_f0 is not None else nominal
    lo, hi = centre * (1 - near_rel), centre * (1 + near_rel)
    step = df / (4 * max(ks_all))
    grid = np.arange(lo, hi, step)
    n_grid_eff = max(1.0, (hi - lo) * max(ks_all) / df)
    floors = {}
    for k in ks_all:
        st = line_level(Spectrum(spec.freqs, pooled[:, None], spec.n_segments, spec.seconds), k * nominal,
                        k * nominal * rel_search + 2 * df, known)
        floors[k] = float(st["floor"][0]) if np.isfinite(st["floor"][0]) else np.inf
    for _ in range(max_combs):
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
        n_tests = len(ks_all) * n_grid_eff
        sig, cands = [], []
        bw = 1.5 * df
        for k in ks_all:
            fk = k * fc
            # centre-to-centre distance, less only the drift part of a known line's width
            if min((abs(fk - f) - max(b - 2 * df, 0.0) for f, b in known), default=np.inf) < max(min_sep_hz, 2 * df):
                continue
            st = line_level(spec, fk, bw, known + [(j * fc, bw) for j in ks_all if j != k])
            if not np.isfinite(st["floor"]).all():
                continue
            p = max(st["p_value"], persistence_p_value(spec, fk, bw, st["floor"]))
            p_adj = min(1.0, p * n_tests)
            cands.append({"family_hz": fc, "harmonic": k, "freq_hz": fk, "level_db": [float(v) for v in
                                                                                     st["level_db"]],
                          "p_value_bonferroni": p_adj, "significant": bool(p_adj < alpha)})
            if p_adj < alpha:
                sig.append(k)
        if len(sig) < 3:   # a note and its octave (k, 2k) must not pass for a comb
            break
        combs.append(Comb(fundamental_hz=fc, harmonics=sig, candidates=cands))
        known += [(k * fc, bw) for k in sig]
        log.info("further hum comb at %.4f Hz, harmonics %s", fc, sig)
    return combs


def cut_db(freqs, before, after, f: float, *, half_width_hz: float = 1.0) -> float:
    """Deepest cut within +-half_width of ``f``: min over bins of after / min(before, floor), in dB,
    averaged over channels (the floor is the median 2-10 Hz away). 0 when nothing is dug out."""
    d = np.abs(freqs - f)
    w = d <= half_width_hz
    near = (d >= 2.0) & (d <= 10.0)
    if not w.any() or near.sum() < 4:
        return 0.0
    floor = np.median(before[near], axis=0)
    ref = np.minimum(before[w], floor)
    with np.errstate(divide="ignore", invalid="ignore"):
        cut = 10 * np.log10(np.maximum(after[w], 1e-300) / np.maximum(ref, 1e-300)).min(axis=0)
    return float(np.mean(cut))
