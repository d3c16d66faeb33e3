"""explain(): calibrate, locate, then add effects one at a time while the data support them.

Decision rule (fixed in advance, calibrated on simulated nulls in ``recipes/bench_mismatch.py``
with seeds disjoint from the evaluation cases):

1. forward selection: every applicable effect is refitted on top of the current model (at first
   the calibrated one); its evidence is the BIC drop against the current model (``score``),
   with both residuals prewhitened by the AR(p) filter of the refit's residual when that noise is
   red (plain BIC for white noise: see :func:`~odnn_sep.mismatch.rivals.step_score`).
   Effects with a discrete choice (which harmonic) pay log(choices) instead of log(n) for it;
2. the best few by score are cross-validated on interleaved contiguous blocks (the model never
   sees the held-out blocks). The held-out gain is the drop of held-out squared error in units of
   the noise variance, ``(SSE_current - SSE_effect) / sigma^2``: an effect that only fits noise
   makes it negative;
3. the best-scoring effect with ``score > bic_threshold`` and held-out gain above
   ``heldout_threshold`` joins the model, and the rest are tested again on top of it;
4. effects the data cannot tell apart from an additive disturbance (an additive periodic
   component, an offset, a drift) join the model as *disturbances*: absorbed and reported in
   plain words, never named as physics. ``periodic_forcing`` (forcing through the dynamics) is
   eligible only when it beats the additive periodic component by the same BIC threshold;
5. backward check: with two or more named effects, each must still pass both thresholds
   against the model without it; one that does not is dropped;
6. rival check: each named effect is compared with the other physics candidates that passed at
   its step, each refitted in its place in the final model; the best prewhitened score is named
   and rivals within 6 of it are reported as equivalent (:mod:`odnn_sep.mismatch.rivals`).
"""
from __future__ import annotations

import logging
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.errors import InputError, as_float_array
from odnn_sep.mismatch.calibrate import Calibration, calibrate, disturbance_columns
from odnn_sep.mismatch.candidates import Candidate, FailedFit  # noqa: F401  (re-exported)
from odnn_sep.mismatch.coupling import EFFECT as COUPLING
from odnn_sep.mismatch.coupling import check_aux, coupling_regressors, coupling_start, with_coupling
from odnn_sep.mismatch.disturbances import parse_disturbance, periodic_columns, residual_lines
from odnn_sep.mismatch.effects import DISTURBANCE_EFFECTS, EFFECTS
from odnn_sep.mismatch.fitting import cross_validate, cv_folds
from odnn_sep.mismatch.locate import locate
from odnn_sep.mismatch.model import Model, make_model
from odnn_sep.mismatch.resolution import resolution
from odnn_sep.mismatch.selection import SelectionSetup, forward_backward
from odnn_sep.mismatch.spikes_series import record_spikes, spikes_entries

log = logging.getLogger(__name__)

BIC_THRESHOLD = 10.0
HELDOUT_THRESHOLD = 6.0
N_CV = 2
MAX_EFFECTS = 4
SMALL_DATA = 60   # below this many samples the held-out test has little power (reported as a note)


