"""Forward selection over the effect library, then a backward check (see explain's decision rule)."""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.errors import ConvergenceWarning
from odnn_sep.mismatch.candidates import (
    Candidate,
    FailedFit,
    FitStub,
    heldout,
    passes,
    rebuild_model,
    refit_robust,
)
from odnn_sep.mismatch.effects import DISTURBANCE_EFFECTS, compatible
from odnn_sep.mismatch.presets import ModelIntegrationError
from odnn_sep.mismatch.rivals import recheck_rivals, step_score

# the additive stand-in of each effect that a linear model cannot tell from it
# (a release-time offset of a body falling from rest is a drift plus an offset of its height)
EQUIVALENT = {"periodic_forcing": "periodic_pickup", "time_delay": "drift"}
# the frequency parameter of each additive sinusoid
PICKUP_OMEGA = {"periodic_pickup": "omega_pk", "periodic_pickup_2": "omega_pk2"}

# two physics effects whose BIC scores differ by at most this much, after dividing by the noise's
# low-frequency variance inflation, are reported as equivalent ("the data cannot tell them apart"):
# 2 ln 19 ~ 6 is where the better one reaches 95 % posterior odds (equal priors), matching the 95 %
# intervals. Checked on development seeds 0+ of recipes/bench_mismatch.py: wrong picks there had
# adjusted gaps up to 3.3, right ones from 0.2 up (a drag law or radiation at these strengths is
# often a coin toss)
EQUIVALENCE_GAP = 6.0
# rivals this far behind at their step are not refitted in the final model (each refit of an ODE
# model costs seconds); on development seeds (cooling, free fall) no rival more than 7 behind at its
# step came within 6 on the final model
RECHECK_GAP = 4 * EQUIVALENCE_GAP


def variance_inflation(resid, t) -> float:
    """Low-frequency variance inflation of the residual, ``(1 + rho) / (1 - rho)`` (AR(1), rho >= 0).

    Effect shapes are smooth, so the BIC gap between two of them is driven by the noise at low
    frequencies, whose power AR(1) noise raises by this factor over white noise of the same variance.

    Parameters
    ----------
    resid : ndarray
        Residual.
    t : ndarray
        Sample times (1.0 is returned for a 2D field).

    Returns
    -------
    float
        At least 1 (white or anti-correlated noise), at most 39 (rho capped at 0.95).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(20.0)
    >>> variance_inflation(np.array([1.0, -1.0] * 10), t), round(variance_inflation(np.array([1.0, 1, -1, -1] * 5), t), 3)
    (1.0, 1.105)
    """
    if np.ndim(t) != 1 or len(resid) < 3:
        return 1.0
    r = np.asarray(resid, float) - np.mean(resid)
    den = float(r @ r)
    rho = float(r[1:] @ r[:-1]) / den if den > 0 else 0.0
    rho = min(max(rho, 0.0), 0.95)
    return (1 + rho) / (1 - rho)


def attach_equivalents(chosen, eligible, bic_threshold, t, gap=EQUIVALENCE_GAP):
    """Record on ``chosen`` the passing physics candidates within ``gap`` (inflation-adjusted) of it.

    Appends to ``chosen.rivals`` (every passing physics rival) and ``chosen.equivalent`` in place.

    Parameters
    ----------
    chosen : Candidate
        The effect selected at this step.
    eligible : list of Candidate
        The step's eligible candidates.
    bic_threshold : float
        A rival must score above it.
    t : ndarray or None
        Sample times (for the variance inflation).
    gap : float, optional
        Largest inflation-adjusted BIC gap reported as equivalent.

    Returns
    -------
    None

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> chosen = NS(effect="radiation", score=30.0, fit=NS(residual=[0.0]), rivals=[], equivalent=[])
    >>> eligible = [chosen, NS(effect="evaporation", score=27.0), NS(effect="two_body_heat", score=12.0)]
    >>> attach_equivalents(chosen, eligible, 10.0, None)
    >>> chosen.equivalent, [r["effect"] for r in chosen.rivals]
    (['evaporation'], ['evaporation', 'two_body_heat'])
    """
    if chosen.effect in DISTURBANCE_EFFECTS:
        return
    vif = variance_inflation(chosen.fit.residual, t)
    for c in eligible:
        if c is chosen or c.effect in DISTURBANCE_EFFECTS or c.score <= bic_threshold:
            continue
        d = chosen.score - c.score
        chosen.rivals.append({"effect": c.effect, "bic_gap": float(d), "inflation": float(vif)})
        if hasattr(chosen, "rival_candidates") and d / vif <= RECHECK_GAP:
            chosen.rival_candidates.append(c)
        if d / vif <= gap:
            chosen.equivalent.append(c.effect)


