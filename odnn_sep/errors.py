"""Every exception and warning the package raises on purpose, plus the input checks all of it shares.

Hierarchy::

    OdnnSepError
    ├── InputError (also ValueError)        bad data or options from the caller
    │   ├── ModelIntegrationError           a model could not be evaluated (ODE failure, non-finite values)
    │   └── NotFittedError (also AttributeError)  a fitted attribute was used before fit
    ├── FormatError (also ValueError)       a file could not be read or written in the requested format
    └── NotIdentifiableError                the physics lies (nearly) inside the disturbance class
    IdentifiabilityWarning, ConvergenceWarning (UserWarning)

Messages follow one pattern: name the parameter, show what was received, say what is allowed
and what to do. The CLI prints them as one line. :func:`check_option` and :func:`check_type` write
the "must be one of" messages (MNE's ``_check_option`` / ``_validate_type``).
"""
from __future__ import annotations

import numpy as np


class OdnnSepError(Exception):
    """Base class of every error this package raises on purpose."""


class InputError(OdnnSepError, ValueError):
    """The caller passed data or options that cannot be used."""


class FormatError(OdnnSepError, ValueError):
    """A file could not be read or written in the requested format."""


class ModelIntegrationError(InputError):
    """The model could not be evaluated (the ODE failed to integrate or gave non-finite values)."""


class NotFittedError(InputError, AttributeError):
    """A fitted attribute or ``predict`` was used before ``fit`` (scikit-learn's convention)."""


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


def check_option(name: str, value, allowed) -> None:
    """Raise InputError unless ``value`` is one of ``allowed`` (MNE's ``_check_option``).

    Examples
    --------
    >>> check_option("solver", "exact", ("exact", "network"))
    >>> check_option("solver", "fast", ("exact", "network"))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: solver must be one of 'exact', 'network'; got 'fast'
    """
    allowed = tuple(allowed)
    try:
        ok = value in allowed
    except TypeError:  # unhashable or incomparable value
        ok = False
    if not ok:
        listed = ", ".join(repr(a) for a in allowed)
        raise InputError(f"{name} must be one of {listed}; got {value!r}")


def check_type(name: str, value, types, what: str | None = None) -> None:
    """Raise InputError unless ``isinstance(value, types)`` (MNE's ``_validate_type``).

    ``what`` describes the allowed types in the message (default: their class names).

    Examples
    --------
    >>> check_type("epochs", 3, int)
    >>> check_type("epochs", "3", int)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: epochs must be int; got str ('3')
    """
    if not isinstance(types, tuple):
        types = (types,)
    if not isinstance(value, types):
        what = what or " or ".join(t.__name__ for t in types)
        raise InputError(f"{name} must be {what}; got {type(value).__name__} ({value!r})")
