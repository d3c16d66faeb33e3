"""Exception and warning types, plus the input checks every front-end shares.

Messages follow one pattern: name the parameter, show what was received, say what is allowed
and what to do. The CLI prints them as one line.
"""
from __future__ import annotations

import numpy as np


class OdnnSepError(Exception):
    """Base class of every error this package raises on purpose."""


class InputError(OdnnSepError, ValueError):
    """The caller passed data or options that cannot be used."""


class FormatError(OdnnSepError, ValueError):
    """A file could not be read or written in the requested format."""


class NotIdentifiableError(OdnnSepError):
    """The physics basis lies (nearly) inside the disturbance class, so theta is not determined."""


class IdentifiabilityWarning(UserWarning):
    """Theta is only weakly determined (ill-conditioned, or only set-identified)."""


class ConvergenceWarning(UserWarning):
    """An iterative solver stopped before meeting its tolerance."""


def check_finite(name: str, a: np.ndarray) -> None:
    """Raise InputError if ``a`` holds NaN or inf, reporting each with a count and first index."""
    a = np.asarray(a)
    if not np.issubdtype(a.dtype, np.floating) and not np.issubdtype(a.dtype, np.complexfloating):
        return
    for label, bad in (("NaN", np.isnan(a)), ("inf", np.isinf(a))):
        n = int(bad.sum())
        if n:
            first = np.unravel_index(int(np.argmax(bad.ravel())), a.shape)
            first = first[0] if len(first) == 1 else tuple(int(i) for i in first)
            raise InputError(
                f"{name} contains {n} {label} value(s) (first at index {first}); "
                f"remove or interpolate them before fitting"
            )


def as_float_array(name: str, a, *, ndim: tuple[int, ...] = (1,)) -> np.ndarray:
    """Copy ``a`` to a float64 array, checking dimensionality, emptiness and finiteness."""
    try:
        arr = np.array(a, dtype=np.float64)  # always a copy: callers' arrays are never mutated
    except (TypeError, ValueError) as exc:
        raise InputError(f"{name} must be numeric; could not convert it to float ({exc})") from None
    if arr.ndim not in ndim:
        allowed = " or ".join(f"{d}-D" for d in ndim)
        raise InputError(f"{name} must be {allowed}; got an array of shape {arr.shape}")
    if arr.size == 0:
        raise InputError(f"{name} is empty (shape {arr.shape}); pass at least one sample")
    check_finite(name, arr)
    return arr