@dataclass(frozen=True)
class SelectionSetup:
    """What every selection step needs besides the current model: the data, the disturbance columns
    ``G``, the candidate-model factory, the held-out split and the thresholds fixed in advance.

    ``make_model(effect, cur)`` returns ``(model, starts)``, and the model alone with
    ``with_starts=False``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import cross_validate, cv_folds, fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60)
    >>> y = 5.0 - 4.9 * t ** 2 + 0.5 * t + 0.001 * np.random.default_rng(0).normal(size=60)
    >>> base = fit(make_model("freefall"), t, y)
    >>> blocks = cv_folds(60, folds=2)
    >>> mse0 = cross_validate(base.model, t, y, base.params, block_id=blocks, folds=2)
    >>> def factory(effect, cur, with_starts=True):
    ...     m = cur.model.with_effect(effect)
    ...     return (m, []) if with_starts else m
    >>> setup = SelectionSetup(t, y, None, factory, blocks, 2, 10.0, 6.0, 2, 3)
    >>> setup.folds, setup.bic_threshold, setup.max_steps
    (2, 10.0, 3)
    """

    t: np.ndarray
    y: np.ndarray
    G: np.ndarray | None
    make_model: object          # (effect, current fit, with_starts=True) -> (model, starts)
    block_id: np.ndarray
    folds: int
    bic_threshold: float
    heldout_threshold: float
    n_cv: int
    max_steps: int
    progress: bool = False


@dataclass
class Selection:
    """Result of :func:`forward_backward`: final fit, accepted candidates, first-step ranking, failures.

    Examples
    --------
    >>> sel = Selection(fit=None)
    >>> sel.accepted, sel.first_step, sel.failed, sel.dropped, sel.heldout_rmse
    ([], [], [], [], None)
    """

    fit: object
    accepted: list = field(default_factory=list)
    first_step: list = field(default_factory=list)
    failed: list = field(default_factory=list)
    dropped: list = field(default_factory=list)
    heldout_rmse: float | None = None


def _score_step(cur, names, setup, step, failed):
    """Every compatible effect refitted on top of ``cur``, best BIC drop first (failed fits to ``failed``)."""
    cands = []
    it = [e for e in names if compatible(e, cur.model.effects)]
    if setup.progress:
        from tqdm import tqdm
        it = tqdm(it, desc=f"effects (step {step})", leave=False)
    for e in it:
        me, starts = setup.make_model(e, cur)
        f, why = refit_robust(e, me, starts, cur, setup.t, setup.y, setup.G)
        if f is None:
            failed.append(FailedFit(e, why, step))
            continue
        cands.append(Candidate(e, step_score(cur, f.residual, f.n_params, setup.t), f, step=step))
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
    return step_score(cur, f.residual, c.fit.n_params, t)


# loss terms: the physics they name removes heat, so a negative coefficient is a heat gain that stands
# in for some other shape of the curve (a slow pickup, a step, a drift), never for that physics
LOSS_TERMS = {"radiation": "r_rad", "evaporation": "e_evap"}


