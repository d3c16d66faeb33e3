"""Effect candidates on top of a current model: robust refits and held-out gains (selection.py ranks them).

Every refit also starts from the current (calibrated) model with the effect at its neutral value,
so a refit can never end worse than the model it extends. One that does anyway (the solver
diverged, the ODE failed) is retried from that start with more evaluations; if it still ends worse,
it is recorded as a failed fit and never ranked.
"""
from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from odnn_sep.errors import ConvergenceWarning
from odnn_sep.mismatch.effects import effect_param_names
from odnn_sep.mismatch.fitting import cross_validate, finish_fit, point_fit
from odnn_sep.mismatch.prediction_memo import exact_key
from odnn_sep.mismatch.presets import ModelIntegrationError

log = logging.getLogger(__name__)


@dataclass
class Candidate:
    """One effect added to the current model: its refit, BIC score and held-out test.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 - 0.3 * t   # free fall + a drift
    >>> cur = fit(make_model("freefall"), t, y)
    >>> f2, why = refit_robust("drift", cur.model.with_effect("drift"), [], cur, t, y, None)
    >>> c = Candidate("drift", cur.bic - f2.bic, f2)
    >>> c.effect, {k: round(v, 6) for k, v in c.effect_params.items()}, c.score > 10
    ('drift', {'drift': -0.3}, True)
    >>> sorted(c.as_dict())[:4]
    ['bic', 'effect', 'equivalent_to', 'heldout_gain']
    """

    effect: str
    score: float                 # BIC(current) - BIC(current + effect)
    fit: object = field(repr=False)
    cv_improvement: float | None = None   # 1 - heldout_rmse(effect) / heldout_rmse(current)
    cv_p_value: float | None = None
    heldout_gain: float | None = None     # (SSE_current - SSE_effect) on held-out blocks / sigma^2
    heldout_rmse: float | None = None
    heldout_mse: object = field(default=None, repr=False)
    step: int = 1                          # forward-selection step at which it was scored
    note: str | None = None
    equivalent: list = field(default_factory=list)   # physics effects the data cannot tell from this one
    rivals: list = field(default_factory=list)       # every other passing physics candidate: gap, inflation
    rival_candidates: list = field(default_factory=list, repr=False)   # those candidates (re-checked at the end)

    @property
    def effect_params(self) -> dict:
        """The effect's own fitted parameters ``{name: value}`` (see the class example)."""
        return {k: self.fit.params[k] for k in effect_param_names(self.effect, self.fit.params)}

    @property
    def intervals(self) -> dict:
        """95 % intervals of the effect's parameters ``{name: (lo, hi) or None}``."""
        iv = self.fit.intervals()
        return {k: iv.get(k) for k in self.effect_params}

    def as_dict(self) -> dict:
        """JSON-ready record: effect, score, parameters, intervals, held-out test, note, equivalents."""
        iv = self.intervals
        return {"effect": self.effect, "score": self.score, "parameters": self.effect_params,
                "stderr": {k: self.fit.reported_stderr(k) for k in self.effect_params},
                "interval95": {k: (list(v) if v is not None else None) for k, v in iv.items()},
                "residual_rms": self.fit.rms, "bic": self.fit.bic, "step": self.step,
                "heldout_improvement": self.cv_improvement, "heldout_gain": self.heldout_gain,
                "heldout_p_value": self.cv_p_value, "note": self.note,
                "equivalent_to": list(self.equivalent)}


@dataclass
class FailedFit:
    """An effect fit that failed (it could not be evaluated, or ended worse than its base model).

    Examples
    --------
    >>> FailedFit("radiation", "the model could not be evaluated from any start").as_dict()
    {'effect': 'radiation', 'reason': 'the model could not be evaluated from any start', 'step': 1}
    """

    effect: str
    reason: str
    step: int = 1

    def as_dict(self) -> dict:
        """JSON-ready record ``{effect, reason, step}``."""
        return {"effect": self.effect, "reason": self.reason, "step": self.step}


def with_data_bounds(m, t, slow_hz=0.0):
    """Frequencies an effect may take are limited by the record: at least 1.5 cycles, below Nyquist.

    A 'modulation' slower than the record is a trend, which the calibration already covers; letting
    it through would make amplitude modulation imitate damping. For oscillatory models the
    modulation must also be slower than half the oscillation frequency (``slow_hz``).

    Parameters
    ----------
    m : Model
        Model with effects.
    t : ndarray
        Sample times (a 2D field is returned unchanged).
    slow_hz : float, optional
        Cut-off of the slow disturbance class (Hz).

    Returns
    -------
    Model
        The model with the frequency bounds of its effects set.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = make_model("oscillator").with_effect("amplitude_modulation")
    >>> with_data_bounds(m, np.linspace(0, 10, 101), slow_hz=0.2).bounds["f_am"]
    (0.15, 0.2)
    """
    if np.ndim(t) != 1:
        return m
    T = float(t[-1] - t[0])
    nyq = 0.5 / float(np.median(np.diff(t)))
    b = dict(m.bounds)
    if "f_am" in m.start:
        # a modulation as fast as the carrier is not an envelope: it would stand in for harmonics
        b["f_am"] = (1.5 / T, slow_hz if slow_hz > 1.5 / T else nyq / 4)
    for key in ("omega_f", "omega_pk"):
        if key in m.start:
            # slower than the disturbance class's cut-off is indistinguishable from the disturbance
            b[key] = (2 * np.pi * max(1.5 / T, slow_hz), 2 * np.pi * nyq)
    return replace(m, bounds=b)


