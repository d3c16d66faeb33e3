"""Preset plumbing: the Preset base class, ODE integration with one clear error, frequency guesses."""
from __future__ import annotations

import warnings

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.core.spectrum import spectrum
from odnn_sep.errors import InputError, ModelIntegrationError  # noqa: F401  (re-exported)

INF = np.inf
# right-hand-side calls one integration may make: a smooth 500-sample pendulum takes about 2400 at
# the tolerance used, a stiff friction law some 10-20 thousand
ODE_CALL_BUDGET = 100_000
ODE_CALLS_PER_SAMPLE = 100
ATOL = 1e-11                  # absolute integration tolerance of a state 1e-3 or larger (see absolute_tolerance)


def integrate_ode(name, rhs, state0, t, p):
    """Integrate ``rhs(t, state)`` with LSODA; any failure raises one :class:`ModelIntegrationError`.

    Parameters
    ----------
    name : str
        Model name, quoted in the error message.
    rhs : callable
        ``rhs(t, state) -> dstate/dt``.
    state0 : sequence of float
        Initial state at ``t[0]``.
    t : ndarray
        Output times (increasing).
    p : dict
        Parameters, shown in the error message.

    Returns
    -------
    ndarray, shape (len(t), len(state0))
        The state at every time.

    Examples
    --------
    >>> import numpy as np
    >>> sol = integrate_ode("decay", lambda t, s: [-s[0]], [1.0], np.array([0.0, 1.0]), {})
    >>> sol.shape, round(float(sol[1, 0]), 4)
    ((2, 1), 0.3679)
    """
    from scipy.integrate import odeint  # on use: the package is imported by every subcommand

    limit = ODE_CALL_BUDGET + ODE_CALLS_PER_SAMPLE * len(t)
    budget = [limit]

    def counted(tt, st):
        # a total budget of calls: mxstep bounds the steps of one output interval only, and a stiff
        # or slowly diverging trial point of an optimiser could otherwise run for many minutes
        budget[0] -= 1
        if budget[0] < 0:
            raise _OverBudget
        return rhs(tt, st)

    with np.errstate(all="ignore"), warnings.catch_warnings():
        # a failure is reported below as one clear error, not as solver chatter
        warnings.simplefilter("ignore")
        try:
            sol, info = odeint(counted, state0, t, full_output=True, mxstep=20000, rtol=1e-9,
                               atol=absolute_tolerance(state0), tfirst=True)
        except _OverBudget:
            sol, info = np.full((len(t), len(state0)), np.nan), {
                "message": f"more than {limit} evaluations of the equations: stiff or diverging"}
    if info.get("message", "").lower().find("successful") < 0 or not np.all(np.isfinite(sol)):
        shown = {k: round(float(v), 6) for k, v in p.items()}
        raise ModelIntegrationError(
            f"model {name!r} failed to integrate with parameters {shown} "
            f"({info.get('message', 'non-finite values')}); check the starting values (--param)")
    return sol


def absolute_tolerance(state0) -> float:
    """The integration's absolute tolerance: 1e-11, or less for a state under 1e-3 in size.

    A motion of nanometres (a cantilever, a seismometer in metres) integrated to 1e-11 absolute
    carries an error of 1 % of itself, as large as its noise. Shrinking the tolerance only for states
    under 1e-3 keeps every other record's integration as it was.

    Parameters
    ----------
    state0 : array_like
        The initial state.

    Returns
    -------
    float

    Examples
    --------
    >>> absolute_tolerance([1.0, 0.0]), f"{absolute_tolerance([1e-9, 0.0]):.1e}"
    (1e-11, '1.0e-17')
    >>> absolute_tolerance([0.0, 0.0])      # a system at rest: driven by its inputs
    1e-11
    """
    size = float(np.max(np.abs(np.asarray(state0, float)))) if np.size(state0) else 0.0
    if not np.isfinite(size) or size == 0.0 or size >= 1e-3:
        return ATOL
    return ATOL * size / 1e-3


class _OverBudget(Exception):
    """Raised from the right-hand side when an integration exceeds its call budget."""