@dataclass
class MismatchResult:
    """What explain() found: ``named`` physics effects (in order), ``disturbances``, failed fits.

    ``effect``/``effects`` give the names, ``verdict`` the first named Candidate, ``as_dict()`` the
    JSON report (see :func:`~odnn_sep.mismatch.report.result_dict`).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 300)
    >>> y = 20 + 70 * np.exp(-0.03 * t) + 0.05 * np.random.default_rng(1).normal(size=300)
    >>> res = explain("cooling", t, y)
    >>> res.effect, res.effects, res.verdict, res.disturbances
    (None, [], None, [])
    >>> round(res.calibration.fit.params["h"], 3), sorted(res.final_intervals)
    (0.03, ['T0', 'T_ambient', 'h'])
    """

    t: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    model: Model = field(repr=False)
    calibration: Calibration = field(repr=False)
    where: list = field(default_factory=list)
    candidates: list = field(default_factory=list)   # first-step candidates, best first
    named: list = field(default_factory=list)        # Candidate per named physics effect, in order
    disturbances: list = field(default_factory=list)  # dicts: effect, parameters, sentence, ...
    failed: list = field(default_factory=list)       # FailedFit per effect fit that failed
    final_fit: object = field(default=None, repr=False)
    heldout_rmse_before: float | None = None
    heldout_rmse_after: float | None = None
    noise_sigma: float | None = None
    aux_channels: list = field(default_factory=list)
    declared: list = field(default_factory=list)     # declared disturbances (sentences)
    dropped: list = field(default_factory=list)      # effects removed by the backward check
    unit: str = ""
    warnings: list = field(default_factory=list)     # non-physical fitted values, in words
    notes: list = field(default_factory=list)        # how the data were analysed (decimation, ...)
    subsample: dict | None = None                    # a long record fitted on every step-th sample: step, record

    @property
    def verdict(self):
        """The first named effect (a Candidate) or None; kept for scripts written for one effect."""
        return self.named[0] if self.named else None

    @property
    def effect(self):
        """Name of the first named effect, or None when nothing is missing (see the class example)."""
        return None if not self.named else self.named[0].effect

    @property
    def effects(self) -> list:
        """Names of every named physics effect, in the order they were added (see the class example)."""
        return [c.effect for c in self.named]

    @property
    def final_intervals(self) -> dict:
        """95 % intervals of the final fit (the calibration when nothing was added): ``{name: (lo, hi)}``."""
        return (self.final_fit or self.calibration.fit).intervals()

    def as_dict(self) -> dict:
        """The JSON-ready report, :func:`~odnn_sep.mismatch.report.result_dict` of this result."""
        from odnn_sep.mismatch.report import result_dict
        return result_dict(self)


# A final residual under this many times the record's resolution (resolution.py) is rounding: the
# record is reproduced exactly (a simulation compared with a simulation).
EXACT_FIT = 10.0


def _validate(t, y, model):
    if np.ndim(t) == 2 and isinstance(model, Model) and model.ndim != 2:
        raise InputError(f"model {model.name!r} describes a time series, but the data are a 2-D field "
                         f"(coordinates of shape {np.shape(t)}); use --model heat2d for a field, or give a CSV "
                         f"with a time column")
    if isinstance(model, Model) and model.ndim == 2 or np.ndim(t) == 2:
        t = as_float_array("t (coordinates)", t, ndim=(2,))
        if t.shape[1] != 2:
            raise InputError(f"2D coordinates must have shape (n, 2); got {t.shape}")
    else:
        t = as_float_array("t", t, ndim=(1,))
    y = as_float_array("y", y, ndim=(1,))
    if len(t) != len(y):
        raise InputError(f"model/data length mismatch: t has {len(t)} samples but y has {len(y)}; "
                         f"pass one time stamp per observation")
    if t.ndim == 1:
        d = np.diff(t)
        if np.any(d <= 0):
            i = int(np.argmax(d <= 0)) + 1
            raise InputError(f"time must be strictly increasing; t[{i}] = {t[i]:g} follows t[{i - 1}] = "
                             f"{t[i - 1]:g}; sort the data by time and remove duplicate time stamps")
    if len(y) > 1 and np.all(y == y[0]):
        # every model fits a constant exactly with its rates undetermined: nothing to test
        raise InputError(f"the record is constant (all {len(y)} values are {y[0]:g}): there is nothing for a "
                         f"model to explain; check that the right column was read (CLI: --column)")
    return t, y