def _quiet_finish(model, t, y, pt, G, max_nfev):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return finish_fit(model, t, y, pt, G=G, max_nfev=max_nfev)


def refit_robust(name, model, starts, cur, t, y, G, *, max_nfev=150):
    """Best fit of ``model`` over ``starts`` plus the current model's own start; (fit, None) or (None, reason).

    Parameters
    ----------
    name : str
        Effect name (for messages).
    model : Model
        Current model plus the effect.
    starts : list of dict
        Starting values to try.
    cur : Fit
        Fit of the current model (the refit must end at least as good).
    t, y : ndarray
        Sample times and samples.
    G : ndarray or None
        Disturbance columns.
    max_nfev : int, optional
        Evaluations per start.

    Returns
    -------
    tuple
        ``(Fit, None)``, or ``(None, reason)`` when every start failed.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 - 0.3 * t   # free fall + a drift
    >>> cur = fit(make_model("freefall"), t, y)
    >>> f2, why = refit_robust("drift", cur.model.with_effect("drift"), [], cur, t, y, None)
    >>> why, round(f2.params["drift"], 6), f2.rss < cur.rss
    (None, -0.3, True)
    """
    base_start = {**model.start, **{k: v for k, v in cur.params.items() if k in model.start}}
    if "t_step" in model.start and np.ndim(t) == 1:
        # the step's instant is held during a fit: at the neutral 0 (or any instant outside the
        # record) it covers every sample or none, a constant offset the step is not (in a cooling
        # record it shifted the temperature scale under evaporation by 24 degrees)
        starts = [s for s in starts if _step_inside({**base_start, **s}["t_step"], t)]
        if not _step_inside(base_start["t_step"], t):
            if not starts:
                return None, "no instant inside the record to place the step at"
            base_start["t_step"] = starts[0]["t_step"]
    # each start needs only its point estimate; the spread and the identifiability profiles (refits
    # of their own) are computed for the best one alone: the same Fit as fitting every start in full
    best, errors, tried = None, [], set()
    for s in list(starts) + [base_start]:
        key = exact_key({**model.start, **s})
        if key is not None and key in tried:
            continue   # the same start fits the same way (a start rule that found nothing gives the base's)
        tried.add(key)
        try:
            f = (point_fit(model, t, y, start={**model.start, **s}, G=G, max_nfev=max_nfev), max_nfev)
        except ModelIntegrationError as exc:
            errors.append(str(exc))
            continue
        if best is None or f[0].rss < best[0].rss:
            best = f
    if best is None or best[0].rss > cur.rss * (1 + 1e-6):
        # worse than the model it extends (which it contains): a failed fit; retry from that model
        try:
            f = (point_fit(model, t, y, start=base_start, G=G, max_nfev=4 * max_nfev), 4 * max_nfev)
            if best is None or f[0].rss < best[0].rss:
                best = f
        except ModelIntegrationError as exc:
            errors.append(str(exc))
    if best is None:
        return None, "the model could not be evaluated from any start" + (f" ({errors[0]})" if errors else "")
    best = _quiet_finish(model, t, y, best[0], G, best[1])
    if _worse_than_penalty(best, cur):
        return None, (f"refit ended worse than the model without it (RSS {best.rss:.4g} > {cur.rss:.4g}) "
                      f"after a retry")
    return best, None


def _step_inside(t_step, t):
    """Whether a step at ``t_step`` changes the level of some samples of ``t`` but not of all.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(5.0)
    >>> _step_inside(2.5, t), _step_inside(0.0, t), _step_inside(9.0, t)
    (True, False, False)
    """
    after = int(np.count_nonzero(np.asarray(t) >= t_step))
    return 0 < after < len(t)


def _worse_than_penalty(f, cur):
    """Whether refit ``f`` ends worse than ``cur`` (which it contains) by more than its BIC penalty.

    Within the penalty it is a fit that found nothing (a score at or below zero, never named), for
    instance a numerically integrated model whose effect-free start differs from the closed-form
    base by the integration error; beyond it the optimiser failed.
    """
    if not np.isfinite(cur.rss):
        return False
    n = max(float(getattr(cur, "n_eff", len(f.residual))), 2.0)
    extra = max(float(f.n_params) - float(getattr(cur, "n_params", f.n_params)), 1.0)
    return n * np.log(max(f.rss, 1e-300) / max(cur.rss, 1e-300)) > extra * np.log(n)


