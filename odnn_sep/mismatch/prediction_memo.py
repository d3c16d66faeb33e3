"""Predictions of a model kept by their exact parameter values, so a fit never integrates the same
ODE twice (its start, its optimum, the folds' common start, and a preset's own part under a change of
an added effect's parameters). Served predictions are bit-for-bit those made anew.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.mismatch.effects import EFFECTS


class PredictionMemo:
    """Predictions of one model on one set of times, kept by their exact parameter values.

    A model's prediction is a deterministic function of its parameters: serving a repeated one
    from here gives bit-for-bit the result of predicting it again, without integrating an ODE
    twice. Parameters are matched exactly (the bits of every float, and its type); a failed
    prediction is not kept (it fails again, with its own error). Copies are handed out, so a
    caller that changes its array cannot change what others are served. At most ``max_bytes`` are
    kept; beyond that, predictions are made and not kept.

    A built-in preset's own part (its equations with their native effects) does not read the
    parameters of the generic effects added on top of it (a pickup's amplitude and frequency, an
    offset, a step, a modulation): that part is kept too, by the other parameters, so the
    Jacobian columns of those parameters, and every trial point that changes only them, apply the
    effect to the kept integration. (Not for a time delay, which moves the times the equations are
    solved at, nor for user models or wrapped presets, whose functions may read any parameter.)

    Parameters
    ----------
    model : Model
        The model (its ``predict``).
    t : ndarray
        The times every prediction is made at (the memo belongs to them).
    max_bytes : int, optional
        Memory kept at most.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = make_model("oscillator").with_effect("cubic_stiffness")
    >>> t = np.linspace(0, 5, 50); memo = PredictionMemo(m, t)
    >>> p = {**m.start, "beta": 0.1}
    >>> a = memo.predict(t, p); b = memo.predict(t, dict(p))
    >>> bool(np.array_equal(a, m.predict(t, p))), bool(np.array_equal(a, b)), memo.hits, memo.misses
    (True, True, 1, 1)
    >>> _ = memo.predict(t, {**p, "beta": float(np.nextafter(0.1, 1.0))})   # the next float: predicted anew
    >>> memo.hits, memo.misses
    (1, 2)
    """

    def __init__(self, model, t, max_bytes=64_000_000):
        self.model, self.t = model, t
        self.max_bytes = max_bytes
        self._kept: dict = {}
        self._inner: dict = {}
        self._bytes = 0
        self.hits = self.misses = self.inner_hits = 0
        self._unread = generic_only_names(model)

    def predict(self, t, p):
        """``model.predict(t, p)``, served from the memo when these exact parameters were predicted."""
        key = exact_key(p) if t is self.t else None
        if key is None:
            return self.model.predict(t, p)
        kept = self._kept.get(key)
        if kept is not None:
            self.hits += 1
            return kept.copy()
        if self._unread:
            out = self.model.predict_through(t, p, self._through_kept)
        else:
            out = self.model.predict(t, p)
        self.misses += 1
        self._keep(self._kept, key, out)
        return out

    def _keep(self, store, key, out):
        if self._bytes + out.nbytes <= self.max_bytes:
            store[key] = out.copy()
            self._bytes += out.nbytes

    def _through_kept(self, inner):
        def served(tt, pp):
            key = exact_key({k: v for k, v in pp.items() if k not in self._unread}) if tt is self.t else None
            if key is None:
                return inner(tt, pp)
            kept = self._inner.get(key)
            if kept is not None:
                self.inner_hits += 1
                return kept.copy()
            out = np.asarray(inner(tt, pp), dtype=float)
            self._keep(self._inner, key, out)
            return out
        return served


def generic_only_names(model):
    """Parameters of ``model`` that only its generic effects read, so its own part never does; None
    where that is not known (a user model, a wrapped or engine preset, a time delay, no generic effect).

    Parameters
    ----------
    model : Model
        The model.

    Returns
    -------
    frozenset or None

    Examples
    --------
    >>> from odnn_sep.mismatch.model import make_model
    >>> sorted(generic_only_names(make_model("oscillator").with_effect("periodic_pickup")))
    ['a_pk', 'b_pk', 'omega_pk']
    >>> generic_only_names(make_model("oscillator").with_effect("periodic_forcing")) is None   # in its equations
    True
    """
    from odnn_sep.mismatch.presets import PRESETS
    pre = model.preset
    if pre is None or type(pre) not in {type(x) for x in PRESETS.values()} or model.builder != pre.build:
        return None
    generic = [e for e in model.effects if e not in model.native]
    if not generic or "time_delay" in generic:
        return None
    names = set().union(*(EFFECTS[e].params for e in generic)) - set(pre.params)
    return frozenset(names) or None


def exact_key(p):
    """A key equal for parameter dicts with the same names (in order), value types and value bits.

    None when a value is neither a string nor a real number (such parameters are not matched).

    Parameters
    ----------
    p : dict
        Parameters.

    Returns
    -------
    tuple or None

    Examples
    --------
    >>> exact_key({"k": 4.0, "n": 2}) == exact_key({"k": 4.0, "n": 2}), exact_key({"k": 4.0}) == exact_key({"k": 4})
    (True, False)
    >>> exact_key({"k": 0.1}) == exact_key({"k": 0.1 + 2e-17}), exact_key({"k": [1.0]})
    (False, None)
    """
    items = []
    for k, v in p.items():
        if isinstance(v, str):
            items.append((k, "str", v))
        elif isinstance(v, (float, int, np.floating, np.integer)) and not isinstance(v, (bool, np.bool_)):
            items.append((k, type(v).__name__, repr(int(v)) if isinstance(v, (int, np.integer)) else float(v).hex()))
        else:
            return None
    return tuple(items)
