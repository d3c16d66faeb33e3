"""Notes on how a record was given, where the physics depends on it: the unit or the direction of its values.

Each looks at the record before any fit and returns a sentence for ``MismatchResult.notes`` (or
None): the verdict is left as the data give it, and the note says what to change when the record
was most likely given in another unit or sign than the preset's.
"""
from __future__ import annotations

import numpy as np


def record_notes(m, t, y) -> list:
    """Every note that applies to record ``(t, y)`` of model ``m``.

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 10, 200)
    >>> record_notes(make_model("pendulum"), t, 30 * np.cos(3 * t))[0].split(";")[0]
    'angles up to 30 look like degrees'
    >>> record_notes(make_model("pendulum"), t, 0.5 * np.cos(3 * t))
    []
    """
    out = [_small_values_note(m, y), _angle_note(m, y), _fall_direction_note(m, t, y)]
    return [n for n in out if n]


# Mechanical records whose values are all under this (metres for a motion of nanometres): the
# effects that grow with the motion are searched with steps sized for values near 1 and are missed
# (a cubic stiffness of an oscillator was missed at amplitudes of 1e-7, found at 1e-6). Single records
# are analysed in a unit that fits them (valuescale.py); joint series are not, and get this note.
SMALL_VALUES = 1e-5
SMALL_VALUE_FAMILIES = ("oscillator", "freefall")


def _small_values_note(m, y):
    """A note for a mechanical record in units far larger than its motion, or None."""
    top = float(np.max(np.abs(y))) if len(y) else 0.0
    if m.family not in SMALL_VALUE_FAMILIES or not 0 < top < SMALL_VALUES:
        return None
    return (f"every value of the record is under {SMALL_VALUES:g} (largest {top:.3g}): the effects that grow with "
            f"the motion (cubic stiffness, drag, friction) are searched with steps sized for values near 1 and "
            f"can be missed at this scale; give the record in smaller units (mm, um or nm)")


def _angle_note(m, y):
    """A note for a pendulum angle record that looks like degrees, or None."""
    if m.family != "pendulum" or float(m.start.get("L", 0.0)) > 0:
        return None     # with L the record is a tangential acceleration
    from odnn_sep.mismatch.units import degrees_warning
    return degrees_warning(y)


def _fall_direction_note(m, t, y):
    """A note for a free-fall record that curves upwards (a distance fallen, positive down), or None.

    Gravity bends a height downwards (h0 - g t^2 / 2) whatever the throw; a record whose t^2 term is
    positive beyond 5 standard errors was measured the other way, and the preset's g sits at 0.
    """
    if m.family != "freefall" or np.ndim(t) != 1 or len(y) < 5:
        return None
    u = (t - t[0]) / max(float(np.ptp(t)), 1e-300)
    X = np.stack([np.ones_like(u), u, u * u], axis=1)
    coef, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ coef
    cov = np.linalg.pinv(X.T @ X) * float(r @ r) / max(len(y) - 3, 1)
    if not coef[2] > 5 * np.sqrt(max(cov[2, 2], 0.0)):
        return None
    return ("the record curves upwards (its t^2 term is positive): it looks like the distance fallen, positive "
            "down, while the free-fall preset describes a height, h0 - g t^2 / 2; analyse the negated column "
            "(h0 - d) for gravity and drag")


