"""Every exception and warning the package raises on purpose, plus the input checks all of it shares.

Hierarchy::

    OdnnSepError
    ├── InputError (also ValueError)        bad data or options from the caller
    │   ├── ModelIntegrationError           a model could not be evaluated (ODE failure, non-finite values)
    │   └── NotFittedError (also AttributeError)  a fitted attribute was used before fit
    ├── FormatError (also ValueError)       a file could not be read or written in the requested format
    ├── MissingDependencyError (also ImportError)  an optional package a feature needs is not installed
    └── NotIdentifiableError                the physics lies (nearly) inside the disturbance class
    IdentifiabilityWarning, ConvergenceWarning (UserWarning)

Messages follow one pattern: name the parameter, show what was received, say what is allowed
and what to do. The CLI prints them as one line. :func:`check_option` and :func:`check_type` write
the "must be one of" messages (MNE's ``_check_option`` / ``_validate_type``), :func:`check_number`
the "'auto' or a number" ones.
"""
from __future__ import annotations

import math

import numpy as np


class OdnnSepError(Exception):
    """Base class of every error this package raises on purpose.

    Examples
    --------
    >>> try:
    ...     check_option("solver", "fast", ("exact", "network"))
    ... except OdnnSepError as exc:          # one except clause for every deliberate error
    ...     print(type(exc).__name__)
    InputError
    """


class InputError(OdnnSepError, ValueError):
    """The caller passed data or options that cannot be used.

    Examples
    --------
    >>> as_float_array("y", [1.0, float("nan")])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: y contains 1 NaN value(s) (first at index 1); remove or interpolate them before fitting
    >>> issubclass(InputError, ValueError)     # code that catches ValueError keeps working
    True
    """


class MarkNotFoundError(InputError):
    """The watermark (text or logo) was searched for and not found in the image.

    Examples
    --------
    >>> issubclass(MarkNotFoundError, InputError)    # callers catching InputError keep working
    True
    """


class FormatError(OdnnSepError, ValueError):
    """A file could not be read or written in the requested format.

    Examples
    --------
    >>> import os, tempfile
    >>> from odnn_sep.fit.data import load_signal
    >>> with tempfile.TemporaryDirectory() as d:
    ...     path = os.path.join(d, "data.xyz")
    ...     with open(path, "w") as fh:
    ...         _ = fh.write("1 2")
    ...     try:
    ...         load_signal(path)
    ...     except FormatError as exc:
    ...         print("FormatError")
    FormatError
    """


class MissingDependencyError(OdnnSepError, ImportError):
    """An optional package a feature needs is not installed; the message names the pip extra.

    Examples
    --------
    >>> from odnn_sep.signals.optional import require
    >>> try:
    ...     require("no_such_package_here", "grid", "the power-grid dataset")
    ... except MissingDependencyError as exc:
    ...     print(str(exc).split("; ")[-1])
    install it with: pip install "odnn-sep[grid]"
    """


class ModelIntegrationError(InputError):
    """The model could not be evaluated (the ODE failed to integrate or gave non-finite values).

    Examples
    --------
    >>> issubclass(ModelIntegrationError, InputError)     # the CLI reports it as bad input (exit 1)
    True
    """


class NotFittedError(InputError, AttributeError):
    """A fitted attribute or ``predict`` was used before ``fit`` (scikit-learn's convention).

    Examples
    --------
    >>> from odnn_sep.core import Basis, Separator
    >>> try:
    ...     Separator(Basis([lambda x: x], names=["a"])).predict([0.0, 1.0])
    ... except NotFittedError:
    ...     print("fit first")
    fit first
    """


class NotIdentifiableError(OdnnSepError):
    """The physics basis lies (nearly) inside the disturbance class, so theta is not determined.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 41)
    >>> try:                                   # x**2 is even: an even disturbance can imitate it
    ...     Separator(Basis([lambda x: x**2], names=["a"]), disturbance=Even()).fit(x, x**2)
    ... except NotIdentifiableError:
    ...     print("not identifiable")
    not identifiable
    """


class IdentifiabilityWarning(UserWarning):
    """Theta is only weakly determined (ill-conditioned, or only set-identified).

    Examples
    --------
    >>> import warnings
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Convex, Separator
    >>> x = np.linspace(-1, 1, 41)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     _ = Separator(Basis([lambda x: np.sin(5 * x)], names=["a"]), disturbance=Convex()).fit(
    ...         x, x**2 + np.sin(5 * x))
    >>> any(issubclass(w.category, IdentifiabilityWarning) for w in caught)   # only an interval
    True
    """


