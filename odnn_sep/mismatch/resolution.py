"""The smallest residual level the mismatch finder reads as information about a record.

A record that a model reproduces exactly (a simulation compared with a simulation, a curve typed
from a formula, a constant column) has no noise: its residual is integration error (the ODEs are
integrated to a relative 1e-9) and floating-point rounding. Read as noise, that gives BIC drops of
ten thousands and held-out gains of 1e300 to effects that change nothing (an effect "named" with
its coefficient at 0, a step of 3e-15 absorbed as a disturbance). Every sum of squares the finder
compares therefore carries ``RESOLUTION_REL * max|y|`` per sample: far under the noise of any
measured record (a 24-bit converter's step is 6e-8 of its full scale), above the numerics.
"""
from __future__ import annotations

import numpy as np

# Relative to the largest absolute value of the record: 10 x the ODE integration tolerance.
RESOLUTION_REL = 1e-8


def resolution(y) -> float:
    """The record's numerical resolution: ``RESOLUTION_REL`` times its largest finite absolute value.

    Parameters
    ----------
    y : array_like
        The record (any shape).

    Returns
    -------
    float
        A level in the record's units (0 for an empty or all-zero record).

    Examples
    --------
    >>> resolution([20.0, 80.0, -5.0])
    8e-07
    >>> resolution([])
    0.0
    """
    a = np.abs(np.asarray(y, float))
    a = a[np.isfinite(a)]
    return float(RESOLUTION_REL * a.max()) if a.size else 0.0
