"""Several series of one system fitted jointly: shared parameters once, the others per series.

Five mugs cooling in one room share the room's temperature but each has its own heat-transfer
rate and starting temperature; several releases of one pendulum share its frequency and damping
but each has its own release angle. The joint model stacks the series on one axis (series ``i``
is shifted to start after series ``i - 1`` ends) and evaluates the preset on each series' own
times with the shared parameters plus that series' own ones, named ``<param>_<series>``.

Which parameters are shared (:data:`SHARED`; ``shared=`` overrides):

========== ======================== =====================================
preset     shared                   per series
========== ======================== =====================================
cooling    T_ambient (one room)     h, T0
freefall   g (one planet)           h0
oscillator k, c (one oscillator)    x0, v0
pendulum   w2, c (one pendulum)     theta0, omega0
========== ======================== =====================================

An effect's parameters are shared: one missing law for every series (radiation, drag, a cubic
stiffness). The slow wander class of the oscillatory presets is taken per series. Only the effects that enter the preset's own equations are tested; the additive ones
(offset, drift, a periodic pickup) would need one copy per series.
"""
from __future__ import annotations

import re

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.mismatch.presets_base import Preset

SHARED = {"cooling": ("T_ambient",), "freefall": ("g",), "oscillator": ("k", "c"), "pendulum": ("w2", "c")}
MAX_SERIES = 50        # each series adds its own parameters to one fit
MIN_POINTS = 8         # fewest samples per series (and at least 3 more than its own parameters)


def series_label(name):
    """A parameter-name-safe label of a series name (letters, digits, underscores).

    Examples
    --------
    >>> series_label("mug A.csv"), series_label("3")
    ('mug_A_csv', 's3')
    """
    lab = re.sub(r"\W+", "_", str(name)).strip("_") or "series"
    return lab if lab[0].isalpha() else f"s{lab}"


class JointPreset(Preset):
    """A preset evaluated on several stacked series with some parameters shared.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.presets import PRESETS
    >>> series = {"a": np.array([0.0, 10.0]), "b": np.array([5.0, 15.0])}
    >>> jp = JointPreset(PRESETS["cooling"], {"h": 0.05, "T_ambient": 20.0, "T0": 90.0}, series, ("T_ambient",))
    >>> sorted(jp.params), sorted(jp.fixed)          # h and T0: the series' median (fixed)
    (['T0', 'T0_a', 'T0_b', 'T_ambient', 'h', 'h_a', 'h_b'], ['T0', 'h'])
    >>> p = {"T_ambient": 20.0, "h_a": 0.1, "T0_a": 90.0, "h_b": 0.0, "T0_b": 50.0}
    >>> np.round(jp.build(())(jp.stacked_times(), p), 3).tolist()
    [90.0, 45.752, 50.0, 50.0]
    """

    def __init__(self, base, start, series_times, shared):
        self.base = base
        self.name, self.family, self.description = base.name, base.family, base.description
        self.native, self.ndim, self.autonomous = base.native, base.ndim, base.autonomous
        self.series_names = [str(n) for n in series_times]
        self.labels = [series_label(n) for n in series_times]
        if len(set(self.labels)) != len(self.labels):
            raise InputError(f"series names {list(series_times)} give the same parameter label twice; "
                             f"rename the series")
        self.shared = tuple(shared)
        self.own = [k for k in start if k not in self.shared and k not in base.fixed]
        # the base names of the per-series parameters stay in the model, fixed at the series' median:
        # effect start rules read them (a second body's rate starts from the cooling rate h)
        self.fixed = frozenset(base.fixed) | frozenset(self.own)
        self.t_first = [float(np.asarray(t)[0]) for t in series_times.values()]
        spans = [float(np.ptp(t)) for t in series_times.values()]
        steps = [float(np.median(np.diff(t))) for t in series_times.values()]
        self.offsets = np.concatenate([[0.0], np.cumsum([s + d for s, d in zip(spans, steps, strict=True)])])[:-1]
        self.series_times = [np.asarray(t, float) for t in series_times.values()]
        self.params = dict(start)
        self._suffixed = {f"{k}_{lab}" for k in self.own for lab in self.labels}
        for lab in self.labels:
            self.params.update({f"{k}_{lab}": start[k] for k in self.own})
        self.bounds = {}
        for k, b in base.bounds.items():
            names = [k] if k in self.shared else [f"{k}_{lab}" for lab in self.labels]
            self.bounds.update({n: b for n in names})

    def stacked_times(self):
        """The joint axis: each series' times shifted to follow the previous series."""
        return np.concatenate([t - t0 + off for t, t0, off in zip(self.series_times, self.t_first, self.offsets,
                                                                   strict=True)])

    def series_params(self, p, i):
        """The base preset's parameters of series ``i`` (shared, own, and every effect parameter)."""
        lab = self.labels[i]
        q = {k: v for k, v in p.items() if k not in self._suffixed}
        q.update({k: p[f"{k}_{lab}"] for k in self.own})
        return q

    def build(self, effects):
        inner = self.base.build(effects)

        def predict(t, p):
            t = np.asarray(t, float)
            which = np.searchsorted(self.offsets, t, side="right") - 1
            out = np.empty(len(t))
            for i in np.unique(which):
                sel = which == i
                out[sel] = inner(t[sel] - self.offsets[i] + self.t_first[i], self.series_params(p, i))
            return out

        return predict

    def initial_guess(self, t, y, p):
        which = np.searchsorted(self.offsets, t, side="right") - 1
        out, shared_guesses = {}, {k: [] for k in self.shared}
        for i, lab in enumerate(self.labels):
            sel = which == i
            g = self.base.initial_guess(self.series_times[i], y[sel], self.series_params(p, i))
            out.update({f"{k}_{lab}": float(g[k]) for k in self.own if k in g})
            for k in self.shared:
                if k in g:
                    shared_guesses[k].append(float(g[k]))
        out.update({k: float(np.median(v)) for k, v in shared_guesses.items() if v})
        out.update({k: float(np.median([out[f"{k}_{lab}"] for lab in self.labels]))
                    for k in self.own if all(f"{k}_{lab}" in out for lab in self.labels)})
        return out