def heldout(c, cur_mse, t, y, G, block_id, folds):
    """Cross-validate candidate ``c`` against the current model's held-out errors ``cur_mse``.

    Sets ``c.heldout_mse``, ``heldout_rmse``, ``cv_improvement``, ``heldout_gain`` and
    ``cv_p_value`` in place (left unset when the held-out fits fail).

    Parameters
    ----------
    c : Candidate
        The candidate.
    cur_mse : ndarray
        Held-out MSE per block of the current model.
    t, y : ndarray
        Sample times and samples.
    G : ndarray or None
        Disturbance columns.
    block_id : ndarray of int
        Block of every sample (:func:`~odnn_sep.mismatch.fitting.cv_folds`).
    folds : int
        Number of folds.

    Returns
    -------
    None

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 - 0.3 * t   # free fall + a drift
    >>> cur = fit(make_model("freefall"), t, y)
    >>> from odnn_sep.mismatch.fitting import cross_validate, cv_folds
    >>> f2, _ = refit_robust("drift", cur.model.with_effect("drift"), [], cur, t, y, None)
    >>> c = Candidate("drift", cur.bic - f2.bic, f2)
    >>> b = cv_folds(60, folds=2)
    >>> heldout(c, cross_validate(cur.model, t, y, cur.params, block_id=b, folds=2), t, y, None, b, 2)
    >>> c.heldout_gain > 6, round(c.cv_p_value, 4), passes(c, 10.0, 6.0)
    (True, 0.0039, True)
    """
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        try:
            mse1 = cross_validate(c.fit.model, t, y, c.fit.params, G=G, block_id=block_id, folds=folds)
        except ModelIntegrationError:
            return
    held = np.isfinite(cur_mse) & np.isfinite(mse1)
    if not held.any():
        return
    c.heldout_mse = mse1
    c.heldout_rmse = float(np.sqrt(mse1[held].mean()))
    c.cv_improvement = float(1.0 - c.heldout_rmse / max(float(np.sqrt(cur_mse[held].mean())), 1e-300))
    d = (cur_mse - mse1)[held]
    sizes = np.bincount(block_id)[held]
    sigma2 = c.fit.rss / max(c.fit.n_eff - len(c.fit.free), 1)
    c.heldout_gain = float(np.sum(d * sizes) / max(sigma2, 1e-300))
    c.cv_p_value = _signed_rank_p(d)


def _signed_rank_p(d):
    """One-sided Wilcoxon signed-rank p-value that the held-out gains ``d`` are positive (1 when all 0)."""
    if np.all(d == 0):
        return 1.0
    from scipy import stats  # on use: the package is imported by every subcommand
    return float(stats.wilcoxon(d, alternative="greater").pvalue)


def passes(c, bic_threshold, heldout_threshold):
    """Whether candidate ``c`` beats both thresholds: BIC drop and held-out gain.

    Parameters
    ----------
    c : Candidate
        The candidate (``heldout_gain`` None fails).
    bic_threshold, heldout_threshold : float
        Thresholds on ``c.score`` and ``c.heldout_gain``.

    Returns
    -------
    bool

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> passes(SimpleNamespace(score=12.0, heldout_gain=7.0), 10.0, 6.0)
    True
    >>> passes(SimpleNamespace(score=12.0, heldout_gain=None), 10.0, 6.0)
    False
    """
    return c.score > bic_threshold and c.heldout_gain is not None and c.heldout_gain > heldout_threshold


@dataclass
class FitStub:
    """Just enough of a Fit (model, params) for a candidate factory and :func:`refit_robust`'s start.

    Examples
    --------
    >>> FitStub(None, {"h": 0.1}).rss
    inf
    """

    model: object
    params: dict
    rss: float = np.inf


def rebuild_model(base, effects, cur, make_model):
    """The model with ``effects`` (in order) on top of ``base``, started at ``cur``'s parameters.

    Parameters
    ----------
    base : Fit
        The calibrated model without effects.
    effects : list of str
        Effects to add, in order.
    cur : Fit or FitStub
        Parameters to start from (where the model has them; the others start at neutral).
    make_model : callable
        Candidate factory ``make_model(effect, fit, with_starts=False) -> Model``.

    Returns
    -------
    FitStub

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60)
    >>> base = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2)
    >>> stub = rebuild_model(base, ["drift"], base, lambda e, f, with_starts: f.model.with_effect(e))
    >>> stub.model.effects, round(stub.params["g"], 3), stub.params["drift"]
    (('drift',), 9.8, 0.0)
    """
    m = base
    for e in effects:
        me = make_model(e, m, with_starts=False)
        m = FitStub(me, {**me.start, **{k: v for k, v in cur.params.items() if k in me.start}})
    return m
