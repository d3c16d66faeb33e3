"""Forward selection over the effect library, then a backward check (see explain's decision rule)."""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.errors import ConvergenceWarning
from odnn_sep.mismatch.candidates import Candidate, FailedFit, heldout, passes, refit_robust
from odnn_sep.mismatch.effects import DISTURBANCE_EFFECTS, compatible
from odnn_sep.mismatch.presets import ModelIntegrationError

# the additive stand-in of each effect that a linear model cannot tell from it
# (a release-time offset of a body falling from rest is a drift plus an offset of its height)
EQUIVALENT = {"periodic_forcing": "periodic_pickup", "time_delay": "drift"}

# two physics effects whose BIC scores differ by at most this much, after dividing by the noise's
# low-frequency variance inflation, are reported as equivalent ("the data cannot tell them apart"):
# 2 ln 19 ~ 6 is where the better one reaches 95 % posterior odds (equal priors), matching the 95 %
# intervals. Checked on development seeds 0+ of recipes/bench_mismatch.py: wrong picks there had
# adjusted gaps up to 3.3, right ones from 0.2 up (a drag law or radiation at these strengths is
# often a coin toss)
EQUIVALENCE_GAP = 6.0


def variance_inflation(resid, t) -> float:
    """Low-frequency variance inflation of the residual, ``(1 + rho) / (1 - rho)`` (AR(1), rho >= 0).

    Effect shapes are smooth, so the BIC gap between two of them is driven by the noise at low
    frequencies, whose power AR(1) noise raises by this factor over white noise of the same variance.
    """
    if np.ndim(t) != 1 or len(resid) < 3:
        return 1.0
    r = np.asarray(resid, float) - np.mean(resid)
    den = float(r @ r)
    rho = float(r[1:] @ r[:-1]) / den if den > 0 else 0.0
    rho = min(max(rho, 0.0), 0.95)
    return (1 + rho) / (1 - rho)


def attach_equivalents(chosen, eligible, bic_threshold, t, gap=EQUIVALENCE_GAP):
    """Record on ``chosen`` the passing physics candidates within ``gap`` (inflation-adjusted) of it."""
    if chosen.effect in DISTURBANCE_EFFECTS:
        return
    vif = variance_inflation(chosen.fit.residual, t)
    for c in eligible:
        if c is chosen or c.effect in DISTURBANCE_EFFECTS or c.score <= bic_threshold:
            continue
        d = chosen.score - c.score
        chosen.rivals.append({"effect": c.effect, "bic_gap": float(d), "inflation": float(vif)})
        if d / vif <= gap:
            chosen.equivalent.append(c.effect)


@dataclass
class Selection:
    fit: object
    accepted: list = field(default_factory=list)
    first_step: list = field(default_factory=list)
    failed: list = field(default_factory=list)
    dropped: list = field(default_factory=list)
    heldout_rmse: float | None = None


def _score_step(cur, names, make_model, t, y, G, step, failed, progress):
    cands = []
    it = [e for e in names if compatible(e, cur.model.effects)]
    if progress:
        from tqdm import tqdm
        it = tqdm(names, desc=f"effects (step {step})", leave=False)
    for e in it:
        me, starts = make_model(e, cur)
        f, why = refit_robust(e, me, starts, cur, t, y, G)
        if f is None:
            failed.append(FailedFit(e, why, step))
            continue
        cands.append(Candidate(e, float(cur.bic - f.bic), f, step=step))
    cands.sort(key=lambda c: -c.score)
    return cands


def _additive_alternative_score(c, cur, t, y, G):
    """Score of an additive sinusoid at the fitted forcing frequency (cos/sin projected out exactly),
    counted with as many parameters as the forcing: what the data say without forcing dynamics."""
    from odnn_sep.mismatch.fitting import fit
    w = float(c.fit.params["omega_f"])
    P = np.column_stack([np.cos(w * t), np.sin(w * t)])
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            f = fit(cur.model, t, y, start=cur.params, G=P if G is None else np.column_stack([G, P]), max_nfev=150)
    except ModelIntegrationError:
        return None
    n = c.fit.n_eff
    bic_add = float(n * np.log(max(f.rss, 1e-300) / n) + c.fit.n_params * np.log(n))
    return float(cur.bic - bic_add)


