"""Checks of a user model's options at construction: names that do not exist are errors, not no-ops.

A ``fixed=["T00"]`` or ``bounds={"kk": ...}`` naming no parameter was silently ignored (the user
believed a parameter held that was refitted); a parameter ``rhs`` does not take failed only inside
the optimiser as "failed to integrate"; an ``output`` beyond the state and a ``rhs`` returning
another number of derivatives than the state crashed with IndexError / RuntimeError.
"""
from __future__ import annotations

import inspect

import numpy as np

from odnn_sep.errors import InputError


def check_options(start, bounds, fixed, what):
    """Every name in ``bounds`` and ``fixed`` is a parameter; every bound is a pair ``lo < hi``.

    Parameters
    ----------
    start : dict
        The model's parameters.
    bounds : dict or None
        ``{name: (lo, hi)}``.
    fixed : iterable of str
        Parameters kept at their start.
    what : str
        The constructor, quoted in the message.

    Raises
    ------
    InputError

    Examples
    --------
    >>> check_options({"k": 1.0, "T0": 2.0}, {"k": (0, 5)}, ["T0"], "ode_model")
    >>> check_options({"k": 1.0, "T0": 2.0}, None, ["T00"], "ode_model")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: ode_model: fixed names 'T00', which is not a parameter; did you mean 'T0'? parameters: k, T0
    """
    from odnn_sep.mismatch.model import suggest_name
    if isinstance(fixed, str):
        raise InputError(f"{what}: fixed must be a list of parameter names, e.g. fixed=[{fixed!r}]; got the "
                         f"string {fixed!r}")
    for label, names in (("fixed", list(fixed or ())), ("bounds", list(dict(bounds or {})))):
        for k in names:
            if k not in start:
                raise InputError(f"{what}: {label} names {k!r}, which is not a parameter; "
                                 f"{suggest_name(k, start)}parameters: {', '.join(start)}")
    for k, b in dict(bounds or {}).items():
        try:
            lo, hi = (float(v) for v in b)
        except (TypeError, ValueError):
            raise InputError(f"{what}: bounds[{k!r}] must be a pair (lo, hi) of numbers; got {b!r}") from None
        if not lo < hi:
            raise InputError(f"{what}: bounds[{k!r}] = ({lo:g}, {hi:g}) is empty; give lo < hi "
                             f"(use fixed=[{k!r}] to hold a parameter)")


def check_rhs(rhs, start, state0, output, input_names=()):
    """``rhs(t, state, **params)`` takes every parameter given, needs none that is not, and ``output``
    indexes the state.

    Parameters
    ----------
    rhs : callable
        The user's right-hand side.
    start : dict
        Parameters (initial-state names included).
    state0 : sequence of float or str
        Initial state.
    output : int
        Observed state component.
    input_names : iterable of str
        Measured inputs passed to ``rhs`` as keywords.

    Raises
    ------
    InputError

    Examples
    --------
    >>> check_rhs(lambda t, s, k: [-k * s[0]], {"k": 1.0, "T0": 2.0}, ["T0"], 0)
    >>> check_rhs(lambda t, s, k: [-k * s[0]], {"kk": 1.0, "T0": 2.0}, ["T0"], 0)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: ode_model: parameter 'kk' is not an argument of rhs; did you mean 'k'? rhs(t, state, ...) accepts: k
    """
    from odnn_sep.mismatch.model import suggest_name
    n = len(state0)
    if not isinstance(output, (int, np.integer)) or not -n <= int(output) < n:
        raise InputError(f"ode_model: output={output!r} is not a component of the state, which has {n} "
                         f"entr{'y' if n == 1 else 'ies'} (state0); give 0..{n - 1}")
    try:
        sig = inspect.signature(rhs)
    except (TypeError, ValueError):
        return
    ps = list(sig.parameters.values())
    if any(p.kind == p.VAR_KEYWORD for p in ps):
        return
    accepted = [p.name for p in ps[2:] if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    states = {s for s in state0 if isinstance(s, str)}
    given = [k for k in start if k not in states] + list(input_names)
    for k in given:
        if k not in accepted:
            raise InputError(f"ode_model: parameter {k!r} is not an argument of rhs; {suggest_name(k, accepted)}"
                             f"rhs(t, state, ...) accepts: {', '.join(accepted) or 'nothing after state'}")
    for p in ps[2:]:
        if p.default is p.empty and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name not in given:
            raise InputError(f"ode_model: rhs needs {p.name!r}, which params does not give; add a starting "
                             f"value params[{p.name!r}] (or a default in rhs)")


def check_derivative_count(name, derivatives, state0):
    """``rhs`` returned one derivative per state entry.

    Examples
    --------
    >>> check_derivative_count("m", [1.0], [2.0])
    >>> check_derivative_count("m", [1.0, 0.0], [2.0])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: model 'm': rhs returned 2 derivative(s) for a state of 1 entr(ies) (state0); return one per state entry
    """
    k = int(np.size(derivatives))
    if k != len(state0):
        raise InputError(f"model {name!r}: rhs returned {k} derivative(s) for a state of {len(state0)} entr(ies) "
                         f"(state0); return one per state entry")
