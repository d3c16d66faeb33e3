"""Final check of each named effect against its rivals, on the final model, with a prewhitened score.

At the step an effect is chosen, its rivals (the other physics candidates that passed) were scored
on top of an incomplete model: a periodic pickup or a second effect not yet absorbed makes the
residual larger and coloured, and the comparison weak. Here every rival replaces the named effect
in the *final* model and is refitted from several starts (the rival's own step fit, its neutral
value, half and twice its step value), so a rival never loses by a failed fit. The two are then
compared by a non-nested likelihood score on the same data:

- the residuals of both models are prewhitened with one AR(p) filter, fitted (order by BIC) to the
  final model's residual: coloured noise counts for what it is, not as independent samples;
- samples that are outliers of the final residual (robust z > 5: spikes) keep only the difference
  of the two models there, not the spike, which would otherwise swamp the noise estimate;
- score = ``n log(RSS_w / n) + k log n`` (BIC of the prewhitened innovations).

The better score is named; rivals within :data:`~odnn_sep.mismatch.selection.EQUIVALENCE_GAP` of it
are reported as equivalent ("the data cannot tell them apart").
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from odnn_sep.core.whitening import ar_fit, prewhiten
from odnn_sep.mismatch.candidates import FitStub, rebuild_model, refit_robust
from odnn_sep.mismatch.effects import DISTURBANCE_EFFECTS, compatible, effect_param_names

OUTLIER_Z = 5.0   # robust z of a spike: P(|z| > 5) ~ 6e-7 per Gaussian sample


def noise_filter(resid) -> np.ndarray:
    """AR prewhitening filter of a residual, or none when the noise is not red at low frequencies.

    A filter whose coefficients sum to zero or less would raise the weight of slow deviations
    above the plain least-squares one: on white noise that is a chance fit of the sample (BIC picks
    a small order now and then), so it is not used; the evidence is then never inflated over the
    plain BIC for smooth effects.

    Parameters
    ----------
    resid : ndarray
        Residual in time order.

    Returns
    -------
    ndarray
        AR coefficients (empty: no filter).

    Examples
    --------
    >>> import numpy as np
    >>> noise_filter(np.random.default_rng(1).normal(size=400)).tolist()
    []
    """
    a = ar_fit(resid)
    return a if len(a) and float(np.sum(a)) > 0 else np.zeros(0)


def outlier_mask(resid) -> np.ndarray:
    """Samples whose robust z-score (median, 1.4826 MAD) exceeds :data:`OUTLIER_Z`.

    Parameters
    ----------
    resid : ndarray
        Residual.

    Returns
    -------
    ndarray of bool

    Examples
    --------
    >>> import numpy as np
    >>> r = np.r_[np.random.default_rng(0).normal(size=99), 30.0]
    >>> np.flatnonzero(outlier_mask(r)).tolist()
    [99]
    """
    r = np.asarray(resid, float)
    med = np.median(r)
    mad = 1.4826 * np.median(np.abs(r - med))
    if mad <= 0:
        return np.zeros(len(r), bool)
    return np.abs(r - med) > OUTLIER_Z * mad


def _sum_sq(e, floor2) -> float:
    """Sum of squares of ``e`` with the record's resolution per sample (resolution.py), never 0."""
    e = np.asarray(e, float)
    return max(float(e @ e) + len(e) * floor2, 1e-300)


def prewhitened_score(resid, ref_resid, n_params, coefs, mask, floor2=0.0) -> float:
    """BIC of the AR-prewhitened residual; at ``mask`` samples only ``resid - ref_resid`` counts.

    Parameters
    ----------
    resid : ndarray
        Residual of the model scored.
    ref_resid : ndarray
        Residual of the reference (final) model.
    n_params : float
        Parameter count of the model scored.
    coefs : ndarray
        AR filter (:func:`~odnn_sep.core.whitening.ar_fit` of the reference residual).
    mask : ndarray of bool
        Outlier samples of the reference residual.
    floor2 : float, optional
        Per-sample square of the record's resolution (:mod:`~odnn_sep.mismatch.resolution`),
        added to the sum of squares.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> r = np.random.default_rng(0).normal(size=100)
    >>> s0 = prewhitened_score(r, r, 1, [], np.zeros(100, bool))
    >>> round(prewhitened_score(r + 0.5, r, 1, [], np.zeros(100, bool)) - s0, 1)
    30.4
    """
    x = np.where(mask, np.asarray(resid) - np.asarray(ref_resid), resid)
    e = prewhiten(x, coefs)
    n = max(len(e), 1)
    return float(n * np.log(_sum_sq(e, floor2) / n) + n_params * np.log(n))


def _rival_starts(stub, rival):
    """Starts for the rival in the final model: its neutral value, its step fit, half and twice that."""
    own = {k: rival.fit.params[k] for k in effect_param_names(rival.effect, rival.fit.params)}
    starts = [dict(stub.params), {**stub.params, **own}]
    for s in (0.5, 2.0):
        starts.append({**stub.params, **{k: v * s if isinstance(v, float) and not k.startswith(("omega", "lam",
                                                                                               "f_", "k_h"))
                                          else v for k, v in own.items()}})
    return starts