def _demote_equivalents(cands, bic_threshold, cur=None, t=None, y=None, G=None):
    """An effect whose additive stand-in fits as well is not eligible as physics (note why)."""
    by = {c.effect: c for c in cands}
    out = []
    for c in cands:
        if c.effect == "periodic_pickup" and t is not None and np.ndim(t) == 1 and cur is not None:
            from odnn_sep.mismatch.starts import near_system_line
            if near_system_line(c.fit.params["omega_pk"] / (2 * np.pi), cur, t):
                c.note = "at the system's own frequency or a harmonic: not taken as a disturbance"
                continue
        alt = by.get(EQUIVALENT.get(c.effect, ""))
        if c.effect == "periodic_forcing" and cur is not None and c.score > bic_threshold:
            s_add = _additive_alternative_score(c, cur, t, y, G)
            if s_add is not None and (alt is None or s_add > alt.score):
                alt = Candidate("periodic_pickup", s_add, None)
        if alt is not None and c.score - alt.score <= bic_threshold:
            c.note = (f"not significantly better than an additive {alt.effect} (BIC {c.score - alt.score:+.1f}); "
                      f"the data cannot tell them apart")
            continue
        out.append(c)
    return out


def forward_backward(base, mse0, names, make_model, t, y, G, *, block_id, folds, bic_threshold,
                     heldout_threshold, n_cv, max_steps, progress=False) -> Selection:
    """Add the best supported effect while one passes both thresholds; then check each named one."""
    sel = Selection(fit=base)
    cur, cur_mse = base, mse0
    remaining = list(names)
    for step in range(1, max_steps + 1):
        if not remaining:
            break
        cands = _score_step(cur, remaining, make_model, t, y, G, step, sel.failed, progress)
        if step == 1:
            sel.first_step = cands
        eligible = _demote_equivalents(cands, bic_threshold, cur, t, y, G)
        chosen = None
        for c in eligible[:n_cv]:
            if c.score <= bic_threshold:
                break
            heldout(c, cur_mse, t, y, G, block_id, folds)
            if passes(c, bic_threshold, heldout_threshold):
                chosen = c
                break
        if chosen is None:
            break
        attach_equivalents(chosen, eligible, bic_threshold, t)
        sel.accepted.append(chosen)
        cur, cur_mse = chosen.fit, chosen.heldout_mse
        sel.heldout_rmse = chosen.heldout_rmse
        remaining = [e for e in remaining if e != chosen.effect]
    sel.fit = cur
    physics = [c for c in sel.accepted if c.effect not in DISTURBANCE_EFFECTS]
    if len(sel.accepted) >= 2 and physics:
        _backward(sel, base, make_model, t, y, G, block_id, folds, bic_threshold, heldout_threshold)
    return sel


def _rebuild(base, effects, cur, make_model):
    """The model with ``effects`` (in order) on top of ``base``, started at ``cur``'s parameters."""
    m = base
    for e in effects:
        me = make_model(e, m, with_starts=False)
        m = _Stub(me, {**me.start, **{k: v for k, v in cur.params.items() if k in me.start}})
    return m


@dataclass
class _Stub:
    """Just enough of a Fit (model, params) for make_model and refit_robust's start."""

    model: object
    params: dict
    rss: float = np.inf


def _backward(sel, base, make_model, t, y, G, block_id, folds, bic_threshold, heldout_threshold):
    """Drop a named effect that no longer passes both thresholds against the model without it."""
    from odnn_sep.mismatch.fitting import cross_validate

    changed = True
    while changed and len(sel.accepted) >= 2:
        changed = False
        for c in [c for c in sel.accepted if c.effect not in DISTURBANCE_EFFECTS]:
            others = [o.effect for o in sel.accepted if o is not c]
            if "channel_coupling" in others + [c.effect]:
                continue   # its model is built from the aux channels, not by name
            stub = _rebuild(base, others, sel.fit, make_model)
            f, _ = refit_robust("backward", stub.model, [stub.params], _Stub(None, {}, np.inf), t, y, G)
            if f is None:
                continue
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ConvergenceWarning)
                    mse_red = cross_validate(f.model, t, y, f.params, G=G, block_id=block_id, folds=folds)
            except ModelIntegrationError:   # a reduced model that cannot be evaluated keeps c
                continue
            check = Candidate(c.effect, float(f.bic - sel.fit.bic), sel.fit)
            check.heldout_mse = None
            heldout(check, mse_red, t, y, G, block_id, folds)
            if not passes(check, bic_threshold, heldout_threshold):
                sel.dropped.append({"effect": c.effect, "score_against_others": check.score,
                                    "heldout_gain_against_others": check.heldout_gain})
                sel.accepted.remove(c)
                sel.fit = f
                sel.heldout_rmse = float(np.sqrt(np.nanmean(mse_red[np.isfinite(mse_red)])))
                changed = True
                break
            c.backward_score = check.score