def explain(model, t, y, *, params=None, effects=None, disturbance="auto", aux=None, folds=4, blocks_per_fold=5,
            bic_threshold=BIC_THRESHOLD, heldout_threshold=HELDOUT_THRESHOLD, n_cv=N_CV, alpha=0.05,
            max_effects=MAX_EFFECTS, unit="", inputs=None, progress=False, despike=True):
    """Find where a model and data disagree, name the missing effect, and refit with it.

    Parameters
    ----------
    model : str or Model
        A preset name (``oscillator``, ``pendulum``, ``cooling``, ``hum``, ``heat2d``, ``freefall``)
        or a model from :func:`custom_model` / :func:`ode_model`.
    t : array (n,) or (n, 2)
        Time stamps (strictly increasing), or 2D coordinates for ``heat2d``.
    y : array (n,)
        Observations.
    params : dict, optional
        Starting guesses for the model's parameters (all are refitted except structural ones).
    effects : list of str, optional
        Restrict the candidate effects (default: every effect that applies to the model).
    disturbance : str or array (n, q)
        Declared disturbances, comma-separated: the wander class ``auto`` (default: the slow band
        for oscillatory models), ``slow`` or ``none``; ``periodic:HZ`` (a known line, absorbed
        exactly); ``lines`` (every significant spectral line of the calibrated residual is
        absorbed). Or an (n, q) array of disturbance columns. Declared disturbances are never named.
    aux : dict name -> array (n,), or array (n, k), optional
        The recording's other channels, sampled with ``y`` (``hum`` preset only). They make the
        ``channel_coupling`` effect a candidate: ``y`` may contain ``kappa_<name>`` times the
        channel's non-hum content plus ``kappaq_<name>`` times its Hilbert transform (crosstalk;
        see :mod:`odnn_sep.mismatch.coupling`).
    max_effects : int
        At most this many effects and disturbances join the model (forward-selection steps).
    unit : str
        Unit of ``y`` for the plain-language descriptions (e.g. "m", "degC").
    inputs : dict name -> array (n,), optional
        Measured inputs driving a preset (oscillator, pendulum, cooling): each enters the
        equation with its own fitted gain ``kd_<name>`` (see :mod:`odnn_sep.mismatch.inputs`).
        User ODE models take them in :func:`ode_model` instead.
    despike : bool
        Repair isolated outliers of the calibrated residual before any effect is tested
        (:mod:`odnn_sep.mismatch.spikes`); they are listed among the disturbances.

    Returns
    -------
    MismatchResult

    Notes
    -----
    Why long (parameter list): these are the analysis's public keyword options, each documented
    above; the work itself is done by the helpers below and :func:`forward_backward`.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch import make_model
    >>> t = np.linspace(0, 0.6, 120)
    >>> truth = make_model("freefall", {"g": 9.81, "h0": 2.0}).with_effect("quadratic_drag", {"q_drag": 0.02})
    >>> y = truth.predict(t) + 0.001 * np.random.default_rng(0).normal(size=120)
    >>> res = explain("freefall", t, y)
    >>> res.effect, round(res.verdict.fit.params["q_drag"], 2)
    ('quadratic_drag', 0.02)
    """
    options = {k: v for k, v in locals().items() if k not in ("model", "t", "y")}
    from odnn_sep.core.threads import one_blas_thread
    with one_blas_thread():     # many small solves: BLAS threads only add contention (core/threads.py)
        return _explain(model, t, y, **options)


