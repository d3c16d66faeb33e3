"""A model = a preset or user function + the effects added to it + parameter starts and bounds."""
from __future__ import annotations

import difflib
import inspect
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from typing import Callable

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.mismatch.effects import EFFECTS, applicable, apply_generic
from odnn_sep.mismatch.presets import PRESETS, ModelIntegrationError, integrate_ode


def suggest_name(word, options):
    """A "did you mean ...? " hint for a misspelt name, or an empty string when nothing is close.

    Parameters
    ----------
    word : str
        The name the user gave.
    options : iterable of str
        The valid names.

    Returns
    -------
    str
        ``"did you mean 'x'? "`` for the closest option, else ``""``.

    Examples
    --------
    >>> suggest_name("osciallator", ["oscillator", "pendulum"])
    "did you mean 'oscillator'? "
    >>> suggest_name("zzz", ["oscillator"])
    ''
    """
    close = difflib.get_close_matches(str(word), list(options), n=1, cutoff=0.5)
    return f"did you mean {close[0]!r}? " if close else ""


@dataclass(frozen=True)
class Model:
    """Immutable model description; ``predict(t, p)`` evaluates it.

    Build one with :func:`make_model` (preset name), :func:`custom_model` (a callable
    ``f(t, **params)``) or :func:`ode_model` (a right-hand side ``rhs(t, state, **params)``).

    Examples
    --------
    >>> import numpy as np
    >>> m = make_model("freefall", {"g": 10.0, "h0": 5.0})
    >>> m.name, m.family, m.free
    ('freefall', 'freefall', ['g', 'h0'])
    >>> m.predict(np.array([0.0, 1.0])).tolist()
    [5.0, 0.0]
    >>> m.with_effect("quadratic_drag").effects
    ('quadratic_drag',)
    """

    name: str
    family: str
    start: dict
    bounds: dict
    fixed: frozenset
    builder: Callable = field(repr=False)
    native: frozenset = frozenset()
    effects: tuple = ()
    ndim: int = 1
    autonomous: bool = True
    preset: object = field(default=None, repr=False)

    @property
    def free(self) -> list:
        """Names of the parameters a fit adjusts (every start that is not fixed), in order.

        Examples
        --------
        >>> make_model("pendulum").free
        ['w2', 'c', 'theta0', 'omega0']
        """
        return [k for k in self.start if k not in self.fixed]

    def predict(self, t, p=None):
        """Evaluate the model at ``t`` with parameters ``p`` (defaults: the starts).

        Parameters
        ----------
        t : ndarray
            Sample times (or (n, 2) coordinates for a 2D field).
        p : dict, optional
            Parameters (default: ``self.start``).

        Returns
        -------
        ndarray, shape (len(t),)

        Raises
        ------
        ModelIntegrationError
            When the model returns non-finite values.

        Examples
        --------
        >>> import numpy as np
        >>> m = make_model("cooling", {"h": 0.1, "T_ambient": 20.0, "T0": 90.0})
        >>> m.predict(np.array([0.0, 10.0])).round(3).tolist()
        [90.0, 45.752]
        """
        return self.predict_through(t, p, None)

    def predict_through(self, t, p, wrap_inner):
        """:meth:`predict`, with the model's own part (before its generic effects) passed through ``wrap_inner``.

        ``wrap_inner(inner) -> callable`` receives ``inner(t, p)``, the preset or user function with
        its native effects, and returns what the generic effects (offset, pickups, ...) are applied
        to; None applies them to ``inner`` itself. A caller that keeps ``inner``'s results can serve
        a change of a generic effect's parameter without integrating the model again.

        Parameters
        ----------
        t : ndarray
            Sample times (or (n, 2) coordinates).
        p : dict or None
            Parameters (None: ``self.start``).
        wrap_inner : callable or None
            See above.

        Returns
        -------
        ndarray, shape (len(t),)

        Examples
        --------
        >>> import numpy as np
        >>> m = make_model("freefall").with_effect("offset")
        >>> seen = []
        >>> def watch(inner):
        ...     return lambda t, p: seen.append(1) or inner(t, p)
        >>> t = np.array([0.0, 0.5])
        >>> bool(np.array_equal(m.predict_through(t, None, watch), m.predict(t))), len(seen)
        (True, 1)
        """
        p = dict(self.start if p is None else p)
        t = np.asarray(t, dtype=float)
        t0 = float(t[0]) if t.ndim == 1 else 0.0
        generic = [e for e in self.effects if e not in self.native]
        inner = self.builder(self.effects)
        fn = apply_generic(generic, inner if wrap_inner is None else wrap_inner(inner), t0=t0)
        out = np.asarray(fn(t, p), dtype=float)
        if out.shape != (len(t),):
            raise InputError(f"model {self.name!r} returned shape {out.shape}; expected ({len(t)},) to match t")
        if not np.all(np.isfinite(out)):
            raise ModelIntegrationError(f"model {self.name!r} returned non-finite values with parameters "
                                        f"{ {k: v for k, v in p.items() if not isinstance(v, str)} }; "
                                        f"check the starting values (--param)")
        return out

    def canonical(self, p: dict) -> dict | None:
        """The same curve's parameters in the preset's canonical labelling, or None when ``p`` is canonical.

        Parameters
        ----------
        p : dict
            Parameters.

        Returns
        -------
        dict or None

        Examples
        --------
        >>> m = make_model("cooling").with_effect("two_body_heat")
        >>> p = {"h": 0.5, "T_ambient": 20.0, "T0": 90.0, "B_2": 10.0, "lam_2": 0.1}   # slow second body
        >>> m.canonical(p)
        {'h': 0.1, 'T_ambient': 20.0, 'T0': 90.0, 'B_2': 60.0, 'lam_2': 0.5}
        >>> m.canonical(m.canonical(p)) is None
        True
        """
        if self.preset is None:
            return None
        return self.preset.canonical(self.effects, p)

    def applicable_effects(self) -> list:
        """Effects of the vocabulary that apply to this model's family and are not in it yet.

        Examples
        --------
        >>> make_model("freefall").with_effect("drift").applicable_effects()
        ['linear_damping', 'quadratic_drag', 'periodic_pickup', 'step_offset', 'time_delay']
        """
        return [e for e in applicable(self.family) if e not in self.effects and self._offers(e)]

    def _offers(self, effect):
        return self.preset is None or not hasattr(self.preset, "offers") or self.preset.offers(effect)

    def with_effect(self, name: str, start: dict | None = None) -> "Model":
        """A copy of the model with effect ``name`` added (its parameters start at their neutral values).

        Parameters
        ----------
        name : str
            Effect name (see :data:`~odnn_sep.mismatch.effects.EFFECTS`).
        start : dict, optional
            Starting values overriding the neutral ones.

        Returns
        -------
        Model

        Raises
        ------
        InputError
            For an unknown effect, or ``channel_coupling`` (which needs the other channels).

        Examples
        --------
        >>> m = make_model("freefall").with_effect("quadratic_drag", {"q_drag": 0.02})
        >>> m.effects, m.start["q_drag"]
        (('quadratic_drag',), 0.02)
        """
        if name not in EFFECTS:
            raise InputError(f"unknown effect {name!r}; {suggest_name(name, EFFECTS)}"
                             f"known effects: {', '.join(EFFECTS)}")
        if name == "channel_coupling":
            raise InputError("channel_coupling needs the recording's other channels: pass aux={name: array} "
                             "to explain() (the CLI does this for multichannel files)")
        if not self._offers(name):
            raise InputError(f"effect {name!r} is not available for model {self.name!r} on this record: it needs "
                             f"the audio engine (a uniformly sampled hum record of more than 40000 samples)")
        eff = EFFECTS[name]
        new_start = dict(self.start)
        new_start.update(eff.params)
        if start:
            new_start.update(start)
        bounds = dict(self.bounds)
        bounds.update(eff.bounds)
        if self.preset is not None and hasattr(self.preset, "effect_bounds"):
            bounds.update(self.preset.effect_bounds(name))
        fixed = self.fixed | frozenset(eff.discrete)
        return replace(self, start=new_start, bounds=bounds, fixed=fixed, effects=self.effects + (name,))

    def with_start(self, values: dict) -> "Model":
        """A copy of the model with some starting values replaced.

        Parameters
        ----------
        values : dict
            New starting values.

        Returns
        -------
        Model

        Examples
        --------
        >>> make_model("freefall").with_start({"g": 9.0}).start
        {'g': 9.0, 'h0': 1.0}
        """
        s = dict(self.start)
        s.update(values)
        return replace(self, start=s)


