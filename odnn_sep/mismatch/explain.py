"""explain(): calibrate, locate, try every applicable effect, and name the one the data support.

Decision rule (fixed in advance, calibrated on simulated nulls in ``recipes/bench_mismatch.py``
with seeds disjoint from the evaluation cases):

1. each applicable effect is refitted on all data; its evidence is the BIC drop against the
   calibrated model (``score``; positive favours the effect). Effects with a discrete choice
   (which harmonic) pay log(choices) instead of log(n) for it;
2. the best few by score are cross-validated on interleaved contiguous blocks (the model never
   sees the held-out blocks). The held-out gain is the drop of held-out squared error in units of
   the noise variance, ``(SSE_base - SSE_effect) / sigma^2`` (twice a held-out log-likelihood
   ratio): an effect that only fits noise makes it negative. A block-wise Wilcoxon p-value is
   reported too, but not used: a mismatch confined to a few blocks (the first minutes of a
   cooling curve) cannot reach block-count significance however large it is;
3. the verdict is the best-scoring effect with ``score > bic_threshold`` and held-out gain above
   ``heldout_threshold``; otherwise the verdict is null ("nothing missing that the data can show").
"""
from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.errors import ConvergenceWarning, InputError, as_float_array
from odnn_sep.mismatch.calibrate import Calibration, calibrate, disturbance_columns
from odnn_sep.mismatch.coupling import EFFECT as COUPLING
from odnn_sep.mismatch.coupling import check_aux, coupling_regressors, coupling_start, with_coupling
from odnn_sep.mismatch.effects import EFFECTS, effect_param_names
from odnn_sep.mismatch.fitting import cross_validate, cv_folds, fit
from odnn_sep.mismatch.locate import locate
from odnn_sep.mismatch.model import Model, make_model
from odnn_sep.mismatch.presets import ModelIntegrationError
from odnn_sep.mismatch.starts import effect_starts

log = logging.getLogger(__name__)

BIC_THRESHOLD = 10.0
HELDOUT_THRESHOLD = 6.0
N_CV = 2


@dataclass
class Candidate:
    effect: str
    score: float                 # BIC(base) - BIC(with effect)
    fit: object = field(repr=False)
    cv_improvement: float | None = None   # 1 - heldout_rmse(effect) / heldout_rmse(base)
    cv_p_value: float | None = None
    heldout_gain: float | None = None     # (SSE_base - SSE_effect) on held-out blocks / sigma^2
    heldout_rmse: float | None = None

    @property
    def effect_params(self) -> dict:
        return {k: self.fit.params[k] for k in effect_param_names(self.effect, self.fit.params)}

    def as_dict(self) -> dict:
        return {"effect": self.effect, "score": self.score, "parameters": self.effect_params,
                "stderr": {k: self.fit.stderr.get(k) for k in self.effect_params},
                "residual_rms": self.fit.rms, "bic": self.fit.bic,
                "heldout_improvement": self.cv_improvement, "heldout_gain": self.heldout_gain,
                "heldout_p_value": self.cv_p_value}


@dataclass
class MismatchResult:
    """What explain() found. ``verdict`` is the named effect or None; see :meth:`as_dict`."""

    t: np.ndarray = field(repr=False)
    y: np.ndarray = field(repr=False)
    model: Model = field(repr=False)
    calibration: Calibration = field(repr=False)
    where: list = field(default_factory=list)
    candidates: list = field(default_factory=list)
    verdict: Candidate | None = None
    heldout_rmse_before: float | None = None
    noise_sigma: float | None = None
    aux_channels: list = field(default_factory=list)

    @property
    def effect(self):
        return None if self.verdict is None else self.verdict.effect

    def as_dict(self) -> dict:
        from odnn_sep.mismatch.report import result_dict
        return result_dict(self)


def _validate(t, y, model):
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
    return t, y


def _with_data_bounds(m, t, slow_hz=0.0):
    """Frequencies an effect may take are limited by the record: at least 1.5 cycles, below Nyquist.

    A 'modulation' slower than the record is a trend, which the calibration already covers; letting
    it through would make amplitude modulation imitate damping. For oscillatory models the
    modulation must also be slower than half the oscillation frequency (``slow_hz``).
    """
    if np.ndim(t) != 1:
        return m
    T = float(t[-1] - t[0])
    nyq = 0.5 / float(np.median(np.diff(t)))
    b = dict(m.bounds)
    if "f_am" in m.start:
        # a modulation as fast as the carrier is not an envelope: it would stand in for harmonics
        b["f_am"] = (1.5 / T, slow_hz if slow_hz > 1.5 / T else nyq / 4)
    if "omega_f" in m.start:
        # forcing slower than the disturbance class's cut-off is indistinguishable from the disturbance
        b["omega_f"] = (2 * np.pi * max(1.5 / T, slow_hz), 2 * np.pi * nyq)
    from dataclasses import replace
    return replace(m, bounds=b)