class ConvergenceWarning(UserWarning):
    """An iterative solver stopped before meeting its tolerance.

    Examples
    --------
    >>> import warnings
    >>> with warnings.catch_warnings():
    ...     warnings.simplefilter("ignore", ConvergenceWarning)   # e.g. short network training in a demo
    """


def check_finite(name: str, a: np.ndarray) -> None:
    """Raise InputError if ``a`` holds NaN or inf, reporting each with a count and first index.

    Parameters
    ----------
    name : str
        The array's name, for the message.
    a : ndarray
        Any shape; arrays that are not floating point are accepted as they are.

    Raises
    ------
    InputError
        For NaN (reported first) or infinite values.

    Examples
    --------
    >>> import numpy as np
    >>> check_finite("x", np.array([0.0, 1.0]))
    >>> check_finite("x", np.array([[0.0, np.inf], [np.inf, 1.0]]))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: x contains 2 inf value(s) (first at index (0, 1)); remove or interpolate them before fitting
    """
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
    """Copy ``a`` to a float64 array, checking dimensionality, emptiness and finiteness.

    Parameters
    ----------
    name : str
        The array's name, for the messages.
    a : array_like
        The values.
    ndim : tuple of int, optional
        Dimensions accepted.

    Returns
    -------
    ndarray
        A float64 copy.

    Raises
    ------
    InputError
        For non-numeric, wrongly shaped, empty or non-finite input.

    Examples
    --------
    >>> as_float_array("t", [1, 2, 3])
    array([1., 2., 3.])
    >>> as_float_array("t", [[1, 2]], ndim=(1,))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: t must be 1-D; got an array of shape (1, 2)
    >>> as_float_array("y", np.array([1 + 2j]))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: y is complex (complex128); pass the real-valued samples (np.real(...) where the imaginary part is zero)
    """
    kind = getattr(getattr(a, "dtype", None), "kind", None)
    if kind == "c":
        # float64 conversion would drop the imaginary part with only a NumPy warning
        raise InputError(f"{name} is complex ({a.dtype}); pass the real-valued samples (np.real(...) where "
                         f"the imaginary part is zero)")
    if kind == "b":
        raise InputError(f"{name} is boolean; pass numeric values")
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

    Parameters
    ----------
    name : str
        The option's name.
    value : object
        The value given.
    allowed : iterable
        The accepted values.

    Raises
    ------
    InputError
        Listing the accepted values.

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

    Parameters
    ----------
    name : str
        The option's name.
    value : object
        The value given.
    types : type or tuple of type
        Accepted types.
    what : str, optional
        Wording of the accepted types in the message.

    Raises
    ------
    InputError

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


def check_number(name: str, value, *, positive: bool = False, allow: tuple[str, ...] = ()):
    """``value`` as a finite float (``> 0`` when ``positive``), or the word of ``allow`` it spells
    (``'auto'``, case and spaces ignored), else InputError. For options such as ``--block-s auto|S``.

    Parameters
    ----------
    name : str
        The option, e.g. ``"--mains"``.
    value : object
        The value given (a number or a string).
    positive : bool, optional
        Require ``> 0``.
    allow : tuple of str, optional
        Words accepted instead of a number (lower case).

    Returns
    -------
    float or str
        The number, or the word of ``allow``.

    Raises
    ------
    InputError
        For anything else, a non-finite number or (with ``positive``) a number ``<= 0``.

    Examples
    --------
    >>> check_number("--mains", " Auto", allow=("auto",)), check_number("--mains", "60", positive=True)
    ('auto', 60.0)
    >>> check_number("--block-s", "long", allow=("auto",))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --block-s must be 'auto' or a number; got 'long'
    >>> check_number("--max-hz", -5, positive=True)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --max-hz must be > 0; got -5
    """
    word = str(value).strip().lower()
    if word in allow:
        return word
    try:
        v = float(value)
    except (TypeError, ValueError):
        words = " or ".join(repr(a) for a in allow)
        raise InputError(f"{name} must be {words + ' or ' if allow else ''}a number; got {value!r}") from None
    if not math.isfinite(v):
        raise InputError(f"{name} must be a finite number; got {value!r}")
    if positive and v <= 0:
        raise InputError(f"{name} must be > 0; got {value!r}")
    return v