def joint_model(name, series, *, params=None, shared=None):
    """The joint Model of preset ``name`` over ``series`` ({name: (t, y)}) and the stacked (t, y).

    Parameters
    ----------
    name : str
        Preset (cooling, freefall, oscillator, pendulum).
    series : dict
        ``{series name: (t, y)}``.
    params : dict, optional
        Starting values of the preset's parameters (every series starts from them).
    shared : sequence of str, optional
        Shared parameters (default :data:`SHARED`).

    Returns
    -------
    model : Model
    t, y : ndarray
        The stacked axis and values.

    Raises
    ------
    InputError
        Unknown preset or shared name, too many series, a series too short.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 30)
    >>> s = {f"mug{i}": (t, 20 + 70 * np.exp(-h * t)) for i, h in enumerate((0.02, 0.03))}
    >>> m, tj, yj = joint_model("cooling", s)
    >>> m.free, len(tj)
    (['T_ambient', 'h_mug0', 'T0_mug0', 'h_mug1', 'T0_mug1'], 60)
    """
    from odnn_sep.mismatch.model import Model, make_model, suggest_name
    if name not in SHARED:
        raise InputError(f"joint series are fitted for the presets {', '.join(SHARED)}; got model {name!r}")
    base_model = make_model(name, params)
    shared = tuple(SHARED[name] if shared is None else shared)
    for k in shared:
        if k not in base_model.free:
            raise InputError(f"shared parameter {k!r} is not a parameter of {name!r}; "
                             f"{suggest_name(k, base_model.free)}parameters: {', '.join(base_model.free)}")
    _check_series(series, len([k for k in base_model.free if k not in shared]))
    jp = JointPreset(base_model.preset, base_model.start, {n: s[0] for n, s in series.items()}, shared)
    m = Model(name=name, family=base_model.family, start=dict(jp.params), bounds=dict(jp.bounds), fixed=jp.fixed,
              builder=jp.build, native=jp.native, ndim=1, autonomous=base_model.autonomous, preset=jp)
    return m, jp.stacked_times(), np.concatenate([np.asarray(s[1], float) for s in series.values()])