def _explain(model, t, y, *, params, effects, disturbance, aux, folds, blocks_per_fold, bic_threshold,
             heldout_threshold, n_cv, alpha, max_effects, unit, inputs, progress, despike):
    """The body of :func:`explain` (same options, all given)."""
    options = {k: v for k, v in locals().items() if k not in ("model", "t", "y")}
    from odnn_sep.mismatch.long_record import check_hum_harmonics, explain_on_subsample
    check_hum_harmonics(model, t, params)
    subsampled = explain_on_subsample(model, t, y, options)   # a long record: fitted on a bounded subsample
    if subsampled is not None:
        return subsampled
    from odnn_sep.mismatch.clock import explain_from_first_sample
    shifted = explain_from_first_sample(model, t, y, options)   # a free fall timed by a far-off clock
    if shifted is not None:
        return shifted
    from odnn_sep.mismatch.timescale_result import explain_in_caller_units
    rescaled = explain_in_caller_units(model, t, y, options)
    if rescaled is not None:   # time far from seconds-like: analysed on t / 1000^k, reported in t's units
        return rescaled
    from odnn_sep.mismatch.hum_engine import explain_on_audio_engine
    on_bands = explain_on_audio_engine(model, t, y, options)   # long hum audio: the lines' basebands
    if on_bands is not None:
        return on_bands
    m, t, y, aux, rate_note = _prepare(model, t, y, params, inputs, aux)
    t, y, aux, saturation = _drop_saturated(m, t, y, aux)
    block_id = cv_folds(len(y), folds=folds, blocks_per_fold=blocks_per_fold)
    G, cal, declared, periodic_declared = _declared_disturbances(disturbance, m, t, y, params)
    # a joint model's series are each repaired on their own (spikes_series.py)
    spikes = record_spikes(m, t, cal.fit.residual, floor=resolution(y)) if despike else None
    if spikes is not None:
        # the record as analysed from here on: every fit, test and interval sees the repaired samples
        y = spikes.repaired(y)
        G, cal, declared, periodic_declared = _declared_disturbances(disturbance, m, t, y, params)
    base = cal.fit
    res = MismatchResult(t=t, y=y, model=m, calibration=cal, declared=declared, unit=unit)
    if rate_note:
        res.notes.append(rate_note)
    if len(y) < SMALL_DATA:
        res.notes.append(f"only {len(y)} samples: the held-out test ({folds} folds) has little power, so a "
                         f"missing effect of moderate size may go unnamed; 'nothing missing' is weak evidence here")
    from odnn_sep.mismatch.record_notes import record_notes
    res.notes.extend(record_notes(m, t, y))
    from odnn_sep.mismatch.locate import noise_sigma
    # a record the model reproduces to rounding has no noise to measure against (resolution.py)
    res.noise_sigma = max(noise_sigma(base.residual), resolution(y))
    res.where = locate(t, base.residual, sigma=res.noise_sigma, alpha=alpha)
    names = _candidate_names(m, effects, aux, G, periodic_declared)
    res.aux_channels = list(aux)
    slow_hz = 0.0
    if G is not None and np.ndim(t) == 1:
        from odnn_sep.mismatch.calibrate import slow_cutoff
        slow_hz = slow_cutoff(t, y, m)
    mse0 = _quiet_cross_validate(base, t, y, G, block_id, folds)
    res.heldout_rmse_before = float(np.sqrt(mse0[np.isfinite(mse0)].mean()))
    setup = SelectionSetup(t=t, y=y, G=G, make_model=_candidate_factory(t, y, aux, G, slow_hz), block_id=block_id,
                           folds=folds, bic_threshold=bic_threshold, heldout_threshold=heldout_threshold, n_cv=n_cv,
                           max_steps=max_effects, progress=progress)
    out = forward_backward(base, mse0, names, setup)
    res.candidates, res.failed, res.final_fit, res.dropped = out.first_step, out.failed, out.fit, out.dropped
    res.heldout_rmse_after = out.heldout_rmse if out.heldout_rmse is not None else res.heldout_rmse_before
    res.named = [c for c in out.accepted if c.effect not in DISTURBANCE_EFFECTS]
    res.disturbances = [_disturbance_entry(c, out.fit, unit) for c in out.accepted
                        if c.effect in DISTURBANCE_EFFECTS]
    if spikes is not None:
        res.disturbances.extend(spikes_entries(spikes, m, t, unit))
    if saturation is not None:
        res.disturbances.append(saturation.entry(unit))
    from odnn_sep.mismatch.identifiability import unidentified_warnings
    from odnn_sep.mismatch.inputs import physical_warnings
    res.warnings = physical_warnings(out.fit.params) + unidentified_warnings(base, out.fit)
    floor = resolution(y)
    if out.fit.rms <= EXACT_FIT * floor:
        res.notes.append(f"the final model reproduces the record to its numerical resolution (residual RMS "
                         f"{out.fit.rms:.3g}): the record has no noise, so the intervals show rounding, not a spread")
    return res


def _drop_saturated(m, t, y, aux):
    """Leave out the samples held at a rail of the sensor (see :mod:`odnn_sep.mismatch.saturation`);
    time series of one record only (not fields, not joint series)."""
    from odnn_sep.mismatch.saturation import find_saturation
    if np.ndim(t) != 1 or hasattr(getattr(m, "preset", None), "series_times"):
        return t, y, aux, None
    sat = find_saturation(y)
    if sat is None:
        return t, y, aux, None
    aux = {k: np.asarray(v)[sat.keep] for k, v in aux.items()} if aux else aux
    return t[sat.keep], y[sat.keep], aux, sat


def _prepare(model, t, y, params, inputs, aux):
    """The model (with its inputs), checked data and aux channels, at the analysis rate (+ a note)."""
    if inputs and isinstance(model, Model):
        raise InputError("inputs of a user model are given to ode_model(..., inputs=...); "
                         "explain(inputs=...) drives the presets")
    if inputs:
        from odnn_sep.mismatch.inputs import check_inputs
        t_arr = as_float_array("t", t, ndim=(1,))
        inputs = check_inputs(inputs, t_arr)
    m = make_model(model, params, inputs=inputs) if not isinstance(model, Model) \
        else model.with_start(params or {})
    t, y = _validate(t, y, m)
    aux = check_aux(aux, len(y))
    from odnn_sep.mismatch.rate import reduce_rate
    t, y, aux, rate_note = reduce_rate(m, t, y, aux)
    if aux and m.family != "hum":
        raise InputError(f"aux channels are used by the channel_coupling effect of the 'hum' preset only; "
                         f"model {m.name!r} has family {m.family!r}: drop aux (CLI: --no-aux)")
    return m, t, y, aux, rate_note


