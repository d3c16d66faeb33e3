"""Temperature units for the cooling preset: its physics (vapour pressure, radiation) is in deg C."""
from __future__ import annotations

import numpy as np

# water cooling in a room: deg C data stay below boiling; deg F data of a hot drink sit well above it
LOOKS_LIKE_DEGF = 105.0
LOOKS_LIKE_KELVIN = 200.0


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
    >>> to_celsius([300.0, 350.0], None)[2].split(";")[0]
    'warning: temperatures 300-350 look like kelvin'
    """
    y = np.asarray(y, float)
    if units == "degF":
        return (y - 32.0) * 5.0 / 9.0, "degC", "values converted from degF to degC for the physics"
    if units == "K":
        return y - 273.15, "degC", "values converted from K to degC for the physics"
    if units == "degC":
        return y, "degC", None
    lo, hi = float(np.min(y)), float(np.max(y))
    if lo > LOOKS_LIKE_KELVIN:
        note = (f"warning: temperatures {lo:.4g}-{hi:.4g} look like kelvin; the cooling physics assumes degC: "
                f"pass --units K (or --units degC if they are)")
    elif hi > LOOKS_LIKE_DEGF:
        note = (f"warning: temperatures up to {hi:.4g} look like degF (above boiling in degC); the cooling "
                f"physics assumes degC: pass --units degF (or --units degC if they are)")
    else:
        note = None
    return y, "", note