def explain(model, t, y, *, params=None, effects=None, disturbance="auto", aux=None, folds=4, blocks_per_fold=5,
            bic_threshold=BIC_THRESHOLD, heldout_threshold=HELDOUT_THRESHOLD, n_cv=N_CV, alpha=0.05, progress=False):
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
    disturbance : {"auto", "slow", "none"} or array (n, q)
        Class the disturbance is confined to during every fit.
    aux : dict name -> array (n,), or array (n, k), optional
        The recording's other channels, sampled with ``y`` (``hum`` preset only). They make the
        ``channel_coupling`` effect a candidate: ``y`` may contain ``kappa_<name>`` times the
        channel's non-hum content plus ``kappaq_<name>`` times its Hilbert transform (crosstalk;
        see :mod:`odnn_sep.mismatch.coupling`).

    Returns
    -------
    MismatchResult

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
    m = make_model(model, params) if not isinstance(model, Model) else model.with_start(params or {})
    t, y = _validate(t, y, m)
    aux = check_aux(aux, len(y))
    if aux and m.family != "hum":
        raise InputError(f"aux channels are used by the channel_coupling effect of the 'hum' preset only; "
                         f"model {m.name!r} has family {m.family!r}: drop aux (CLI: --no-aux)")
    block_id = cv_folds(len(y), folds=folds, blocks_per_fold=blocks_per_fold)
    G = disturbance_columns(disturbance, m, t, y)
    cal = calibrate(m, t, y, user_params=params, G=G)
    slow_hz = 0.0
    if G is not None and np.ndim(t) == 1:
        from odnn_sep.mismatch.calibrate import slow_cutoff
        slow_hz = slow_cutoff(t, y, m)
    base = cal.fit
    res = MismatchResult(t=t, y=y, model=m, calibration=cal)
    from odnn_sep.mismatch.locate import noise_sigma
    res.noise_sigma = noise_sigma(base.residual)
    res.where = locate(t, base.residual, sigma=res.noise_sigma, alpha=alpha)

    names = m.applicable_effects() if effects is None else list(effects)
    if COUPLING in names and not aux:
        if effects is not None:
            raise InputError("effect 'channel_coupling' needs the recording's other channels: pass aux= "
                             "(the CLI passes the other channels of a multichannel file unless --no-aux)")
        names.remove(COUPLING)
    res.aux_channels = list(aux)
    if G is not None:
        # the disturbance class contains a constant and a line: offset and drift are not identifiable
        names = [e for e in names if e not in ("offset", "drift")]
    for e in names:
        if e not in EFFECTS:
            from odnn_sep.mismatch.model import _suggest
            raise InputError(f"unknown effect {e!r}; {_suggest(e, EFFECTS)}known effects: {', '.join(EFFECTS)}")
    it = names
    if progress:
        from tqdm import tqdm
        it = tqdm(names, desc="effects", leave=False)
    cands = []
    for e in it:
        if e == COUPLING:
            regs = coupling_regressors(t, aux, f0=base.params["f0"], harmonics=base.params["harmonics"])
            me = with_coupling(base.model, regs)
            starts = [coupling_start(me, base, t, y, G, regs)]
        else:
            me = _with_data_bounds(base.model.with_effect(e), t, slow_hz)
            starts = effect_starts(e, base, t, y, model=me, G=G)
        best = None
        for s in starts:
            start = dict(me.start)
            start.update(s)
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", ConvergenceWarning)
                    f = fit(me, t, y, start=start, G=G, max_nfev=150)
            except ModelIntegrationError as exc:
                log.debug("effect %s: start failed: %s", e, exc)
                continue
            if best is None or f.rss < best.rss:
                best = f
        if best is None:
            continue
        cands.append(Candidate(e, float(base.bic - best.bic), best))
    cands.sort(key=lambda c: -c.score)

    # held-out check of the strongest candidates (and the base model once)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", ConvergenceWarning)
        mse0 = cross_validate(base.model, t, y, base.params, G=G, block_id=block_id, folds=folds)
        held = np.isfinite(mse0)
        res.heldout_rmse_before = float(np.sqrt(mse0[held].mean()))
        for c in cands[:n_cv]:
            try:
                mse1 = cross_validate(c.fit.model, t, y, c.fit.params, G=G, block_id=block_id, folds=folds)
            except ModelIntegrationError:
                continue
            c.heldout_rmse = float(np.sqrt(mse1[held].mean()))
            c.cv_improvement = float(1.0 - c.heldout_rmse / max(res.heldout_rmse_before, 1e-300))
            d = (mse0 - mse1)[held]
            sizes = np.bincount(block_id)[held]
            sigma2 = c.fit.rss / max(c.fit.n_eff - len(c.fit.free), 1)
            c.heldout_gain = float(np.sum(d * sizes) / max(sigma2, 1e-300))
            if np.all(d == 0):
                c.cv_p_value = 1.0
            else:
                from scipy import stats  # on use: the package is imported by every subcommand

                c.cv_p_value = float(stats.wilcoxon(d, alternative="greater").pvalue)
    res.candidates = cands
    for c in cands:
        if c.score > bic_threshold and c.heldout_gain is not None and c.heldout_gain > heldout_threshold:
            res.verdict = c
            break
    return res
