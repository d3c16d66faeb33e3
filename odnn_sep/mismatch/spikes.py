"""Isolated outliers (spikes) of a record: found on the calibrated model's residual and repaired
before any effect is tested (a Hampel filter on the residual, not on the data).

Why: least squares gives a spike of ten noise levels the weight of a hundred ordinary samples.
One or two per cent of such samples made up most of a record's residual sum of squares, so the
effects' BIC drops, held-out gains and intervals were decided by where the spikes fell (a heat
field with an extra source beside a given one was explained by moving the given source, with a
periodic pattern fitted to the spikes on top).

Why against the residual's neighbours: a missing effect is smooth on the scale of a few samples
(physics sampled finely enough to be fitted at all), so the local median of the residual follows
it, and a spike stands out against that median. The data themselves are not median-filtered: an
oscillation sampled twenty times a period would be flattened at its peaks.

Why repaired and not dropped: the analysis assumes equally spaced samples in several places (the
AR prewhitening of red noise, the spectra of the periodic candidates, the held-out blocks). A
spike's sample is given its neighbours' median residual on top of the fitted model, which is
what a Hampel filter gives; the record keeps its length and spacing.

What is flagged: samples that depart from both sides' medians (a field: its nearest points')
by more than ``Z_SPIKE`` robust standard deviations, measured against the spread of the
``LOCAL_SPREAD`` samples around them where that is larger, in runs of at most ``MAX_RUN`` samples
(a longer run is a transient, which may be physics), and only while they are at most
``MAX_SHARE`` of the record (more outliers than that is heavy-tailed noise or a wrong model, not
spikes: nothing is repaired then).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

Z_SPIKE = 5.0      # P(|z| > 5) ~ 6e-7 per Gaussian sample (bursts of content have heavier tails)
HALF_WINDOW = 3    # neighbours on each side of a sample of a series
NEIGHBOURS_2D = 8  # nearest neighbours of a point of a field
MAX_RUN = 2
LOCAL_SPREAD = 41  # samples of a series over which the spread around a sample is measured
MAX_SHARE = 0.05
MIN_SAMPLES = 20


@dataclass
class Spikes:
    """Flagged samples: their indices and the excess removed from each (data minus repaired).

    Examples
    --------
    >>> s = Spikes(index=np.array([2]), excess=np.array([1.5]), sigma=0.1)
    >>> s.count, s.repaired(np.zeros(4)).tolist()
    (1, [0.0, 0.0, -1.5, 0.0])
    """

    index: np.ndarray
    excess: np.ndarray
    sigma: float          # robust standard deviation of a sample's departure from its neighbours

    @property
    def count(self) -> int:
        return int(len(self.index))

    def repaired(self, y: np.ndarray) -> np.ndarray:
        """A copy of ``y`` with each flagged sample's excess removed."""
        out = np.array(y, dtype=float, copy=True)
        out[self.index] -= self.excess
        return out

    def description(self, unit: str = "") -> str:
        """One plain sentence for the report."""
        u = f" {unit}" if unit else ""
        big = float(np.max(np.abs(self.excess))) if self.count else 0.0
        return (f"{self.count} isolated outlier{'s' if self.count != 1 else ''} (spikes, up to {big:.3g}{u} from "
                f"their neighbours, {big / self.sigma:.0f} noise levels) replaced by the local median of the "
                f"residual before any effect was tested: single samples off their neighbours are read as "
                f"glitches of the sensor, not physics (--keep-spikes keeps them)")


