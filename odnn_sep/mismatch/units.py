"""Units the physics depends on: temperatures of the cooling preset (vapour pressure and radiation are in
deg C) and angles of the pendulum (its restoring force is sin(theta), theta in radians)."""
from __future__ import annotations

import numpy as np

# water cooling in a room: deg C data stay below boiling; deg F data of a hot drink sit well above it
LOOKS_LIKE_DEGF = 105.0
LOOKS_LIKE_KELVIN = 200.0
# --units K with every value under this is a unit mix-up (colder than -120 degC)
NOT_KELVIN = 150.0
# a pendulum's angle in radians stays under pi (a swing over the top is not a pendulum's record);
# over 2 pi it is all but surely in degrees
LOOKS_LIKE_DEGREES = 2 * np.pi


def to_celsius(y, units):
    """Return (values in deg C, unit label, note or None). ``units`` None: guess only to warn.

    Parameters
    ----------
    y : array_like
        Temperatures.
    units : {"degC", "degF", "K"} or None
        Their unit; None leaves the values as they are and warns when they look like degF or K.

    Returns
    -------
    values : ndarray
        Temperatures in deg C (unchanged when ``units`` is None).
    label : str
        ``"degC"``, or ``""`` when the unit was not given.
    note : str or None
        What was converted, or a warning.

    Examples
    --------
    >>> to_celsius([212.0, 32.0], "degF")[0].tolist()
    [100.0, 0.0]
    >>> to_celsius([80.0, 20.0], "K")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --units K, but every value is under 150 (largest 80): that is below -120 degC; these look like degC (drop --units K, or give --units degC)
    >>> to_celsius([300.0, 350.0], None)[2].split(";")[0]
    'Warning: temperatures 300-350 look like kelvin'
    """
    y = np.asarray(y, float)
    if units == "degF":
        return (y - 32.0) * 5.0 / 9.0, "degC", "values converted from degF to degC for the physics"
    if units == "K":
        if np.max(y) < NOT_KELVIN:
            from odnn_sep.errors import InputError
            raise InputError(f"--units K, but every value is under {NOT_KELVIN:g} (largest {np.max(y):.4g}): that is "
                             f"below -120 degC; these look like degC (drop --units K, or give --units degC)")
        return y - 273.15, "degC", "values converted from K to degC for the physics"
    if units == "degC":
        return y, "degC", None
    lo, hi = float(np.min(y)), float(np.max(y))
    if lo > LOOKS_LIKE_KELVIN:
        note = (f"Warning: temperatures {lo:.4g}-{hi:.4g} look like kelvin; the cooling physics assumes degC: "
                f"pass --units K (or --units degC if they are)")
    elif hi > LOOKS_LIKE_DEGF:
        note = (f"Warning: temperatures up to {hi:.4g} look like degF (above boiling in degC); the cooling "
                f"physics assumes degC: pass --units degF (or --units degC if they are)")
    else:
        note = None
    return y, "", note


def to_radians(y, units):
    """Return (angles in rad, unit label, note or None). ``units`` None: guess only to warn.

    Parameters
    ----------
    y : array_like
        Angles of a pendulum record.
    units : {"deg", "rad"} or None
        Their unit; None leaves the values as they are (explain() notes angles that look like
        degrees: :func:`degrees_warning`).

    Returns
    -------
    values : ndarray
        Angles in rad (unchanged when ``units`` is None).
    label : str
        ``"rad"``, or ``""`` when the unit was not given.
    note : str or None
        What was converted.

    Examples
    --------
    >>> np.round(to_radians([90.0, -45.0], "deg")[0], 4).tolist()
    [1.5708, -0.7854]
    >>> to_radians([30.0, -28.0], None)[1:]
    ('', None)
    """
    y = np.asarray(y, float)
    if units == "deg":
        return np.deg2rad(y), "rad", "angles converted from deg to rad for the physics (sin theta); the report gives rad"
    if units == "rad":
        return y, "rad", None
    return y, "", None


def degrees_warning(y):
    """The warning for pendulum angles that look like degrees, or None (see :func:`to_radians`).

    Examples
    --------
    >>> degrees_warning([0.5, -0.4]) is None
    True
    >>> degrees_warning([30.0, -28.0]).split(";")[0]
    'angles up to 30 look like degrees'
    """
    top = float(np.max(np.abs(np.asarray(y, float)))) if np.size(y) else 0.0
    if not top > LOOKS_LIKE_DEGREES:
        return None
    return (f"angles up to {top:.4g} look like degrees; the pendulum physics (sin theta) assumes radians, so "
            f"the large-angle effect is not tested as it should be: convert them (CLI: --units deg, or "
            f"--units rad if they are radians)")