def friction_scale(v_scale):
    """Velocity scale ``eps`` of the smoothed Coulomb friction ``tanh(v / eps)``: 3 % of ``v_scale``.

    Parameters
    ----------
    v_scale : float
        Typical speed of the motion.

    Returns
    -------
    float
        The smoothing scale (at least 3e-11).

    Examples
    --------
    >>> round(friction_scale(2.0), 6)
    0.06
    """
    # tanh(v/eps) replaces sign(v): LSODA cannot step through a discontinuous force.
    return 3e-2 * max(float(v_scale), 1e-9)


class Preset:
    """Base class: ``params`` (name -> default), ``bounds``, ``fixed`` (structural, never refit).

    A subclass implements ``build(effects)``, returning ``predict(t, p) -> y``; it may override
    ``initial_guess`` (data-driven starts) and ``canonical`` (one labelling of symmetric fits).

    Examples
    --------
    >>> import numpy as np
    >>> class Line(Preset):
    ...     name = family = "line"
    ...     params = {"a": 1.0, "b": 0.0}
    ...     def build(self, effects):
    ...         return lambda t, p: p["a"] * t + p["b"]
    >>> Line().build(())(np.array([0.0, 2.0]), {"a": 3.0, "b": 1.0}).tolist()
    [1.0, 7.0]
    >>> Line().initial_guess(None, None, {}), Line().canonical((), {})
    ({}, None)
    """

    name = ""
    family = ""
    description = ""
    params: dict = {}
    bounds: dict = {}
    fixed: frozenset = frozenset()
    native: frozenset = frozenset()   # effects implemented inside the preset's equations
    not_offered: frozenset = frozenset()   # effects of the family this preset cannot evaluate
    autonomous = True
    ndim = 1
    inputs: dict = {}   # measured inputs {name: (t, u)}: set on a per-model copy (see make_model)

    def build(self, effects):
        """The prediction function of the preset with ``effects`` folded in.

        Parameters
        ----------
        effects : iterable of str
            Effects of the model; those in ``native`` enter the equations, the others are ignored
            here (the generic wrapper adds them).

        Returns
        -------
        callable
            ``predict(t, p) -> y``.
        """
        raise NotImplementedError

    def offers(self, effect):
        """Whether the preset implements ``effect`` (an effect of its family it cannot evaluate: False)."""
        return effect not in self.not_offered

    def effect_bounds(self, effect):
        """Bounds of ``effect``'s parameters that depend on the preset's data (default: none)."""
        return {}

    def initial_guess(self, t, y, p):
        """Data-driven starting values for parameters the user did not give (dict, may be partial).

        Parameters
        ----------
        t, y : ndarray
            Sample times (or 2D coordinates) and samples.
        p : dict
            Current starts (user values included).

        Returns
        -------
        dict
        """
        return {}

    def canonical(self, effects, p):
        """Parameters of the same curve in the canonical labelling when ``p`` is another one, else None."""
        return None


def dominant_omega(t, y):
    """Angular frequency of the largest periodogram peak (zero-padded, mean removed).

    Parameters
    ----------
    t : ndarray
        Sample times (uniform or not).
    y : ndarray
        Samples.

    Returns
    -------
    float
        Angular frequency (rad per unit of ``t``) of the peak.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 20, 400)
    >>> round(float(dominant_omega(t, np.cos(3.0 * t))), 1)
    3.0
    """
    n = len(t)
    nfft = int(2 ** np.ceil(np.log2(8 * n)))
    freqs, X = spectrum(t, y - y.mean(), nfft=nfft, taper=True)   # irregular times: non-uniform DFT
    spec = np.abs(X)
    spec[0] = 0
    return 2 * np.pi * freqs[int(np.argmax(spec))]


def sinusoid_start(t, y, omega):
    """Amplitudes (x0, v0) of a pure oscillation at omega matched to the data by least squares.

    Parameters
    ----------
    t : ndarray
        Sample times.
    y : ndarray
        Samples.
    omega : float
        Angular frequency of the oscillation.

    Returns
    -------
    tuple of float
        Initial position ``x0`` and velocity ``v0`` at ``t[0]``.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.linspace(0, 10, 200)
    >>> x0, v0 = sinusoid_start(t, 2.0 * np.cos(t) + 3.0 * np.sin(t), 1.0)
    >>> round(x0, 6), round(v0, 6)
    (2.0, 3.0)
    """
    tau = t - t[0]
    F = np.column_stack([np.cos(omega * tau), np.sin(omega * tau), np.ones_like(tau)])
    coef = solve(F, y, method="lstsq")
    return float(coef[0]), float(coef[1] * omega)