def _check_series(series, n_own):
    if len(series) < 2:
        raise InputError(f"a joint fit needs at least 2 series; got {len(series)}")
    if len(series) > MAX_SERIES:
        raise InputError(f"at most {MAX_SERIES} series are fitted jointly (each adds its own parameters); "
                         f"got {len(series)}: fit them in groups")
    need = max(MIN_POINTS, n_own + 3)
    for nm, (t, y) in series.items():
        if len(t) != len(y) or not np.all(np.isfinite(y)):
            raise InputError(f"series {nm!r}: {len(t)} times but {len(y)} values, or non-finite values; "
                             f"give one finite value per time stamp")
        if len(t) < need:
            raise InputError(f"series {nm!r} has {len(t)} points; each series needs at least {need} "
                             f"(it has {n_own} parameters of its own)")
        if np.any(np.diff(t) <= 0):
            raise InputError(f"series {nm!r}: time must be strictly increasing; sort each series by time")
    _refuse_repeated_series(series)


def _refuse_repeated_series(series):
    """The same record given twice (one file under two names, a series column copied): its noise would
    count twice and every shared interval would narrow by about sqrt(2) with no new information.
    Distinct recordings never agree at every sample; a constant series (a held value) is left alone."""
    seen = {}
    for nm, (_, y) in series.items():
        y = np.asarray(y, float)
        if np.ptp(y) == 0:
            continue
        key = (len(y), float(y[0]), float(y[-1]))
        for other in seen.get(key, []):
            if np.array_equal(series[other][1], y):
                raise InputError(f"series {other!r} and {nm!r} hold the same {len(y)} values: the same record "
                                 f"given twice would count its noise twice and narrow every interval; give "
                                 f"each record once")
        seen.setdefault(key, []).append(nm)


def explain_joint(name, series, *, params=None, shared=None, **options):
    """explain() of several series jointly; the result carries ``joint`` (the preset) for the report.

    Parameters
    ----------
    name : str
        Preset.
    series : dict
        ``{series name: (t, y)}``.
    params, shared
        As in :func:`joint_model`.
    **options
        explain()'s options (``folds``, ``disturbance``, ``unit``, ...); ``effects`` default to the
        preset's own (shared-law) effects.

    Returns
    -------
    MismatchResult

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 40); rng = np.random.default_rng(0)
    >>> s = {f"mug{i}": (t, 21 + 70 * np.exp(-h * t) + 0.05 * rng.normal(size=40)) for i, h in enumerate((0.02, 0.04))}
    >>> res = explain_joint("cooling", s)
    >>> res.effects, round(res.final_fit.params["T_ambient"], 1)
    ([], 21.0)
    """
    from odnn_sep.mismatch.long_record import subsample_series
    from odnn_sep.mismatch.timescale_result import explain_joint_in_caller_units
    series, long_note = subsample_series(series)   # long series: bounded subsamples, fitted as a whole
    rescaled = explain_joint_in_caller_units(name, series, params, shared, options)
    if rescaled is not None:   # times far from seconds-like: each series on t / 1000^k, reported in t's units
        if long_note:
            rescaled.notes.insert(0, long_note)
        return rescaled
    from odnn_sep.mismatch.effects import EFFECTS, applicable
    from odnn_sep.mismatch.explain import explain
    m, t, y = joint_model(name, series, params=params, shared=shared)
    own_effects = [e for e in applicable(m.family) if e in m.native and not EFFECTS[e].generic]
    effects = options.pop("effects", None)
    if effects is not None:
        bad = [e for e in effects if e not in own_effects]
        if bad:
            raise InputError(f"effects {bad} cannot be tested on joint series (one law for every series); "
                             f"allowed: {', '.join(own_effects)}")
    disturbance = options.pop("disturbance", "auto")
    if isinstance(disturbance, str) and disturbance in ("auto", "slow"):
        disturbance = _slow_blocks(name, series, params, disturbance)
    res = explain(m, t, y, effects=effects if effects is not None else own_effects, disturbance=disturbance,
                  **options)
    res.joint = m.preset
    if long_note:
        res.notes.insert(0, long_note)
    res.notes.append(f"{len(series)} series fitted jointly; shared: {', '.join(m.preset.shared) or 'none'}; "
                     f"per series: {', '.join(m.preset.own)}; effect parameters are shared")
    return res


