"""Parameters the record cannot separate: groups that only enter the model through a combination.

A model ``a * b * exp(-k t)`` fits a record as well with ``(2a, b/2)`` as with ``(a, b)``: the
Jacobian's columns of ``a`` and ``b`` are parallel. The sandwich's pseudo-inverse then drops that
direction and reports *tight* intervals for both (``a = 2.629 ± 0.0004`` for any split of a product
of 6), which is a confident wrong answer. Here such groups are found and their parameters get no
interval, with a sentence saying which combination is determined.

A direction is suspect when its singular value, on the column-equilibrated Jacobian, is under
:data:`SUSPECT` of the largest (a forward-difference Jacobian of an exactly confounded pair sits at
1e-6 to 1e-16; the two-exponential models of the benchmark at 1e-3 and above). A suspect group is
confirmed by a profile: its leading parameter is fixed at twice its value (or moved by one unit from
zero), the others are refitted, and the sum of squares must not rise by more than the 95 % quantile
of chi-square with one degree of freedom in noise variances. An ill-conditioned but identified
model fails the profile and keeps its (wide) intervals.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

SUSPECT = 1e-4          # singular value ratio under which a direction is checked by a profile
MEMBER = 0.1            # a parameter belongs to a null direction when its share of the unit vector exceeds this
CHI2_95_1DOF = 3.84     # profile rise (in noise variances) under which the moved value fits as well


def suspect_groups(J, names):
    """Groups of parameters along the near-null directions of the equilibrated Jacobian ``J``.

    Parameters
    ----------
    J : array_like, shape (n, q)
        Jacobian of the residual at the optimum.
    names : list of str
        The ``q`` free parameters, in the order of ``J``'s columns.

    Returns
    -------
    list of list of str
        Each group's parameters in the order of ``names`` (the first is the one a profile moves);
        overlapping groups are merged. Empty when every direction is determined.

    Examples
    --------
    >>> import numpy as np
    >>> e = np.exp(-np.linspace(0, 5, 50))
    >>> suspect_groups(np.c_[2 * e, 3 * e, np.linspace(0, 1, 50)], ["a", "b", "k"])
    [['a', 'b']]
    >>> suspect_groups(np.c_[e, np.linspace(0, 1, 50)], ["a", "k"])
    []
    """
    J = np.asarray(J, float)
    if J.ndim != 2 or J.shape[1] == 0 or not np.all(np.isfinite(J)):
        return []
    d = np.linalg.norm(J, axis=0)
    d = np.where(d > 0, d, 1.0)
    # only V is needed: with more rows than columns the thin decomposition has all of it, without the
    # n x n U a full one builds (3 GB and minutes for a 20 000-sample record)
    _, s, vt = np.linalg.svd(J / d, full_matrices=J.shape[0] < J.shape[1])
    s = np.r_[s, np.zeros(J.shape[1] - len(s))]
    top = float(s.max()) if s.size else 0.0
    groups = []
    for sv, v in zip(s, vt, strict=True):
        if top > 0 and sv > SUSPECT * top:
            continue
        share = np.abs(v) / max(float(np.abs(v).max()), 1e-300)
        members = [names[i] for i in range(len(names)) if share[i] > MEMBER]
        merged = [g for g in groups if set(g) & set(members)]
        for g in merged:
            groups.remove(g)
            members += [x for x in g if x not in members]
        groups.append([x for x in names if x in members])
    return groups


def _moved(value, lo, hi):
    """A value far from ``value`` inside ``[lo, hi]``: twice it, half it, or one unit off zero."""
    tries = [2.0 * value, 0.5 * value] if value != 0 else [1.0, -1.0]
    for x in tries:
        if lo <= x <= hi and x != value:
            return x
    return None


def confirmed_groups(model, groups, params, rss, n_eff, refit):
    """The suspect groups whose leading parameter, moved far, fits as well once the others are refitted.

    Parameters
    ----------
    model : Model
        The fitted model.
    groups : list of list of str
        From :func:`suspect_groups`.
    params : dict
        Fitted parameters.
    rss : float
        Sum of squares at ``params``.
    n_eff : int
        Effective sample count (for the noise variance ``rss / (n_eff - q)``).
    refit : callable
        ``refit(model, start) -> rss`` of a fit of ``model`` from ``start``.

    Returns
    -------
    list of dict
        ``{"parameters": [...], "moved": name, "from": v, "to": x, "rise": noise variances}`` per
        confirmed group.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import custom_model
    >>> from odnn_sep.mismatch.fitting import fit
    >>> t = np.linspace(0, 10, 200)
    >>> y = 6 * np.exp(-0.3 * t) + 0.01 * np.random.default_rng(0).normal(size=200)
    >>> f = fit(custom_model(lambda t, a, b, k: a * b * np.exp(-k * t), {"a": 1.0, "b": 1.0, "k": 0.5}), t, y)
    >>> [g["parameters"] for g in f.unidentified], f.intervals().keys()
    ([['a', 'b']], dict_keys(['k']))
    """
    out = []
    sigma2 = rss / max(n_eff - len(model.free), 1)
    for g in groups:
        lead = g[0]
        lo, hi = model.bounds.get(lead, (-np.inf, np.inf))
        x = _moved(float(params[lead]), lo, hi)
        if x is None:
            continue
        pinned = replace(model, fixed=model.fixed | {lead}, start={**model.start, **params, lead: x})
        try:
            rss_moved = refit(pinned, {**params, lead: x})
        except Exception:  # noqa: BLE001 - a profile that cannot be evaluated confirms nothing
            continue
        rise = (rss_moved - rss) / max(sigma2, 1e-300)
        if np.isfinite(rise) and rise < CHI2_95_1DOF:
            out.append({"parameters": list(g), "moved": lead, "from": float(params[lead]), "to": float(x),
                        "rise": float(max(rise, 0.0))})
    return out


def unidentified_sentence(group):
    """The plain sentence of one confirmed group (from :func:`confirmed_groups`).

    Examples
    --------
    >>> unidentified_sentence({"parameters": ["a", "b"], "moved": "a", "from": 2.0, "to": 4.0, "rise": 0.0})
    'parameters a, b are not identifiable from this record: with a fixed at 4 instead of 2 and the others refitted, the model fits as well (the sum of squares rises by 0 noise variances), so only a combination of them is determined; they get no interval. Fix all but one of them (custom_model/ode_model fixed=[...]) or reparametrise the model'
    """
    names = ", ".join(group["parameters"])
    if len(group["parameters"]) == 1:
        head = f"parameter {names} is not identifiable from this record: it does not change the fit"
    else:
        head = f"parameters {names} are not identifiable from this record"
    # a measured input's gain kd_<name>: a column that does not vary acts as one more constant
    inputs = [k[3:] for k in group["parameters"] if k.startswith("kd_")]
    fix = (f"the input {', '.join(repr(k) for k in inputs)} does not vary enough to tell its gain from the "
           f"model's constants: give a record in which it changes, or leave it out"
           if inputs else "Fix all but one of them (custom_model/ode_model fixed=[...]) or reparametrise the model")
    return (f"{head}: with {group['moved']} fixed at {group['to']:.4g} instead of {group['from']:.4g} and the "
            f"others refitted, the model fits as well (the sum of squares rises by {group['rise']:.2g} noise "
            f"variances), so only a combination of them is determined; they get no interval. {fix}")


def unidentified_warnings(*fits):
    """One sentence per group of parameters that any of ``fits`` could not separate (each group once).

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> g = {"parameters": ["a", "b"], "moved": "a", "from": 2.0, "to": 4.0, "rise": 0.0}
    >>> len(unidentified_warnings(SimpleNamespace(unidentified=[g]), SimpleNamespace(unidentified=[g]), None))
    1
    """
    seen, out = set(), []
    for f in fits:
        for g in getattr(f, "unidentified", None) or []:
            key = tuple(sorted(g["parameters"]))
            if key not in seen:
                seen.add(key)
                out.append(unidentified_sentence(g))
    return out
