"""Hum shared by many channels, removed through its spatial components (in the spirit of ZapLine).

ZapLine (de Cheveigné 2020; meegkit ``dss_line``) finds, by denoising source separation (DSS), the
spatial components whose power is most concentrated at the line frequencies, and projects them out
of the data above the line frequency, removing their whole time course (brain signal in those
directions included). Here the same components are found, but inside them only the hum itself is
removed:

1. DSS: the covariance of the data in narrow bands around the candidate harmonics (k x 50 and
   k x 60 Hz, or the given fundamental) against the covariance over the bands and their flanks,
   after whitening (rank deficient data such as average-referenced EEG is fine). Each component's
   score is the fraction of its local power that sits in the bands (unlike ZapLine's total-power
   reference, this does not depend on how much low-frequency EEG the data hold).
2. Components whose score stands out (``ODDS_RATIO``, see :func:`n_hum_components`; at most
   ``MAX_COMPONENTS``) are handed to the single-channel engine together: one tracked fundamental,
   phase-locked line test, block-wise amplitude/phase fit in each component. Their summed
   power at the line is far above any single channel's, so weak hum is detected and tracked.
   Where a line stays more than ``REFIT_LEVEL_DB`` above its floor (line noise whose amplitude
   changes within seconds), the components are fitted again with ``SHORT_BLOCK_S`` blocks.
3. The fitted hum is mapped back to the channels line by line, with a complex gain per channel and
   component (least squares of the channels' DFT bins on the components' bins in the line's band,
   over windowed segments), and subtracted: off the lines the data are untouched.
4. Residual check: channels whose lines still stand out against their flanks go through the
   engine on their own at the fundamental found (hum outside the component subspace, e.g. one
   bad electrode); when the components show no hum, every channel does.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio.channel_engine import clean_columns
from odnn_sep.core.linalg import solve

ODDS_RATIO = 4.0         # a hum component's band/flank power ratio is >= 4x the median component's (dev seeds)
MAX_COMPONENTS = 6
SEGMENT_S = 16.0         # covariance segments (0.0625 Hz bins)
FLANK_HZ = 3.0           # reference band on each side of a line band: the local floor
BAND_HZ = 0.4            # half-width of each band: BAND_HZ + BAND_REL * frequency (drift grows with k)
BAND_REL = 0.004
MAX_HARMONIC = 40
SHORT_BLOCK_S = 0.5      # block length (s) of the components' refit when the hum changes faster than 'auto' follows
REFIT_LEVEL_DB = 6.0     # ... i.e. when a line stays this far above its floor in a component (dev seeds)


def line_bands(sfreq: float, mains, harmonics="auto", max_hz=None) -> list[tuple[float, float]]:
    """Frequency bands (Hz) around the candidate hum lines, below 0.95 x Nyquist.

    Parameters
    ----------
    sfreq : float
        Sampling frequency (Hz).
    mains : 'auto' or float
        ``'auto'`` (any string): both the 50 and 60 Hz families; else that fundamental.
    harmonics : 'auto', int, str of digits or sequence of int
        Harmonics to cover (``'auto'``: up to :data:`MAX_HARMONIC`).
    max_hz : float, optional
        Highest frequency covered.

    Returns
    -------
    list of (float, float)
        Sorted ``(low, high)`` bands, half-width ``BAND_HZ + BAND_REL f``.

    Examples
    --------
    >>> [(round(lo, 2), round(hi, 2)) for lo, hi in line_bands(250.0, 50)]
    [(49.4, 50.6), (99.2, 100.8)]
    """
    auto = isinstance(mains, str)
    nominals = (50.0, 60.0) if auto else (float(mains),)
    top = min(0.95 * sfreq / 2, max_hz if max_hz is not None else np.inf)
    if isinstance(harmonics, (list, tuple)):
        ks = [int(k) for k in harmonics]
    elif isinstance(harmonics, (int, np.integer)) or (isinstance(harmonics, str) and harmonics.isdigit()):
        ks = list(range(1, int(harmonics) + 1))
    else:
        ks = list(range(1, MAX_HARMONIC + 1))
    bands = []
    for f0 in nominals:
        for k in ks:
            f = k * f0
            hw = BAND_HZ + BAND_REL * f
            if f + hw < top:
                bands.append((f - hw, f + hw))
    return sorted(bands)


def band_covariances(x: np.ndarray, sfreq: float, bands) -> tuple[np.ndarray, np.ndarray]:
    """Covariances of the channels ``x`` (n_channels, n_times) around the lines: ``c_local`` over each
    band and its flanks (``FLANK_HZ`` on each side), ``c_band`` over the bands alone (Parseval on
    Hann-windowed, half-overlapping segments; one segment in memory at a time).

    Parameters
    ----------
    x : (n_channels, n_times) array
        The channels.
    sfreq : float
        Sampling frequency (Hz).
    bands : sequence of (float, float)
        Line bands (Hz), as :func:`line_bands` gives them.

    Returns
    -------
    c_local, c_band : (n_channels, n_channels) arrays

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> x = rng.standard_normal((4, t.size)) + np.outer([2.0, 1.0, -1.5, 0.5], np.cos(2 * np.pi * 50 * t))
    >>> c_local, c_band = band_covariances(x, sfreq, line_bands(sfreq, 50))
    >>> c_local.shape, bool(np.all(np.diag(c_band) < np.diag(c_local)))
    ((4, 4), True)
    """
    C, N = x.shape
    seg = int(min(N, max(16, round(SEGMENT_S * sfreq))))
    f = np.fft.rfftfreq(seg, 1.0 / sfreq)
    in_band, local = np.zeros(f.size, bool), np.zeros(f.size, bool)
    for lo, hi in bands:
        in_band |= (f >= lo) & (f <= hi)
        local |= (f >= lo - FLANK_HZ) & (f <= hi + FLANK_HZ)
    win = np.hanning(seg)
    c_local, c_band = np.zeros((C, C)), np.zeros((C, C))
    mean = x.mean(axis=1, keepdims=True)
    for s in list(range(0, N - seg + 1, seg // 2)) or [0]:
        F = np.fft.rfft((x[:, s: s + seg] - mean) * win, axis=1)
        Fl, Fb = F[:, local], F[:, in_band]
        c_local += (Fl @ Fl.conj().T).real
        c_band += (Fb @ Fb.conj().T).real
    return c_local, c_band


def hum_components(c_total: np.ndarray, c_band: np.ndarray, rel_tol: float = 1e-10):
    """DSS: spatial filters ``W`` (n_channels, m) maximising in-band over total power, best first,
    with their scores (the in-band fraction, 0..1). Directions with no power are dropped.

    Parameters
    ----------
    c_total : (C, C) array
        Reference covariance (bands and flanks).
    c_band : (C, C) array
        In-band covariance.
    rel_tol : float
        Eigenvalues of ``c_total`` below this fraction of the largest are dropped.

    Returns
    -------
    scores : (m,) array
    W : (C, m) array

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> x = rng.standard_normal((4, t.size)) + np.outer([2.0, 1.0, -1.5, 0.5], np.cos(2 * np.pi * 50 * t))
    >>> scores, W = hum_components(*band_covariances(x, sfreq, line_bands(sfreq, 50)))
    >>> scores.round(2).tolist(), W.shape
    ([0.97, 0.2, 0.17, 0.15], (4, 4))
    """
    d, V = np.linalg.eigh(c_total)
    keep = d > rel_tol * max(d.max(), np.finfo(float).tiny)
    P = V[:, keep] / np.sqrt(d[keep])
    s, U = np.linalg.eigh(P.T @ c_band @ P)
    order = np.argsort(s)[::-1]
    return np.clip(s[order], 0.0, 1.0), P @ U[:, order]


def n_hum_components(scores: np.ndarray, odds_ratio: float | None = None) -> int:
    """How many leading components stand out as hum: their band-to-flank power ratio
    ``s / (1 - s)`` is at least ``odds_ratio`` (default ODDS_RATIO) times the median component's (a
    smooth spectrum gives every component about the same ratio, the bands' share of the width).

    Parameters
    ----------
    scores : (m,) array
        Component scores of :func:`hum_components`, best first.
    odds_ratio : float, optional
        Threshold over the median component's odds.

    Returns
    -------
    int
        At most ``MAX_COMPONENTS`` and ``m - 1``.

    Examples
    --------
    >>> n_hum_components(np.array([0.97, 0.2, 0.17, 0.15])), n_hum_components(np.array([0.1, 0.1, 0.1]))
    (1, 0)
    """
    if scores.size < 2:
        return 0
    odds = scores / np.maximum(1.0 - scores, 1e-12)
    strong = odds >= (ODDS_RATIO if odds_ratio is None else odds_ratio) * float(np.median(odds))
    n = int(np.argmin(strong)) if not strong.all() else strong.size
    return min(n, MAX_COMPONENTS, scores.size - 1)


def fit_components(S: np.ndarray, sfreq: float, opts: dict):
    """The engine on the component time courses ``S`` (r, n_times) together. Where a line stays more
    than REFIT_LEVEL_DB above its floor after the engine's own block length (real line noise often
    changes within seconds), the components are fitted again with SHORT_BLOCK_S blocks: the notch
    widens to about 1/SHORT_BLOCK_S Hz but follows the changes. Returns (hum (n_times, r), summary).

    Parameters
    ----------
    S : (r, n_times) array
        Component time courses.
    sfreq : float
        Sampling frequency (Hz).
    opts : dict
        Engine options.

    Returns
    -------
    hum : (n_times, r) array
    summary : dict
        As :func:`~odnn_sep.audio.channel_engine.clean_columns`, with the ``block_s`` used.

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq
    >>> S = np.random.default_rng(0).standard_normal((1, t.size)) + 3 * np.cos(2 * np.pi * 50 * t)
    >>> hum, summary = fit_components(S, sfreq, {})
    >>> hum.shape, summary["harmonics"], summary["block_s"]
    ((5000, 1), [1], 'auto')
    """
    hum_s, comp = clean_columns(S.T, sfreq, opts)
    comp["block_s"] = opts.get("block_s", "auto")
    auto = str(comp["block_s"]).strip().lower() == "auto"
    left = [v for line in comp["level_after_db"] for v in np.ravel(line) if v is not None and np.isfinite(v)]
    if auto and comp["line_freqs_hz"] and max(left, default=-np.inf) > REFIT_LEVEL_DB:
        hum_short, comp_short = clean_columns(S.T, sfreq, dict(opts, block_s=SHORT_BLOCK_S))
        if comp_short["line_freqs_hz"]:
            hum_s, comp = hum_short, dict(comp_short, block_s=SHORT_BLOCK_S)
    return hum_s, comp


def line_patterns(x: np.ndarray, S: np.ndarray, sfreq: float, line_hz: float) -> np.ndarray:
    """Complex pattern (n_channels, r) of each component at one line: least squares of the channels'
    DFT bins on the components' bins within the line's band, over Hann-windowed half-overlapping
    segments. Windowed segments keep a transient (a filter's start-up, a step) local instead of
    letting its in-band content weigh on the whole fit; complex patterns let every channel have
    its own phase.

    Parameters
    ----------
    x : (n_channels, n_times) array
        The channels.
    S : (r, n_times) array
        Component time courses.
    sfreq : float
        Sampling frequency (Hz).
    line_hz : float
        The line (Hz).

    Returns
    -------
    (n_channels, r) complex array

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> s = np.cos(2 * np.pi * 50 * t)
    >>> x = 0.1 * rng.standard_normal((3, t.size)) + np.outer([2.0, 1.0, -1.5], s)
    >>> A = line_patterns(x, s[None, :], sfreq, 50.0)
    >>> A.shape, A[:, 0].real.round(1).tolist()
    ((3, 1), [2.0, 1.0, -1.5])
    """
    C, N = x.shape
    seg = int(min(N, max(16, round(SEGMENT_S * sfreq))))
    f = np.fft.rfftfreq(seg, 1.0 / sfreq)
    band = np.abs(f - line_hz) <= BAND_HZ + BAND_REL * line_hz
    win = np.hanning(seg)
    rows_s, rows_x = [], []
    for s in list(range(0, N - seg + 1, seg // 2)) or [0]:
        rows_s.append(np.fft.rfft(S[:, s: s + seg] * win, axis=1)[:, band].T)
        rows_x.append(np.fft.rfft(x[:, s: s + seg] * win, axis=1)[:, band].T)
    return solve(np.vstack(rows_s), np.vstack(rows_x)).T


def channel_hum(x: np.ndarray, S: np.ndarray, hum_s: np.ndarray, line_freqs, sfreq: float) -> np.ndarray:
    """The channels' hum from the components' fitted hum ``hum_s`` (r, n_times): line by line, the
    analytic signal of the components' hum near the line times each channel's complex pattern.

    Parameters
    ----------
    x : (n_channels, n_times) array
        The channels.
    S : (r, n_times) array
        Component time courses.
    hum_s : (r, n_times) array
        The components' fitted hum.
    line_freqs : sequence of float
        Lines (Hz) in ``hum_s``.
    sfreq : float
        Sampling frequency (Hz).

    Returns
    -------
    (n_channels, n_times) array

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> s = np.cos(2 * np.pi * 50 * t)
    >>> x = 0.1 * rng.standard_normal((3, t.size)) + np.outer([2.0, 1.0, -1.5], s)
    >>> h = channel_hum(x, s[None, :], s[None, :], [50.0], sfreq)
    >>> h.shape, bool(np.abs(h - np.outer([2.0, 1.0, -1.5], s)).max() < 0.05)
    ((3, 5000), True)
    """
    N = x.shape[1]
    H = np.fft.rfft(hum_s, axis=1)
    f = np.fft.rfftfreq(N, 1.0 / sfreq)
    lines = np.asarray(line_freqs, float)
    nearest = np.argmin(np.abs(f[:, None] - lines[None, :]), axis=1)   # each bin to its closest line
    out = np.zeros_like(x)
    for j, fl in enumerate(lines):
        Hj = np.where(nearest == j, H, 0)
        z = np.fft.irfft(Hj, n=N, axis=1) + 1j * np.fft.irfft(-1j * Hj, n=N, axis=1)   # analytic signal
        A = line_patterns(x, S, sfreq, fl)
        out += A.real @ z.real      # Re(A z), without a complex (n_channels, n_times) temporary
        out -= A.imag @ z.imag
    return out


def residual_channels(x: np.ndarray, sfreq: float, line_freqs) -> np.ndarray:
    """Channels whose power in the bands around ``line_freqs`` still stands out against the flanks
    (``ODDS_RATIO`` times what a smooth spectrum gives): the ones the residual check refits.

    Parameters
    ----------
    x : (n_channels, n_times) array
        The channels (after the components' hum is removed).
    sfreq : float
        Sampling frequency (Hz).
    line_freqs : sequence of float
        Lines (Hz).

    Returns
    -------
    int array
        Channel indices.

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> x = rng.standard_normal((3, t.size)); x[1] += np.cos(2 * np.pi * 50 * t)
    >>> residual_channels(x, sfreq, [50.0]).tolist()
    [1]
    """
    bands = [(fl - BAND_HZ - BAND_REL * fl, fl + BAND_HZ + BAND_REL * fl) for fl in line_freqs]
    c_local, c_band = band_covariances(x, sfreq, bands)
    band, local = np.diag(c_band), np.diag(c_local)
    width_band = sum(hi - lo for lo, hi in bands)
    smooth_odds = width_band / (2 * FLANK_HZ * len(bands))
    odds = band / np.maximum(local - band, np.finfo(float).tiny)
    return np.flatnonzero(odds >= ODDS_RATIO * smooth_odds)


def spatial_hum(x: np.ndarray, sfreq: float, opts: dict):
    """The hum in channels ``x`` (n_channels, n_times) found through its spatial components.

    Parameters
    ----------
    x : (n_channels, n_times) array
        The picked channels, float64.
    sfreq : float
        Sampling frequency (Hz).
    opts : dict
        Engine options (``mains``, ``harmonics``, ``max_hz``, ...).

    Returns
    -------
    hum : ndarray, shape of ``x``
    spatial : dict
        ``scores`` of all components, ``n_components`` used, what the engine found in them
        (``components``), the channels the residual check refitted.
    channels : list of dict
        Per channel: the lines removed through the components (``spatial_harmonics``) and by the
        residual check (as in channel_engine.clean_columns; empty where it was not needed).

    Examples
    --------
    >>> sfreq = 250.0; t = np.arange(5000) / sfreq; rng = np.random.default_rng(0)
    >>> x = rng.standard_normal((4, t.size)) + np.outer([2.0, 1.0, -1.5, 0.5], np.cos(2 * np.pi * 50 * t))
    >>> hum, spatial, channels = spatial_hum(x, sfreq, {})
    >>> hum.shape, spatial["n_components"], spatial["components"]["harmonics"], spatial["residual_refit"]
    ((4, 5000), 1, [1], [])
    """
    bands = line_bands(sfreq, opts.get("mains", "auto"), opts.get("harmonics", "auto"), opts.get("max_hz"))
    scores, W = hum_components(*band_covariances(x, sfreq, bands))
    r = n_hum_components(scores)
    hum = np.zeros_like(x)
    comp = {"harmonics": [], "mains_hz": None, "line_freqs_hz": [], "tones_hz": []}
    if r:
        S = W[:, :r].T @ x                                   # component time courses (r, n_times)
        hum_s, comp = fit_components(S, sfreq, opts)          # the engine decides which lines are hum
        if comp["line_freqs_hz"]:
            hum = channel_hum(x, S, hum_s.T, comp["line_freqs_hz"], sfreq)
    resid_opts = dict(opts)
    if comp["mains_hz"] is not None:
        resid_opts["mains"] = comp["mains_hz"]
        refit = residual_channels(x - hum, sfreq, comp["line_freqs_hz"])
    else:   # nothing shared: every channel on its own
        refit = np.arange(x.shape[0])
    channels = [{"mains_hz": None, "nominal_hz": None, "harmonics": [], "tones_hz": [], "line_freqs_hz": [],
                 "level_before_db": [], "level_after_db": [], "refit": False,
                 "spatial_harmonics": list(comp["harmonics"])} for _ in range(x.shape[0])]
    for c in refit:
        h, summary = clean_columns(x[c] - hum[c], sfreq, resid_opts)
        hum[c] += h
        channels[c].update(summary, refit=True)
    spatial = {"scores": scores.tolist(), "n_components": r, "components": comp,
               "bands_hz": [list(b) for b in bands], "residual_refit": refit.tolist()}
    return hum, spatial, channels
