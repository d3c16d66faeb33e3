"""Where the calibrated model and the data disagree: time windows, frequency bands, 2D regions.

Each location comes with a proper test against the noise level, never a per-case threshold:

- time windows / regions: the residual energy of a window divided by sigma^2 is chi-square with
  (about) as many degrees of freedom as samples under "only noise left"; windows are kept under
  Benjamini-Hochberg false-discovery control at ``alpha``.
- frequency bands: under white noise each periodogram ordinate divided by its expectation is
  exponential(1); bins are kept with a Bonferroni correction over all bins, then merged into bands.

sigma comes from first differences (robust to slow structure) capped by the median window energy
(robust to structure near the Nyquist frequency, which inflates differences).
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.spectrum import spectrum


def _chi2():
    # imported on use: ``odnn-sep`` imports this package for every subcommand (and ``--help``)
    from scipy import stats

    return stats.chi2


def noise_sigma(residual) -> float:
    """Robust white-noise level of a 1-D residual.

    Parameters
    ----------
    residual : array_like
        The residual.

    Returns
    -------
    float
        Standard deviation of its white-noise part.

    Examples
    --------
    >>> import numpy as np
    >>> round(noise_sigma(np.random.default_rng(0).normal(0, 0.5, 2000)), 2)
    0.5
    """
    r = np.asarray(residual, float)
    d = np.diff(r)
    s_diff = 1.4826 * np.median(np.abs(d - np.median(d))) / np.sqrt(2.0)
    nw = max(4, min(40, len(r) // 25))
    chunks = np.array_split(r, nw)
    ms = np.array([np.mean(c ** 2) for c in chunks])
    # median of chi2_m/m is a bit below 1; correct with the median of the chi2 for the window size
    m = len(r) / nw
    s_win = np.sqrt(np.median(ms) / (_chi2().median(m) / m))
    if not (np.isfinite(s_diff) and s_diff > 0):
        return float(s_win if np.isfinite(s_win) and s_win > 0 else np.std(r) + 1e-300)
    # differences are exact for white noise; fall back to window energies only when structure near
    # the Nyquist frequency clearly inflates them
    return float(s_win if s_win < 0.7 * s_diff else s_diff)


def _bh(pvals, alpha):
    p = np.asarray(pvals)
    order = np.argsort(p)
    thresh = alpha * (np.arange(1, len(p) + 1)) / len(p)
    passed = p[order] <= thresh
    keep = np.zeros(len(p), bool)
    if passed.any():
        last = np.max(np.flatnonzero(passed))
        keep[order[: last + 1]] = True
    return keep


def locate_time(t, residual, *, sigma=None, n_windows=None, alpha=0.05, dof_fraction=1.0):
    """Time windows whose residual energy exceeds the noise (BH-controlled). Returns a list of dicts.

    Parameters
    ----------
    t, residual : ndarray
        Sample times and residual.
    sigma : float, optional
        Noise level (default: :func:`noise_sigma`).
    n_windows : int, optional
        Number of windows (default: n / 50, between 4 and 20).
    alpha : float, optional
        False-discovery rate.
    dof_fraction : float, optional
        Degrees of freedom per sample (below 1 after a fit).

    Returns
    -------
    list of dict
        Merged runs of flagged windows: ``kind``, ``start``, ``end``, ``rms_over_noise``, ``p_value``.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> t = np.linspace(0, 10, 1000); r = rng.normal(0, 1, 1000); r[400:500] += 3.0
    >>> [(round(w["start"], 1), round(w["end"], 1)) for w in locate_time(t, r, sigma=1.0)]
    [(4.0, 5.0)]
    """
    r = np.asarray(residual, float)
    n = len(r)
    sigma = noise_sigma(r) if sigma is None else sigma
    nw = n_windows or int(np.clip(n // 50, 4, 20))
    edges = np.linspace(0, n, nw + 1).astype(int)
    pv, chi, ratio = [], [], []
    for a, b in zip(edges[:-1], edges[1:], strict=True):
        m = b - a
        c = float(np.sum(r[a:b] ** 2) / sigma ** 2)
        dof = max(m * dof_fraction, 1.0)
        pv.append(float(_chi2().sf(c, dof)))
        chi.append(c)
        ratio.append(float(np.sqrt(c / m)))
    keep = _bh(pv, alpha)
    out = []
    i = 0
    while i < nw:
        if not keep[i]:
            i += 1
            continue
        j = i
        while j + 1 < nw and keep[j + 1]:
            j += 1
        a, b = edges[i], edges[j + 1] - 1
        out.append({"kind": "time", "start": float(t[a]), "end": float(t[b]),
                    "rms_over_noise": float(np.sqrt(np.sum(r[a:b + 1] ** 2) / (b + 1 - a)) / sigma),
                    "p_value": float(min(pv[i:j + 1]))})
        i = j + 1
    return out


def locate_frequency(t, residual, *, sigma=None, alpha=0.05, max_bands=5):
    """Frequency bands where the residual periodogram exceeds white noise (Bonferroni over bins).

    Parameters
    ----------
    t, residual : ndarray
        Sample times (s) and residual.
    sigma : float, optional
        Noise level (default: :func:`noise_sigma`).
    alpha : float, optional
        Family-wise false-alarm rate.
    max_bands : int, optional
        Most bands returned, strongest first.

    Returns
    -------
    list of dict
        ``kind``, ``lo_hz``, ``hi_hz``, ``peak_hz``, ``power_over_noise``, ``p_value``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(1000) / 100.0
    >>> r = np.random.default_rng(1).normal(0, 1, 1000) + 0.5 * np.sin(2 * np.pi * 5 * t)
    >>> [round(b["peak_hz"], 2) for b in locate_frequency(t, r, sigma=1.0)]
    [5.0]
    """
    r = np.asarray(residual, float)
    n = len(r)
    sigma = noise_sigma(r) if sigma is None else sigma
    freqs, X = spectrum(t, r)
    spec = np.abs(X) ** 2 / (n * sigma ** 2)   # exp(1) per interior bin under white noise
    interior = np.arange(1, len(spec) - (1 if n % 2 == 0 else 0))
    if len(interior) == 0:
        return []
    pbin = np.exp(-spec[interior])
    flagged = pbin < alpha / len(interior)
    bands = []
    i = 0
    while i < len(interior):
        if not flagged[i]:
            i += 1
            continue
        j = i
        while j + 1 < len(interior) and flagged[j + 1]:
            j += 1
        sl = interior[i:j + 1]
        peak = sl[int(np.argmax(spec[sl]))]
        bands.append({"kind": "frequency", "lo_hz": float(freqs[sl[0]]), "hi_hz": float(freqs[sl[-1]]),
                      "peak_hz": float(freqs[peak]), "power_over_noise": float(spec[peak]),
                      "p_value": float(min(1.0, np.exp(-spec[peak]) * len(interior)))})
        i = j + 1
    bands.sort(key=lambda b: -b["power_over_noise"])
    return bands[:max_bands]


def locate_regions(xy, residual, *, sigma=None, tiles=4, alpha=0.05):
    """Rectangular tiles of a 2D field whose residual energy exceeds the noise (BH-controlled).

    Parameters
    ----------
    xy : ndarray, shape (n, 2)
        Point coordinates.
    residual : ndarray, shape (n,)
        The residual.
    sigma : float, optional
        Noise level (default: :func:`noise_sigma`).
    tiles : int, optional
        Tiles per axis.
    alpha : float, optional
        False-discovery rate.

    Returns
    -------
    list of dict
        ``kind``, ``x``, ``y`` (tile edges), ``rms_over_noise``, ``p_value``; most significant first.

    Examples
    --------
    >>> import numpy as np
    >>> g = np.linspace(0, 1, 20); X, Y = np.meshgrid(g, g)
    >>> xy = np.column_stack([X.ravel(), Y.ravel()])
    >>> r = np.random.default_rng(0).normal(0, 1, 400)
    >>> r[(xy[:, 0] < 0.25) & (xy[:, 1] < 0.25)] += 3.0   # a hot corner
    >>> [(w["x"], w["y"]) for w in locate_regions(xy, r, sigma=1.0)]
    [([0.0, 0.25], [0.0, 0.25])]
    """
    r = np.asarray(residual, float)
    sigma = noise_sigma(r) if sigma is None else sigma
    xe = np.linspace(xy[:, 0].min(), xy[:, 0].max(), tiles + 1)
    ye = np.linspace(xy[:, 1].min(), xy[:, 1].max(), tiles + 1)
    ix = np.clip(np.searchsorted(xe, xy[:, 0], side="right") - 1, 0, tiles - 1)
    iy = np.clip(np.searchsorted(ye, xy[:, 1], side="right") - 1, 0, tiles - 1)
    cells, pv = [], []
    for a in range(tiles):
        for b in range(tiles):
            sel = (ix == a) & (iy == b)
            m = int(sel.sum())
            if m == 0:
                continue
            c = float(np.sum(r[sel] ** 2) / sigma ** 2)
            cells.append((a, b, m, c))
            pv.append(float(_chi2().sf(c, m)))
    keep = _bh(pv, alpha)
    out = []
    for (a, b, m, c), p, k in zip(cells, pv, keep, strict=True):
        if k:
            out.append({"kind": "region", "x": [float(xe[a]), float(xe[a + 1])],
                        "y": [float(ye[b]), float(ye[b + 1])], "rms_over_noise": float(np.sqrt(c / m)),
                        "p_value": p})
    out.sort(key=lambda d: d["p_value"])
    return out


def locate(t: np.ndarray, residual: np.ndarray, *, sigma: float | None = None, alpha: float = 0.05):
    """All locations: time windows + frequency bands for 1-D data, regions for 2D fields.

    Parameters
    ----------
    t : ndarray, shape (n,) or (n, 2)
        Sample times, or 2D coordinates.
    residual : ndarray, shape (n,)
        The calibrated residual.
    sigma : float, optional
        Noise level (default: :func:`noise_sigma`).
    alpha : float, optional
        False-discovery (windows, regions) or family-wise (bands) rate.

    Returns
    -------
    list of dict
        :func:`locate_time` then :func:`locate_frequency` results, or :func:`locate_regions`'.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> t = np.linspace(0, 10, 1000); r = rng.normal(0, 1, 1000); r[400:500] += 3.0
    >>> wins = [w for w in locate(t, r) if w["kind"] == "time"]
    >>> round(min(wins, key=lambda w: w["p_value"])["start"], 1)
    4.0
    """
    t = np.asarray(t, float)
    if t.ndim == 2:
        return locate_regions(t, residual, sigma=sigma, alpha=alpha)
    sigma = noise_sigma(residual) if sigma is None else sigma
    return (locate_time(t, residual, sigma=sigma, alpha=alpha)
            + locate_frequency(t, residual, sigma=sigma, alpha=alpha))