def wrong_sign(c) -> str | None:
    """Why candidate ``c`` is not physics because its loss coefficient came out negative, else None.

    Parameters
    ----------
    c : Candidate
        A refitted candidate (``c.fit.params``).

    Returns
    -------
    str or None
        The note, or None when the effect is not a loss term or its coefficient is >= 0.

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> wrong_sign(NS(effect="radiation", fit=NS(params={"r_rad": -0.001})))[:31]
    'fitted as a heat gain (r_rad = '
    >>> wrong_sign(NS(effect="radiation", fit=NS(params={"r_rad": 0.002}))) is None
    True
    """
    key = LOSS_TERMS.get(c.effect)
    if key is None or c.fit is None:
        return None
    v = c.fit.params.get(key)
    if v is None or not v < 0:
        return None
    return (f"fitted as a heat gain ({key} = {v:.3g}): a loss term with the wrong sign stands in for some "
            f"other shape of the curve, not for {c.effect}")


# a sinusoid near an oscillator's own frequency is the oscillation itself, refitted with another
# frequency or decay (standing in for the physics that shapes it), not a pickup beating with it, when
# it has more than BEAT_MAX_SHARE of the oscillation's amplitude or lies within BEAT_MIN_CELLS
# resolution cells of the own frequency (less than half a beat over the record). Development cases:
# the probe's pickups are 2-15 % of the oscillation and 0.4-6 cells off; a pendulum's own swing was
# taken as a "pickup" of 55 %, and the decay of an oscillator with drag and a cubic stiffness
# (benchmark development seed 0) as one of 21 % at 0.1 cells (the physics then lost)
BEAT_MAX_SHARE = 0.25
BEAT_MIN_CELLS = 0.5


def _own_line(c, cur, t):
    """Whether pickup candidate ``c`` sits on the system's own line: at a harmonic, at the own
    frequency of a family that does not beat (hum), or near a beating family's own frequency with
    the amplitude of the oscillation rather than of a pickup."""
    from odnn_sep.mismatch.starts import BEATING_FAMILIES, system_frequency, system_line_number
    key = PICKUP_OMEGA[c.effect]
    f = c.fit.params[key] / (2 * np.pi)
    k = system_line_number(f, cur, t)
    if k != 1 or cur.model.family not in BEATING_FAMILIES:
        return k > 0
    if abs(f - system_frequency(cur)) * float(t[-1] - t[0]) < BEAT_MIN_CELLS:
        return True
    sfx = key[len("omega_pk"):]
    amp = float(np.hypot(c.fit.params["a_pk" + sfx], c.fit.params["b_pk" + sfx]))
    pred = np.asarray(cur.prediction, float)
    return amp > BEAT_MAX_SHARE * float(np.max(np.abs(pred - np.mean(pred))))


def _demote_equivalents(cands, bic_threshold, cur=None, t=None, y=None, G=None):
    """An effect whose additive stand-in fits as well, or a loss term fitted as a gain, is not eligible
    as physics (note why)."""
    by = {c.effect: c for c in cands}
    out = []
    for c in cands:
        why = wrong_sign(c)
        if why is not None:
            c.note = why
            continue
        if c.effect in PICKUP_OMEGA and t is not None and np.ndim(t) == 1 and cur is not None:
            if _own_line(c, cur, t):
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


def _choose(eligible, cur_mse, setup):
    """The best of the top ``n_cv`` eligible candidates that passes both thresholds, or None."""
    for c in eligible[:setup.n_cv]:
        if c.score <= setup.bic_threshold:
            return None
        heldout(c, cur_mse, setup.t, setup.y, setup.G, setup.block_id, setup.folds)
        if passes(c, setup.bic_threshold, setup.heldout_threshold):
            return c
    return None