def departures(t, r: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each sample's departure from its neighbours' residuals: ``(d, both)``.

    A series (``t`` 1-D, in order): ``d`` is the departure from the median of the ``HALF_WINDOW``
    samples on either side, and ``both`` the smaller in size of the departures from each side's
    own median, signed (zero where the two disagree in sign, or where a side has fewer than two
    samples: the record's first and last two samples). A step or the start of a fast transient
    departs from one side only. A field (``t`` of shape (n, 2)): the departure from the median of
    the ``NEIGHBOURS_2D`` nearest points, for both.

    Parameters
    ----------
    t : (n,) or (n, 2) array
        Time stamps or coordinates.
    r : (n,) array
        Residual.

    Returns
    -------
    (n,) array, (n,) array

    Examples
    --------
    >>> d, both = departures(np.arange(8.0), np.array([0.0, 0, 0, 9, 0, 0, 5, 5]))
    >>> d.tolist(), both.tolist()
    ([0.0, 0.0, 0.0, 9.0, -2.5, -5.0, 2.5, 5.0], [0.0, 0.0, 0.0, 9.0, 0.0, 0.0, 0.0, 0.0])
    """
    r = np.asarray(r, float)
    n = len(r)
    if np.ndim(t) == 2:
        from scipy.spatial import cKDTree
        k = min(NEIGHBOURS_2D + 1, n)
        _, idx = cKDTree(np.asarray(t, float)).query(t, k=k)
        d = r - np.median(r[idx[:, 1:]], axis=1)
        return d, d
    h = HALF_WINDOW
    pad = np.full(n + 2 * h, np.nan)
    pad[h:h + n] = r
    left = np.stack([pad[h + s: h + s + n] for s in range(-h, 0)], axis=1)
    right = np.stack([pad[h + s: h + s + n] for s in range(1, h + 1)], axis=1)
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)   # all-NaN sides at the ends
        d = r - np.nanmedian(np.concatenate([left, right], axis=1), axis=1)
        dl, dr = r - np.nanmedian(left, axis=1), r - np.nanmedian(right, axis=1)
    enough = (np.sum(np.isfinite(left), axis=1) >= 2) & (np.sum(np.isfinite(right), axis=1) >= 2)
    same = enough & (np.sign(dl) == np.sign(dr))
    both = np.where(same, np.sign(dl) * np.minimum(np.abs(np.nan_to_num(dl)), np.abs(np.nan_to_num(dr))), 0.0)
    return np.nan_to_num(d), both


def find_spikes(t, residual, floor=0.0) -> Spikes | None:
    """The isolated outliers of ``residual`` (see the module text), or None when there are none,
    too few samples to tell, or too many outliers to be spikes.

    Parameters
    ----------
    t : (n,) or (n, 2) array
        Time stamps or coordinates.
    residual : (n,) array
        The calibrated model's residual.
    floor : float, optional
        The record's resolution (:mod:`~odnn_sep.mismatch.resolution`): the spread is never taken
        under it, so the rounding of an exactly fitted record has no outliers.

    Returns
    -------
    Spikes or None

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.linspace(0, 10, 400); r = 0.1 * rng.normal(size=400) + 0.5 * np.sin(t)
    >>> find_spikes(t, r) is None                      # a smooth missing effect is not a spike
    True
    >>> r[[50, 200]] += [2.0, -1.5]
    >>> s = find_spikes(t, r); s.index.tolist(), bool(np.all(np.abs(s.excess - [2.0, -1.5]) < 0.3))
    ([50, 200], True)
    """
    r = np.asarray(residual, float)
    n = len(r)
    if n < MIN_SAMPLES or not np.all(np.isfinite(r)):
        return None
    d, both = departures(t, r)
    sigma = max(_spread(d), floor)
    if not sigma > 0:
        return None
    scale = np.full(n, sigma)
    if np.ndim(t) == 1:
        # bursts of content in the residual (a coupled channel's speech, a transient's ringing) have
        # a larger spread of their own: a sample is measured against the spread around it
        from scipy.ndimage import median_filter
        scale = np.maximum(scale, 1.4826 * median_filter(np.abs(d), size=LOCAL_SPREAD, mode="nearest"))
    flag = np.abs(both) > Z_SPIKE * scale
    if np.ndim(t) == 1:
        flag &= _short_runs(flag)
    if not flag.any() or flag.sum() > MAX_SHARE * n:
        return None
    idx = np.flatnonzero(flag)
    return Spikes(index=idx, excess=d[idx], sigma=sigma)


def _spread(d: np.ndarray) -> float:
    """Robust standard deviation of the departures: the median absolute deviation, or the spread
    of the central 96 % where that is larger (quantised data: most samples equal their
    neighbours' median, the deviation is near zero, and every quantisation step would stand out)."""
    mad = 1.4826 * float(np.median(np.abs(d - np.median(d))))
    lo, hi = np.quantile(d, [0.02, 0.98])
    core = d[(d >= lo) & (d <= hi)]
    trimmed = float(np.std(core)) / 0.88 if len(core) > 2 else 0.0   # 0.88: std of the central 96 % of a normal
    return max(mad, trimmed)


def _short_runs(flag: np.ndarray) -> np.ndarray:
    """True where ``flag`` is set in a run of at most ``MAX_RUN`` consecutive samples."""
    edges = np.diff(np.concatenate([[0], flag.astype(np.int8), [0]]))
    starts, ends = np.flatnonzero(edges == 1), np.flatnonzero(edges == -1)
    keep = np.zeros_like(flag)
    for a, b in zip(starts, ends, strict=True):
        if b - a <= MAX_RUN:
            keep[a:b] = True
    return keep
