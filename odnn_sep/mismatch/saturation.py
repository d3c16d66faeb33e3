"""Samples held at a rail of the sensor (clipping) are left out before anything is fitted.

A sensor or an ADC that saturates reports its rail value for every sample beyond it: the record's
largest (or smallest) value then repeats, flat, where the physics goes on. A model fitted through
those samples sees a flat stretch that no effect of the vocabulary describes, and the nearest one
(a second body, a drag law) gets named. The rule: the record's maximum (minimum) value, when taken by
at least ``MIN_RUN`` samples and by more than ``EXCESS`` times as many samples as an average value
of the record takes (so that the repeated levels of a coarse ADC are not read as a rail), is a rail;
the samples on it are left out and reported as a disturbance (``clipping``).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

MIN_RUN = 3
EXCESS = 2.0


@dataclass
class Saturation:
    """Where the record sits at a rail: the kept-sample mask and the rails found.

    Examples
    --------
    >>> s = Saturation(keep=np.array([False, True]), rails=[("upper", 5.0, 1)])
    >>> int(s.keep.sum()), s.rails[0][0]
    (1, 'upper')
    """

    keep: np.ndarray
    rails: list          # (side, value, samples)

    def entry(self, unit="") -> dict:
        """The disturbance entry of the report (see :func:`find_saturation` for an example)."""
        u = f" {unit}" if unit else ""
        parts = [f"{k} samples at the {side} rail {v:.6g}{u}" for side, v, k in self.rails]
        return {"effect": "clipping", "parameters": {side: float(v) for side, v, _ in self.rails},
                "interval95": {}, "score": None, "heldout_gain": None, "note": None,
                "count": int(sum(k for _, _, k in self.rails)),
                "rails": [[side, float(v), int(k)] for side, v, k in self.rails],
                "description": (f"the sensor saturates: {'; '.join(parts)} (the record's extreme value, repeated) "
                                f"were left out before any fit: a clipped stretch is not physics")}


def find_saturation(y) -> Saturation | None:
    """Samples at the record's maximum or minimum value when that value is a rail (module docstring).

    Parameters
    ----------
    y : ndarray
        The record.

    Returns
    -------
    Saturation or None
        None when no rail is found (or leaving the rail samples out would leave fewer than 10).

    Examples
    --------
    >>> y = np.minimum(np.linspace(10.0, 0.0, 50), 8.0)       # clipped at 8 for the first 10 samples
    >>> s = find_saturation(y)
    >>> s.rails, int((~s.keep).sum())
    ([('upper', 8.0, 10)], 10)
    >>> s.entry("degC")["description"][:60]
    'the sensor saturates: 10 samples at the upper rail 8 degC (t'
    >>> find_saturation(np.round(np.linspace(0.0, 1.0, 50), 1)) is None   # a coarse ADC, no rail
    True
    >>> tail = 1.2 + 0.5 * np.random.default_rng(3).normal(size=100)
    >>> flat = np.round(np.r_[np.linspace(30.0, 1.5, 40), tail])    # a coarse ADC on a curve that flattens
    >>> int(np.sum(flat == flat.min())), int(np.sum(flat == flat.min() + 1))   # its lowest level: no pile-up
    (11, 63)
    >>> find_saturation(flat) is None
    True
    """
    y = np.asarray(y, float)
    n = len(y)
    if n < 10 or not np.all(np.isfinite(y)):
        return None
    levels, counts = np.unique(y, return_counts=True)
    if len(levels) < 3:
        return None
    avg = n / len(levels)
    keep = np.ones(n, bool)
    rails = []
    for side, i, inward in (("upper", -1, -2), ("lower", 0, 1)):
        v = float(levels[i])
        on = y == v
        k = int(counts[i])
        if k >= MIN_RUN and k > EXCESS * avg and k > EXCESS * counts[inward]:
            keep &= ~on
            rails.append((side, v, k))
    if not rails or keep.sum() < 10:
        return None
    return Saturation(keep=keep, rails=rails)