def absorb_disturbance_first(chosen, eligible, cur_mse, setup):
    """A disturbance that fits as well as the chosen physics effect is taken first.

    When an additive disturbance (a drift, a pickup, an offset) scores within the equivalence gap of
    the physics effect chosen at this step (the plain BIC gap: a near tie; it is not widened for
    correlated noise, so a physics effect clearly ahead is never deferred), the data cannot tell the
    two apart at this step. The disturbance is then
    absorbed first, and the physics effect is tested again at the next step on top of it: it is named
    only if it still passes both thresholds there.

    Parameters
    ----------
    chosen : Candidate
        The effect chosen at this step (passes both thresholds).
    eligible : list of Candidate
        The step's eligible candidates, best score first.
    cur_mse : ndarray
        Held-out MSE per block of the current model.
    setup : SelectionSetup
        Data, split and thresholds.

    Returns
    -------
    Candidate
        ``chosen``, or the disturbance taken in its place (then ``chosen.note`` says why).

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> import numpy as np
    >>> setup = NS(t=None, bic_threshold=10.0, heldout_threshold=6.0)
    >>> phys = NS(effect="radiation", score=27.1, fit=NS(residual=np.zeros(3)), note=None)
    >>> drift = NS(effect="drift", score=26.9, heldout_gain=20.0)
    >>> absorb_disturbance_first(phys, [phys, drift], None, setup).effect
    'drift'
    >>> absorb_disturbance_first(phys, [phys, NS(effect="drift", score=12.0, heldout_gain=20.0)], None, setup).effect
    'radiation'
    """
    if chosen.effect in DISTURBANCE_EFFECTS:
        return chosen
    for d in eligible:
        if d.effect not in DISTURBANCE_EFFECTS or d.score <= setup.bic_threshold:
            continue
        if chosen.score - d.score > EQUIVALENCE_GAP:
            continue
        if getattr(d, "heldout_gain", None) is None:
            heldout(d, cur_mse, setup.t, setup.y, setup.G, setup.block_id, setup.folds)
        if passes(d, setup.bic_threshold, setup.heldout_threshold):
            chosen.note = (f"no better than the additive {d.effect} (BIC {chosen.score - d.score:+.1f}): the "
                           f"disturbance is absorbed first and {chosen.effect} tested again on top of it")
            return d
    return chosen


def forward_backward(base, mse0, names, setup: SelectionSetup) -> Selection:
    """Add the best supported effect while one passes both thresholds; then check each named one.

    Parameters
    ----------
    base : Fit
        Calibrated model without effects.
    mse0 : ndarray
        Its held-out MSE per block.
    names : list of str
        Effects to try.
    setup : SelectionSetup
        Data, factory, split and thresholds.

    Returns
    -------
    Selection

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import cross_validate, cv_folds, fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60)
    >>> y = 5.0 - 4.9 * t ** 2 + 0.5 * t + 0.001 * np.random.default_rng(0).normal(size=60)
    >>> base = fit(make_model("freefall"), t, y)
    >>> blocks = cv_folds(60, folds=2)
    >>> mse0 = cross_validate(base.model, t, y, base.params, block_id=blocks, folds=2)
    >>> def factory(effect, cur, with_starts=True):
    ...     m = cur.model.with_effect(effect)
    ...     return (m, []) if with_starts else m
    >>> setup = SelectionSetup(t, y, None, factory, blocks, 2, 10.0, 6.0, 2, 3)
    >>> sel = forward_backward(base, mse0, ["drift", "linear_damping"], setup)
    >>> [c.effect for c in sel.accepted], [c.effect for c in sel.first_step], round(sel.fit.params["drift"], 2)
    (['drift'], ['drift', 'linear_damping'], 0.5)
    """
    sel = Selection(fit=base)
    cur, cur_mse = base, mse0
    remaining = list(names)
    for step in range(1, setup.max_steps + 1):
        if not remaining:
            break
        cands = _score_step(cur, remaining, setup, step, sel.failed)
        if step == 1:
            sel.first_step = cands
        eligible = _demote_equivalents(cands, setup.bic_threshold, cur, setup.t, setup.y, setup.G)
        chosen = _choose(eligible, cur_mse, setup)
        if chosen is None:
            break
        chosen = absorb_disturbance_first(chosen, eligible, cur_mse, setup)
        attach_equivalents(chosen, eligible, setup.bic_threshold, setup.t)
        sel.accepted.append(chosen)
        cur, cur_mse = chosen.fit, chosen.heldout_mse
        sel.heldout_rmse = chosen.heldout_rmse
        remaining = [e for e in remaining if e != chosen.effect]
        if chosen.effect == "periodic_pickup":
            remaining.append("periodic_pickup_2")   # a second pickup may be there too
    sel.fit = cur
    if len(sel.accepted) >= 2 and any(c.effect not in DISTURBANCE_EFFECTS for c in sel.accepted):
        _backward(sel, base, setup)
    _drop_wrong_sign(sel, base, setup)
    recheck_rivals(sel, base, setup, EQUIVALENCE_GAP)
    _drop_named_equivalents(sel.accepted)
    return sel