def _refit_with(sel, base, setup, named, rival):
    """The final model with ``named`` replaced by ``rival``, refitted; None when it cannot be fitted."""
    effects = [rival.effect if o is named else o.effect for o in sel.accepted]
    others = [e for e in effects if e != rival.effect]
    if not compatible(rival.effect, others):
        return None
    try:
        stub = rebuild_model(base, effects, sel.fit, setup.make_model)
    except (KeyError, ValueError):
        return None
    f, _ = refit_robust(rival.effect, stub.model, _rival_starts(stub, rival), FitStub(None, {}, np.inf),
                        setup.t, setup.y, setup.G)
    return f


def recheck_rivals(sel, base, setup, gap):
    """Re-decide each named effect against its rivals on the final model (see the module notes).

    Replaces a named effect by a rival that scores better, sets ``equivalent`` to the rivals within
    ``gap`` and records every score in ``rivals`` (``prewhitened_gap``, ``ar_order``). In place.

    Parameters
    ----------
    sel : Selection
        The selection after the backward check (``accepted``, ``fit``).
    base : Fit
        The calibrated model without effects.
    setup : SelectionSetup
        Data, candidate factory and disturbance columns.
    gap : float
        Largest prewhitened score gap reported as equivalent.

    Returns
    -------
    None

    Examples
    --------
    :func:`~odnn_sep.mismatch.explain` calls it after the backward check; each rival's score gap
    on the final model ends in ``rivals`` of the named effect:

    >>> import numpy as np
    >>> from odnn_sep.mismatch import explain, make_model
    >>> t = np.linspace(0, 0.6, 120)
    >>> truth = make_model("freefall", {"g": 9.81, "h0": 2.0}).with_effect("quadratic_drag", {"q_drag": 0.1})
    >>> y = truth.predict(t) + 0.001 * np.random.default_rng(0).normal(size=120)
    >>> res = explain("freefall", t, y)
    >>> res.effects, res.named[0].equivalent
    (['quadratic_drag'], [])
    """
    for i, named in enumerate(list(sel.accepted)):
        current = {o.effect for o in sel.accepted}
        rivals = [r for r in getattr(named, "rival_candidates", []) if r.effect not in current]
        if named.effect in DISTURBANCE_EFFECTS or not rivals:
            continue
        ref = sel.fit.residual
        mask = outlier_mask(ref)
        coefs = noise_filter(np.where(mask, 0.0, ref)) if np.ndim(setup.t) == 1 else np.zeros(0)
        fl = sel.fit.floor2
        scores = {named.effect: (prewhitened_score(ref, ref, sel.fit.n_params, coefs, mask, fl), sel.fit, named)}
        for r in rivals:
            f = _refit_with(sel, base, setup, named, r)
            if f is not None:
                scores[r.effect] = (prewhitened_score(f.residual, ref, f.n_params, coefs, mask, fl), f, r)
        if len(scores) > 1:
            _name_best(sel, i, named, scores, gap, {"ar_order": len(coefs), "outliers": int(mask.sum())})


def _name_best(sel, i, named, scores, gap, info):
    """Put the best-scoring of ``scores`` ({effect: (score, fit, candidate)}) in place ``i`` of the
    selection, with its rivals' gaps (and ``info``) and the equivalent ones (within ``gap``)."""
    best = min(scores, key=lambda e: scores[e][0])
    s_best, f_best, c_best = scores[best]
    if best != named.effect:
        c_best = replace(c_best, fit=f_best, step=named.step, rivals=[], equivalent=[],
                         rival_candidates=[scores[e][2] for e in scores if e != best],
                         note=f"preferred to {named.effect} on the final model (prewhitened score "
                              f"{scores[named.effect][0] - s_best:+.1f})")
        sel.accepted[i] = c_best
        sel.fit = f_best
    c_best.equivalent = [e for e in scores if e != best and scores[e][0] - s_best <= gap]
    c_best.rivals = [{"effect": e, "prewhitened_gap": float(scores[e][0] - s_best), **info}
                     for e in scores if e != best]


def step_score(cur, resid, n_params, t) -> float:
    """Evidence for a refit with residual ``resid`` over the current model ``cur``: BIC drop.

    The BIC of both is taken on residuals prewhitened by the AR(p) filter of the refit's own
    residual (order by BIC; none for white noise, which gives the plain BIC drop exactly). Coloured
    noise then counts for its effective number of independent samples, so an effect that only
    follows slow noise (an amplitude modulation on AR(1) noise) does not gain by it.

    Parameters
    ----------
    cur : Fit
        The current model.
    resid : ndarray
        Residual of the refit (current model plus the effect).
    n_params : float
        Parameter count of the refit.
    t : ndarray
        Sample times (a 2D field gets the plain BIC drop).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60)
    >>> cur = fit(make_model("freefall"), t, y)
    >>> f = fit(cur.model.with_effect("drift"), t, y)
    >>> abs(step_score(cur, f.residual, f.n_params, t) - (cur.bic - f.bic)) < 1e-9
    True
    """
    n_eff = cur.n_eff
    floor2 = getattr(cur, "floor2", 0.0)   # cur.rss includes it (fitting.fit)
    plain = float(n_eff * np.log(max(cur.rss, 1e-300) / _sum_sq(resid, floor2))
                  + (cur.n_params - n_params) * np.log(max(n_eff, 1)))
    if np.ndim(t) != 1:
        return plain
    coefs = noise_filter(resid)
    if len(coefs) == 0:
        return plain
    e_cur, e_new = prewhiten(cur.residual, coefs), prewhiten(resid, coefs)
    n = max(n_eff - len(coefs), 1)
    return float(n * np.log(_sum_sq(e_cur, floor2) / _sum_sq(e_new, floor2))
                 + (cur.n_params - n_params) * np.log(n))
