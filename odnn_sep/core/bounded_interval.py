"""Confidence intervals that respect a parameter's physical bounds (a rate > 0, a fraction in (0, 1)).

A Wald interval ``theta -+ z se`` is symmetric and can cross a bound: a cooling rate reported as
``h in [-5.7e-5, 5.7e-5]``. Here the interval is built on a transformed parameter that has no bound,
then mapped back, so it is asymmetric and never leaves the bounds:

- one finite bound ``lo`` (or ``hi``): ``u = log(theta - lo)`` (or ``log(hi - theta)``), with
  ``se_u = se / (theta - lo)`` by the delta method;
- two finite bounds: ``u = logit((theta - lo) / (hi - lo))``.

The transform is used only where it matters and is trustworthy:

- a Wald interval that stays inside the bounds is returned unchanged (it is then the usual, well
  calibrated answer, and the transformed one would differ from it only at second order);
- when the estimate is less than one standard error from a bound (``se_u > 1``), the data cannot
  separate the parameter from that bound: the log interval would stretch over orders of magnitude,
  so the answer is the Wald interval cut at the bound, whose end then *is* the bound (it is the
  profile of the local quadratic likelihood under the constraint). Callers can read that as
  "not separated from the bound".
"""
from __future__ import annotations

import math

import numpy as np

from odnn_sep.core.uncertainty import Z95

__all__ = ["bounded_interval"]

MAX_TRANSFORMED_SE = 1.0   # beyond this spread on the log scale, the bound itself is inside the interval


def bounded_interval(value, stderr, lo=-np.inf, hi=np.inf, *, z=Z95):
    """A ``z``-sigma interval of ``value`` inside ``[lo, hi]`` (transformed where a bound is near).

    Parameters
    ----------
    value : float
        Estimate.
    stderr : float
        Its standard error (already widened for the spread's degrees of freedom, if needed).
    lo, hi : float, optional
        Physical bounds of the parameter (infinite: none).
    z : float, optional
        Normal quantile (1.96 for 95 %).

    Returns
    -------
    (float, float)
        Lower and upper ends, always within ``[lo, hi]``.

    Examples
    --------
    A rate known to be positive, estimated at 1.0e-4 +- 0.7e-4: the Wald interval would cross 0.

    >>> lo, hi = bounded_interval(1.0e-4, 0.7e-4, 0.0)
    >>> round(lo, 7), round(hi, 6), lo > 0
    (2.54e-05, 0.000394, True)

    Far from the bound the Wald interval is kept; next to it the interval is cut at the bound.

    >>> [round(v, 4) for v in bounded_interval(5.0, 1.0, 0.0)]
    [3.04, 6.96]
    >>> bounded_interval(1.0e-7, 0.7e-4, 0.0)[0]
    0.0

    A fraction between 0 and 1 (logit):

    >>> [round(v, 4) for v in bounded_interval(0.95, 0.04, 0.0, 1.0)]
    [0.7848, 0.99]
    """
    v, se, lo, hi = float(value), abs(float(stderr)), float(lo), float(hi)
    a, b = v - z * se, v + z * se
    wald = (max(lo, a), min(hi, b))
    if not (np.isfinite(v) and np.isfinite(se)) or se == 0.0 or (lo <= a and b <= hi) or not lo < v < hi:
        return wald
    out = _transformed(v, se, lo, hi, z)
    return wald if out is None else out


def _transformed(v, se, lo, hi, z):
    """The logit (two bounds) or log (one bound) interval, or None when the estimate is too near a bound."""
    if np.isfinite(lo) and np.isfinite(hi):
        w = hi - lo
        x = (v - lo) / w
        den = w * x * (1.0 - x)
        if not den > 0.0 or se > MAX_TRANSFORMED_SE * den:   # on a bound to float precision, or too near
            return None
        su = se / den
        u = math.log(x / (1.0 - x))
        return lo + w * _expit(u - z * su), lo + w * _expit(u + z * su)
    d, sign, bound = (v - lo, 1.0, lo) if np.isfinite(lo) else (hi - v, -1.0, hi)
    if not d > 0.0 or se > MAX_TRANSFORMED_SE * d:
        return None
    su = se / d
    ends = sorted((bound + sign * d * math.exp(-z * su), bound + sign * d * math.exp(z * su)))
    return ends[0], ends[1]


def _expit(u):
    return 1.0 / (1.0 + math.exp(-u)) if u >= 0 else math.exp(u) / (1.0 + math.exp(u))