def _drop_named_equivalents(accepted):
    """An effect that is itself named is not an alternative to another named one: both are in the model."""
    named = {c.effect for c in accepted}
    for c in accepted:
        c.equivalent = [e for e in c.equivalent if e not in named]


def _drop_check(c, sel, base, setup):
    """Candidate-like record of ``c`` against the model without it (score, held-out gain), with that
    model's fit and held-out errors; None when the reduced model cannot be fitted or evaluated."""
    from odnn_sep.mismatch.fitting import cross_validate

    others = [o.effect for o in sel.accepted if o is not c]
    stub = rebuild_model(base, others, sel.fit, setup.make_model)
    f, _ = refit_robust("backward", stub.model, [stub.params], FitStub(None, {}, np.inf), setup.t, setup.y, setup.G)
    if f is None:
        return None
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", ConvergenceWarning)
            mse_red = cross_validate(f.model, setup.t, setup.y, f.params, G=setup.G, block_id=setup.block_id,
                                     folds=setup.folds)
    except ModelIntegrationError:   # a reduced model that cannot be evaluated keeps c
        return None
    check = Candidate(c.effect, step_score(f, sel.fit.residual, sel.fit.n_params, setup.t), sel.fit)
    check.heldout_mse = None
    heldout(check, mse_red, setup.t, setup.y, setup.G, setup.block_id, setup.folds)
    return check, f, mse_red


def _drop(sel, c, check, f, mse_red, reason=None):
    """Remove named effect ``c``: record its check against the others, and take the reduced fit."""
    entry = {"effect": c.effect, "score_against_others": check.score,
             "heldout_gain_against_others": check.heldout_gain}
    if reason is not None:
        entry["reason"] = reason
    sel.dropped.append(entry)
    sel.accepted.remove(c)
    sel.fit = f
    sel.heldout_rmse = float(np.sqrt(np.nanmean(mse_red[np.isfinite(mse_red)])))


def _drop_wrong_sign(sel, base, setup):
    """A loss term that ends with the wrong sign in the final model is dropped, as at its own step.

    Its sign is checked when it is chosen; refits on top of it (a second pickup, a drift) and the
    backward check can still turn it into a heat gain, which stands in for some other shape of the
    curve (a cooling null with two pickups ended with radiation r = -0.19)."""
    for c in [c for c in sel.accepted if c.effect in LOSS_TERMS]:
        v = sel.fit.params.get(LOSS_TERMS[c.effect])
        if v is None or not v < 0:
            continue
        out = _drop_check(c, sel, base, setup)
        if out is None:
            continue
        check, f, mse_red = out
        _drop(sel, c, check, f, mse_red,
              reason=f"fitted as a heat gain in the final model ({LOSS_TERMS[c.effect]} = {v:.3g})")


def _backward(sel, base, setup):
    """Drop a named effect that no longer passes both thresholds against the model without it."""
    changed = True
    while changed and len(sel.accepted) >= 2:
        changed = False
        for c in [c for c in sel.accepted if c.effect not in DISTURBANCE_EFFECTS]:
            if "channel_coupling" in [o.effect for o in sel.accepted]:
                continue   # its model is built from the aux channels, not by name
            out = _drop_check(c, sel, base, setup)
            if out is None:
                continue
            check, f, mse_red = out
            if not passes(check, setup.bic_threshold, setup.heldout_threshold):
                _drop(sel, c, check, f, mse_red)
                changed = True
                break
            c.backward_score = check.score