def _driven_preset(key, preset, inputs, start):
    """A copy of ``preset`` driven by ``inputs``; their gains join ``start`` (at 0)."""
    from odnn_sep.mismatch.inputs import DRIVEN_PRESETS, gain_names
    if key not in DRIVEN_PRESETS:
        raise InputError(f"measured inputs (--input) drive the presets {', '.join(DRIVEN_PRESETS)} and user "
                         f"ODE models; model {key!r} takes none")
    import copy
    preset = copy.copy(preset)
    preset.inputs = dict(inputs)
    start.update({g: 0.0 for g in gain_names(inputs)})
    return preset


def _structural_starts(key, preset, start):
    """Starts of the parameters a structural setting creates (hum amplitudes, heat2d source strengths)."""
    if key == "hum":
        for n in preset.amplitude_names(start["harmonics"]):
            start.setdefault(n, 0.0)
    if key == "heat2d":
        from odnn_sep.mismatch.presets import parse_sources
        for i in range(len(parse_sources(start["sources"]))):
            start.setdefault(f"S{i + 1}", 1.0)
        start.update({k: v for k, v in preset.extra_params(start).items() if k not in start})


def make_model(name: str, params: dict | None = None, *, inputs: dict | None = None) -> Model:
    """Build a preset model; ``params`` are starting guesses (unknown names raise with a suggestion).

    ``inputs`` ({name: (t, u)}, see :mod:`odnn_sep.mismatch.inputs`) drive the oscillator,
    pendulum or cooling preset; each gets a gain ``kd_<name>``.

    Parameters
    ----------
    name : str or Model
        Preset name (``oscillator``, ``pendulum``, ``cooling``, ``hum``, ``heat2d``, ``freefall``);
        a Model gets ``params`` as new starts.
    params : dict, optional
        Starting values (or structural settings such as ``harmonics``, ``sources``).
    inputs : dict, optional
        Measured inputs ``{name: (t, u)}``.

    Returns
    -------
    Model

    Raises
    ------
    InputError
        For an unknown preset or parameter, or inputs to a preset that takes none.

    Examples
    --------
    >>> m = make_model("oscillator", {"k": 4.0})
    >>> m.free
    ['k', 'c', 'x0', 'v0']
    """
    if isinstance(name, Model):
        return name.with_start(params or {})
    key = str(name)
    if key not in PRESETS:
        raise InputError(f"unknown model {key!r}; {suggest_name(key, PRESETS)}"
                         f"available presets: {', '.join(PRESETS)}")
    preset = PRESETS[key]
    start = dict(preset.params)
    params = dict(params or {})
    if inputs:
        preset = _driven_preset(key, preset, inputs, start)
    _check_param_names(key, preset, params, start)
    start.update(_coerce_params(params))
    _structural_starts(key, preset, start)
    return Model(name=key, family=preset.family, start=start, bounds=dict(preset.bounds),
                 fixed=frozenset(preset.fixed), builder=preset.build, native=preset.native,
                 ndim=preset.ndim, autonomous=preset.autonomous and not inputs, preset=preset)


