"""Spikes of a record, or of each series of a joint fit on its own, and their entries in the report.

Why per series: the series of a joint fit are stacked on one axis (:mod:`odnn_sep.mismatch.joint`),
but each comes from its own sensor. On the stacked axis the noise level a spike is measured against
is pooled over every series, so a quiet thermometer's spikes hide under a noisy one's spread; the 5 %
limit counts the whole stack, so one series full of outliers (heavy-tailed noise, not spikes) is
repaired as if it were spikes; and a series' first samples are compared with the end of the one
before. Each series is therefore repaired exactly as a single record would be
(:func:`~odnn_sep.mismatch.spikes.find_spikes` on its own slice of the calibrated residual) and its
spikes are listed under the disturbances with its name and its own times.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.mismatch.spikes import Spikes, find_spikes


@dataclass
class SeriesSpikes:
    """Spikes of several stacked series: ``parts`` = [(series name, first row, its Spikes)], rows local.

    Examples
    --------
    >>> a = Spikes(index=np.array([1]), excess=np.array([2.0]), sigma=0.1)
    >>> s = SeriesSpikes([("mug2", 3, a)])
    >>> s.count, s.index.tolist(), s.repaired(np.zeros(6)).tolist()
    (1, [4], [0.0, 0.0, 0.0, 0.0, -2.0, 0.0])
    """

    parts: list

    @property
    def index(self) -> np.ndarray:
        return np.concatenate([start + s.index for _, start, s in self.parts])

    @property
    def excess(self) -> np.ndarray:
        return np.concatenate([s.excess for _, _, s in self.parts])

    @property
    def count(self) -> int:
        return int(sum(s.count for _, _, s in self.parts))

    def repaired(self, y: np.ndarray) -> np.ndarray:
        """A copy of ``y`` with every series' flagged samples repaired."""
        out = np.array(y, dtype=float, copy=True)
        out[self.index] -= self.excess
        return out


def record_spikes(model, t, residual, floor=0.0):
    """The spikes of a record (:func:`find_spikes`), or of each series of a joint model on its own.

    Parameters
    ----------
    model : Model
        The calibrated model (a joint model's preset knows its series).
    t : ndarray
        Time stamps (the stacked axis of a joint model) or 2-D coordinates.
    residual : ndarray
        The calibrated residual.
    floor : float, optional
        The record's resolution (see :func:`find_spikes`).

    Returns
    -------
    Spikes, SeriesSpikes or None

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> rng = np.random.default_rng(0); t = np.linspace(0, 10, 100); r = 0.01 * rng.normal(size=100)
    >>> r[40] += 0.5
    >>> record_spikes(make_model("cooling"), t, r).index.tolist()
    [40]
    """
    jp = getattr(model, "preset", None)
    if not hasattr(jp, "series_times"):
        return find_spikes(t, residual, floor)
    parts, start = [], 0
    for name, ts in zip(jp.series_names, jp.series_times, strict=True):
        s = find_spikes(ts, residual[start:start + len(ts)], floor)
        if s is not None:
            parts.append((name, start, s))
        start += len(ts)
    return SeriesSpikes(parts) if parts else None


def spikes_entries(spikes, model, t, unit):
    """The disturbance entries of the repaired spikes: one for a record, one per series with spikes.

    Each gives the count, where (the first 20, in the series' own times) and how large, and a plain
    sentence.

    Parameters
    ----------
    spikes : Spikes or SeriesSpikes
        From :func:`record_spikes`.
    model : Model
        The model (a joint model's preset gives each series' times).
    t : ndarray
        The analysed time stamps.
    unit : str
        Unit of the data.

    Returns
    -------
    list of dict

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> s = Spikes(index=np.array([2]), excess=np.array([0.5]), sigma=0.01)
    >>> e = spikes_entries(s, make_model("cooling"), np.arange(5.0), "degC")[0]
    >>> e["effect"], e["parameters"], e["at"]
    ('spikes', {'count': 1}, [2.0])
    """
    if isinstance(spikes, Spikes):
        return [_entry(spikes, np.asarray(t)[spikes.index[:20]], unit)]
    out = []
    for name, _, s in spikes.parts:
        ts = model.preset.series_times[model.preset.series_names.index(name)]
        e = _entry(s, ts[s.index[:20]], unit)
        e["series"] = name
        e["description"] = f"series {name}: {e['description']}"
        out.append(e)
    return out


def _entry(spikes, where, unit):
    return {"effect": "spikes", "parameters": {"count": spikes.count}, "interval95": {},
            "score": None, "heldout_gain": None, "note": None,
            "at": np.asarray(where).tolist(), "excess": [float(e) for e in spikes.excess[:20]],
            "largest": float(np.max(np.abs(spikes.excess))) if spikes.count else 0.0,
            "noise_level": float(spikes.sigma), "description": spikes.description(unit)}