def _slow_blocks(name, series, params, disturbance):
    """The slow wander class of each series on its own rows (oscillatory presets, or ``slow``), else the option.

    One slow band over the stacked axis would tie series together that only share a room or a rig.
    """
    from odnn_sep.mismatch.calibrate import SLOW_FAMILIES, slow_disturbance
    from odnn_sep.mismatch.model import make_model
    m = make_model(name, params)
    if disturbance == "auto" and m.family not in SLOW_FAMILIES:
        return "none"
    blocks = [slow_disturbance(np.asarray(t, float), y=np.asarray(y, float), model=m) for t, y in series.values()]
    G = np.zeros((sum(len(b) for b in blocks), sum(b.shape[1] for b in blocks)))
    r = c = 0
    for b in blocks:
        G[r:r + len(b), c:c + b.shape[1]] = b
        r, c = r + len(b), c + b.shape[1]
    return G


def joint_estimates(res):
    """Shared and per-series estimates of a joint result with their 95 % intervals, as a dict.

    Parameters
    ----------
    res : MismatchResult
        From :func:`explain_joint`.

    Returns
    -------
    dict
        ``{"shared": {param: [value, lo, hi]}, "series": {series: {param: [value, lo, hi]}}}``;
        effect parameters are among the shared ones.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 100, 40); rng = np.random.default_rng(0)
    >>> s = {f"mug{i}": (t, 21 + 70 * np.exp(-h * t) + 0.05 * rng.normal(size=40)) for i, h in enumerate((0.02, 0.04))}
    >>> est = joint_estimates(explain_joint("cooling", s))
    >>> list(est["shared"]), sorted(est["series"]["mug1"]), round(est["series"]["mug1"]["h"][0], 3)
    (['T_ambient'], ['T0', 'h'], 0.04)
    """
    jp = res.joint
    fit = res.final_fit or res.calibration.fit
    iv = fit.intervals()

    def entry(name):
        lo, hi = iv.get(name, (np.nan, np.nan))
        return [float(fit.params[name]), float(lo), float(hi)]

    suffixed = {f"{k}_{lab}" for k in jp.own for lab in jp.labels}
    shared = {k: entry(k) for k in fit.model.free if k not in suffixed}
    per = {name: {k: entry(f"{k}_{lab}") for k in jp.own}
           for name, lab in zip(jp.series_names, jp.labels, strict=True)}
    return {"shared": shared, "series": per}


def joint_text(est):
    """Plain-text table of :func:`joint_estimates` (shared first, then one line per series).

    Examples
    --------
    >>> print(joint_text({"shared": {"T_ambient": [21.0, 20.9, 21.1]},
    ...                   "series": {"mug0": {"h": [0.02, 0.019, 0.021]}}}))
    Joint fit: shared parameters
      T_ambient = 21  [95%: 20.9, 21.1]
    Per series:
      mug0: h = 0.02 [0.019, 0.021]
    """
    def iv(lo, hi, label=""):
        # a spread the fit could not determine has no interval (nan): never printed as one
        return "[interval not determined]" if not (np.isfinite(lo) and np.isfinite(hi)) else f"[{label}{lo:.4g}, {hi:.4g}]"

    lines = ["Joint fit: shared parameters"]
    lines += [f"  {k} = {v:.4g}  {iv(lo, hi, '95%: ')}" for k, (v, lo, hi) in est["shared"].items()]
    lines.append("Per series:")
    for name, ps in est["series"].items():
        lines.append(f"  {name}: " + "; ".join(f"{k} = {v:.4g} {iv(lo, hi)}" for k, (v, lo, hi) in ps.items()))
    return "\n".join(lines)