def _check_param_names(key, preset, params, start):
    """Every given parameter is one the preset knows (hum amplitudes and heat2d strengths included)."""
    allowed = set(start)
    if key == "hum":
        allowed |= set(preset.amplitude_names(int(float(params.get("harmonics", start["harmonics"])))))
    if key == "heat2d":
        from odnn_sep.mismatch.presets import parse_sources
        n_src = len(parse_sources(params.get("sources", start["sources"])))
        allowed |= {f"S{i + 1}" for i in range(n_src)} | set(preset.extra_params({**start, **params}))
    for k in params:
        if k not in allowed:
            raise InputError(f"unknown parameter {k!r} for model {key!r}; {suggest_name(k, allowed)}"
                             f"parameters: {', '.join(sorted(allowed))}")


def _coerce_params(params):
    """Given parameters as the preset stores them: sources a string, harmonics a count, the rest floats."""
    out = {}
    for k, v in params.items():
        if k == "sources":
            out[k] = str(v)
        elif k == "harmonics":
            h = int(float(v))
            if h < 1 or h != float(v):
                raise InputError(f"harmonics must be a positive integer (number of harmonics); got {v!r}")
            out[k] = h
        else:
            try:
                out[k] = float(v)
            except (TypeError, ValueError):
                raise InputError(f"parameter {k!r} must be a number; got {v!r}") from None
    return out


def _check_user_params(func, params, what):
    if not params:
        raise InputError(f"{what} needs params={{name: starting value}} for the parameters to calibrate")
    for k, v in params.items():
        try:
            float(v)
        except (TypeError, ValueError):
            raise InputError(f"parameter {k!r} must be a number; got {v!r}") from None
    try:
        sig = inspect.signature(func)
    except (TypeError, ValueError):
        return
    has_kw = any(p.kind == p.VAR_KEYWORD for p in sig.parameters.values())
    if not has_kw:
        names = list(sig.parameters)
        for k in params:
            if k not in names:
                raise InputError(f"unknown parameter {k!r} for the user model; {suggest_name(k, names)}"
                                 f"its signature accepts: {', '.join(names)}")