def _declared_disturbances(disturbance, m, t, y, params):
    """Disturbance columns G (the wander class plus declared lines), the calibration with them
    projected out, the declared disturbances in words, and whether any periodic one was declared."""
    cls, declared_hz, want_lines = parse_disturbance(disturbance)
    G = disturbance_columns(cls if cls is not None else "auto", m, t, y)
    declared = [f"a periodic component at {f:.4g} Hz (declared; absorbed)" for f in declared_hz]
    if declared_hz:
        G = _stack(G, periodic_columns(t, declared_hz))
    cal = calibrate(m, t, y, user_params=params, G=G)
    if want_lines and np.ndim(t) == 1:
        found = residual_lines(t, cal.fit.residual)
        if found:
            G = _stack(G, periodic_columns(t, found))
            cal = calibrate(m, t, y, user_params={**(params or {}), **_numeric(cal.fit.params, m)}, G=G)
        declared.append("spectral lines of the residual (declared 'lines'; absorbed): " +
                        (", ".join(f"{f:.4g} Hz" for f in found) if found else "none found"))
    return G, cal, declared, bool(declared_hz or want_lines)


def _candidate_factory(t, y, aux, G, slow_hz):
    """make_model(e, cur, with_starts=True) -> (model with effect e on top of cur, starts)."""
    def make_candidate_model(e, cur, with_starts=True):
        if e == COUPLING:   # the coupling effect is built from the aux channels
            regs = getattr(cur.model.preset, "coupling", None) or \
                coupling_regressors(t, aux, f0=cur.params["f0"], harmonics=cur.params["harmonics"])
            me = with_coupling(cur.model, regs)
            if not with_starts:
                return me
            return me, [coupling_start(me, cur, t, y, G, regs)]
        from odnn_sep.mismatch.candidates import with_data_bounds
        from odnn_sep.mismatch.starts import effect_starts
        me = with_data_bounds(cur.model.with_effect(e), t, slow_hz)
        if not with_starts:
            return me
        return me, effect_starts(e, cur, t, y, model=me, G=G)
    return make_candidate_model


def _quiet_cross_validate(fit, t, y, G, block_id, folds):
    import warnings

    from odnn_sep.errors import ConvergenceWarning
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        return cross_validate(fit.model, t, y, fit.params, G=G, block_id=block_id, folds=folds)


def _stack(G, P):
    if P is None:
        return G
    return P if G is None else np.column_stack([G, P])


def _numeric(p, m):
    return {k: v for k, v in p.items() if k in m.start and not isinstance(v, str) and k not in m.fixed}


def _candidate_names(m, effects, aux, G, periodic_declared):
    names = m.applicable_effects() if effects is None else list(effects)
    if COUPLING in names and not aux:
        if effects is not None:
            raise InputError("effect 'channel_coupling' needs the recording's other channels: pass aux= "
                             "(the CLI passes the other channels of a multichannel file unless --no-aux)")
        names.remove(COUPLING)
    if G is not None:
        # a slow disturbance class contains a constant and a line: offset and drift are absorbed there
        names = [e for e in names if e not in ("offset", "drift")]
    for e in names:
        if e not in EFFECTS:
            from odnn_sep.mismatch.model import suggest_name
            raise InputError(f"unknown effect {e!r}; {suggest_name(e, EFFECTS)}known effects: {', '.join(EFFECTS)}")
    return names


def _disturbance_entry(c, final, unit):
    """A found disturbance: its parameters (from the final fit), intervals and a plain sentence."""
    from odnn_sep.mismatch.disturbances import describe, linear_model
    p = {k: final.params[k] for k in c.effect_params}
    iv = final.intervals()
    return {"effect": c.effect, "parameters": p, "interval95": {k: list(iv[k]) if k in iv else None for k in p},
            "score": c.score, "heldout_gain": c.heldout_gain, "note": c.note,
            "description": describe(c.effect, final.params, model_family=final.model.family,
                                    linear=linear_model(final.model), unit=unit)}