def custom_model(func: Callable, params: dict, *, bounds: dict | None = None, fixed: Iterable[str] = (),
                 name: str = "user") -> Model:
    """Wrap ``func(t, **params) -> y`` as a model; the generic effects apply to it.

    Parameters
    ----------
    func : callable
        ``func(t, **params) -> y`` with ``y`` of the shape of ``t``.
    params : dict
        Starting values of the parameters to calibrate.
    bounds : dict, optional
        ``{name: (lo, hi)}``.
    fixed : iterable of str, optional
        Parameters kept at their start.
    name : str, optional
        Model name in reports.

    Returns
    -------
    Model

    Examples
    --------
    >>> import numpy as np
    >>> m = custom_model(lambda t, a, b: a * np.exp(-b * t), {"a": 1.0, "b": 0.5})
    >>> m.predict(np.array([0.0, 1.0])).round(3).tolist()
    [1.0, 0.607]
    """
    _check_user_params(func, params, "custom_model")
    start = {k: float(v) for k, v in params.items()}
    from odnn_sep.mismatch.user_checks import check_options
    check_options(start, bounds, fixed, "custom_model")

    def builder(effects):
        def predict(t, p):
            try:
                return func(t, **{k: p[k] for k in start})
            except (ArithmeticError, ValueError, FloatingPointError) as exc:
                raise ModelIntegrationError(f"model {name!r} failed to evaluate with parameters "
                                            f"{ {k: p[k] for k in start} }: {exc}") from None
        return predict

    return Model(name=name, family="user", start=start, bounds=dict(bounds or {}), fixed=frozenset(fixed),
                 builder=builder, autonomous=False)


def ode_model(rhs: Callable, params: dict, state0: Sequence[float | str], *, output: int = 0,
              bounds: dict | None = None, fixed: Iterable[str] = (), name: str = "user_ode",
              inputs: dict | None = None) -> Model:
    """Wrap an ODE ``rhs(t, state, **params) -> dstate/dt`` as a model observed through ``state[output]``.

    ``state0`` lists the initial state: numbers, or names of entries of ``params`` (refitted).
    ``inputs`` ({name: (t, u)}) are measured inputs: ``rhs`` receives each one's value at the
    current time as a keyword argument of that name (linear interpolation between samples).

    Parameters
    ----------
    rhs : callable
        ``rhs(t, state, **params) -> dstate/dt``.
    params : dict
        Starting values of the parameters to calibrate (initial-state names included).
    state0 : sequence of float or str
        Initial state.
    output : int, optional
        Observed state component.
    bounds : dict, optional
        ``{name: (lo, hi)}``.
    fixed : iterable of str, optional
        Parameters kept at their start.
    name : str, optional
        Model name in reports.
    inputs : dict, optional
        Measured inputs ``{name: (t, u)}``.

    Returns
    -------
    Model

    Examples
    --------
    >>> import numpy as np
    >>> m = ode_model(lambda t, s, k: [-k * s[0]], {"k": 1.0, "T0": 2.0}, ["T0"])
    >>> float(m.predict(np.array([0.0, 1.0]))[1].round(3))
    0.736
    """
    start = {k: float(v) for k, v in params.items()}
    if not start:
        raise InputError("ode_model needs params={name: starting value} for the parameters to calibrate")
    for s in state0:
        if isinstance(s, str) and s not in start:
            raise InputError(f"state0 entry {s!r} is not a parameter; {suggest_name(s, start)}"
                             f"parameters: {', '.join(start)}")
    rhs_names = [k for k in start if k not in {s for s in state0 if isinstance(s, str)}]
    from odnn_sep.mismatch.inputs import check_inputs, interpolator
    from odnn_sep.mismatch.user_checks import check_options, check_rhs
    check_options(start, bounds, fixed, "ode_model")
    ins = check_inputs(inputs, None) if inputs else {}
    check_rhs(rhs, start, state0, output, list(ins))
    at = {k: interpolator(tu, u) for k, (tu, u) in ins.items()}
    builder = _ode_builder(name, rhs, state0, output, rhs_names, at, list(start))
    return Model(name=name, family="user", start=start, bounds=dict(bounds or {}), fixed=frozenset(fixed),
                 builder=builder, autonomous=False)


def _ode_builder(name, rhs, state0, output, rhs_names, at, names):
    """``builder(effects) -> predict(t, p)`` integrating ``rhs`` with the inputs ``at`` ({name: u(t)})."""
    def builder(effects):
        def predict(t, p):
            y0 = [p[s] if isinstance(s, str) else float(s) for s in state0]
            kw = {k: p[k] for k in rhs_names}

            def f(tt, s):
                return rhs(tt, s, **kw, **{k: g(tt) for k, g in at.items()})
            from odnn_sep.mismatch.user_checks import check_derivative_count
            try:
                first = f(float(t[0]), np.asarray(y0, float))
            except (ArithmeticError, ValueError, TypeError):
                first = y0      # the integration below says what failed
            check_derivative_count(name, first, state0)
            try:
                return integrate_ode(name, f, y0, t, p)[:, output]
            except (ArithmeticError, ValueError, TypeError) as exc:
                raise ModelIntegrationError(f"model {name!r} failed to integrate with parameters "
                                            f"{ {k: p[k] for k in names} }: {exc}") from None
        return predict
    return builder
