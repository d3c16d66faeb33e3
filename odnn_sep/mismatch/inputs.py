"""Measured inputs (a drive angle, a heater power, an ambient temperature) fed into a model.

An input column ``u`` enters the model's equation with its own gain ``kd_<name>``:

- oscillator / pendulum: ``m x'' + c x' + k x = sum_j kd_j u_j(t)`` (a driven, damped oscillator);
- cooling: ``dT/dt = -h (T - T_ambient) + sum_j kd_j u_j(t)`` (a heater power, or an ambient
  temperature that follows ``u``: ``h (T_amb(t) - T)`` is the same form);
- user ODEs (:func:`odnn_sep.mismatch.ode_model` with ``inputs=``): the right-hand side receives
  each input's value at the current time as a keyword argument of that name.

Between samples the input is interpolated linearly.
"""
from __future__ import annotations

import bisect

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.core.spectrum import is_uniform
from odnn_sep.errors import InputError

DRIVEN_PRESETS = ("oscillator", "pendulum", "cooling")
MAX_INPUTS = 8
# grid points of the uniform grid a driven linear model is simulated on when its times are irregular
MAX_GRID = 2_000_000


def check_inputs(inputs, t):
    """Validate ``inputs`` (dict name -> array aligned with ``t``) into {name: (t, u)} float arrays.

    Parameters
    ----------
    inputs : dict
        ``{name: u}`` aligned with ``t``, or ``{name: (tu, u)}`` with their own time stamps.
    t : ndarray or None
        Time stamps of the data.

    Returns
    -------
    dict
        ``{name: (tu, u)}`` float arrays.

    Raises
    ------
    InputError
        On a length mismatch, a non-finite value, a bad name or too many inputs.

    Examples
    --------
    >>> ins = check_inputs({"P": [0, 1, 1]}, [0.0, 1.0, 2.0])
    >>> ins["P"][0].tolist(), ins["P"][1].tolist()
    ([0.0, 1.0, 2.0], [0.0, 1.0, 1.0])
    """
    if not inputs:
        return {}
    if len(inputs) > MAX_INPUTS:
        raise InputError(f"{len(inputs)} input columns given; at most {MAX_INPUTS}")
    t = None if t is None else np.asarray(t, float)
    out = {}
    for name, u in inputs.items():
        if isinstance(u, tuple):
            tu, u = (np.asarray(a, float) for a in u)
        elif t is None:
            raise InputError(f"input {name!r}: give a (t, u) pair of arrays (time stamps and values)")
        else:
            tu, u = t, np.asarray(u, float)
        if u.ndim != 1 or len(u) != len(tu):
            raise InputError(f"input {name!r} has {np.size(u)} values but the data have {len(tu)} time stamps; "
                             f"give one input value per sample")
        if not np.all(np.isfinite(u)):
            i = int(np.argmax(~np.isfinite(u)))
            raise InputError(f"input {name!r} has a missing or non-finite value at sample {i}; "
                             f"fill or remove those rows")
        if not str(name).isidentifier():
            raise InputError(f"input name {name!r} must be a plain identifier (letters, digits, _)")
        out[str(name)] = (tu, u)
    return out


def gain_names(inputs) -> list[str]:
    """Names of the gain parameters of the inputs: ``kd_<name>`` each.

    Parameters
    ----------
    inputs : dict or iterable of str
        The inputs (their names).

    Returns
    -------
    list of str

    Examples
    --------
    >>> gain_names({"P": None, "angle": None})
    ['kd_P', 'kd_angle']
    """
    return [f"kd_{name}" for name in inputs]


def interpolator(tu, u):
    """Fast scalar linear interpolation (LSODA calls it thousands of times per integration).

    Parameters
    ----------
    tu, u : array_like
        Time stamps (increasing) and values; held constant outside the record.

    Returns
    -------
    callable
        ``at(tt) -> float`` for a scalar time.

    Examples
    --------
    >>> at = interpolator([0.0, 1.0, 2.0], [0.0, 10.0, 0.0])
    >>> at(0.25), at(1.5), at(-1.0), at(5.0)
    (2.5, 5.0, 0.0, 0.0)
    """
    tl, ul = [float(v) for v in tu], [float(v) for v in u]
    n = len(tl)
    d = np.diff(tu)
    if n > 1 and np.ptp(d) <= 1e-9 * abs(d[0]):
        # uniform grid: the sample index is arithmetic, no search
        t0, step, slope = tl[0], float(d[0]), [b - a for a, b in zip(ul[:-1], ul[1:], strict=True)]

        def at_uniform(tt):
            x = (tt - t0) / step
            i = int(x)
            if i < 0:
                return ul[0]
            if i >= n - 1:
                return ul[-1]
            return ul[i] + (x - i) * slope[i]

        return at_uniform

    def at(tt):
        i = bisect.bisect_right(tl, tt)
        if i <= 0:
            return ul[0]
        if i >= n:
            return ul[-1]
        w = (tt - tl[i - 1]) / (tl[i] - tl[i - 1])
        return ul[i - 1] + w * (ul[i] - ul[i - 1])

    return at


def drive_function(inputs, p):
    """f(tt) = sum_j kd_j u_j(tt), or None without inputs.

    Parameters
    ----------
    inputs : dict
        ``{name: (tu, u)}`` (:func:`check_inputs`).
    p : dict
        Parameters, with the gains ``kd_<name>``.

    Returns
    -------
    callable or None
        ``drive(tt) -> float`` for a scalar time.

    Examples
    --------
    >>> ins = {"P": ([0.0, 1.0], [0.0, 1.0])}
    >>> drive_function(ins, {"kd_P": 2.0})(0.5), drive_function({}, {})
    (1.0, None)
    """
    if not inputs:
        return None
    parts = [(float(p[f"kd_{name}"]), interpolator(tu, u)) for name, (tu, u) in inputs.items()]

    def drive(tt):
        return sum(g * f(tt) for g, f in parts)

    return drive


def drive_on_grid(inputs, p, t):
    """The drive sum_j kd_j u_j evaluated on an array of times.

    Parameters
    ----------
    inputs : dict
        ``{name: (tu, u)}`` (:func:`check_inputs`).
    p : dict
        Parameters, with the gains ``kd_<name>``.
    t : ndarray
        Times.

    Returns
    -------
    ndarray, shape (len(t),)

    Examples
    --------
    >>> import numpy as np
    >>> ins = {"P": (np.array([0.0, 1.0]), np.array([0.0, 1.0]))}
    >>> drive_on_grid(ins, {"kd_P": 2.0}, np.array([0.0, 0.5, 1.0])).tolist()
    [0.0, 1.0, 2.0]
    """
    out = np.zeros(len(t))
    for name, (tu, u) in inputs.items():
        out += float(p[f"kd_{name}"]) * np.interp(t, tu, u)
    return out


def regression_start(t, y, inputs, order):
    """Least-squares start from smoothed derivatives: y'' (order 2) or y' (order 1) on y, y', inputs.

    Returns (coefficients of [y, (y'), 1, u_j ...], ok). A start only: the ODE fit refines it.

    Parameters
    ----------
    t, y : ndarray
        Sample times and samples.
    inputs : dict
        ``{name: (tu, u)}``.
    order : {1, 2}
        Order of the ODE: ``y' = -a y + b + sum g_j u_j`` or ``y'' = -a y - b y' + sum g_j u_j``.

    Returns
    -------
    ndarray
        The coefficients ``[a, b, g_1, ...]``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 20, 401); u = np.where(t > 5, 1.0, 0.0)   # a heater switched on at t = 5
    >>> m = make_model("cooling", {"h": 0.5, "T_ambient": 20.0, "T0": 20.0, "kd_P": 2.0}, inputs={"P": (t, u)})
    >>> np.round(regression_start(t, m.predict(t), {"P": (t, u)}, 1), 1).tolist()   # h, h T_amb, kd_P
    [0.5, 9.9, 2.0]
    """
    from scipy.signal import savgol_filter
    n = len(y)
    dt = float(np.median(np.diff(t)))
    win = max(7, (n // 60) | 1)
    if is_uniform(t):
        def deriv(k):
            return savgol_filter(y, win, 3, deriv=k, delta=dt)
    else:   # irregular times: the smoothing filter needs equal steps, so take it on a uniform grid
        g = np.linspace(float(t[0]), float(t[-1]), n)
        yg = np.interp(g, t, y)

        def deriv(k):
            return np.interp(t, g, savgol_filter(yg, win, 3, deriv=k, delta=float(g[1] - g[0])))
    d1 = deriv(1)
    us = [np.interp(t, tu, u) for tu, u in inputs.values()]
    if order == 2:
        d2 = deriv(2)
        A = np.column_stack([-y, -d1] + us)
        target = d2
    else:
        A = np.column_stack([-y, np.ones(n)] + us)
        target = d1
    coef = solve(A, target, method="lstsq")
    return coef


def physical_warnings(params) -> list[str]:
    """Plain warnings for fitted values outside what the physics allows (kept, not clipped).

    Parameters
    ----------
    params : dict
        Fitted parameters.

    Returns
    -------
    list of str
        One sentence per suspicious value; empty when all are physical.

    Examples
    --------
    >>> physical_warnings({"k": 4.0, "c": 0.1})
    []
    >>> [w.split(":")[0] for w in physical_warnings({"c": -0.2, "h": 0.0})]
    ['negative damping c = -0.2', 'heat-transfer rate h = 0 sits at its physical bound (0)']
    >>> physical_warnings({"r_rad": -0.016})[0].split(":")[0]
    'radiation r_rad = -0.016 is a heat gain'
    """
    out = []
    c = params.get("c")
    if c is not None and not isinstance(c, str) and c < 0:
        out.append(f"negative damping c = {c:.4g}: the fitted system gains energy; a drive the model lacks "
                   f"(measure it and pass --input) or a wrong model is more likely than negative friction")
    for k, what in (("h", "heat-transfer rate"), ("k", "stiffness"), ("w2", "g/L"), ("g", "gravity"),
                    ("alpha", "diffusivity")):
        v = params.get(k)
        if v is not None and not isinstance(v, str) and v <= 0:
            out.append(f"{what} {k} = {v:.4g} sits at its physical bound (0): the model does not describe "
                       f"these data")
    for k, what in (("r_rad", "radiation"), ("e_evap", "evaporation")):
        # signed on purpose (the test is two-sided), so a loss term can come out as a gain
        v = params.get(k)
        if v is not None and not isinstance(v, str) and v < 0:
            out.append(f"{what} {k} = {v:.4g} is a heat gain: a loss term fitted with the wrong sign stands in "
                       f"for some other shape of the curve the model lacks, not for {what}")
    return out


def linear_response(A, B, x0, t, drive):
    """States of the linear system x' = A x + B d(t), x(t0) = x0, on ``t`` (first-order hold on d).

    ``scipy.signal.lsim`` steps with matrix exponentials, exact for a piecewise-linear input: a
    driven linear oscillator or cooling law costs one call instead of an ODE integration.

    Parameters
    ----------
    A : array_like, shape (k, k)
        System matrix.
    B : array_like, shape (k,)
        Input vector.
    x0 : array_like, shape (k,)
        State at ``t[0]``.
    t : ndarray
        Times (increasing).
    drive : ndarray
        ``d(t)`` on ``t``.

    Returns
    -------
    ndarray, shape (len(t), k)

    Examples
    --------
    >>> import numpy as np
    >>> x = linear_response([[-0.5]], [1.0], [0.0], np.array([0.0, 1.0, 2.0]), np.ones(3))
    >>> x.shape, np.round(x[:, 0], 4).tolist()   # 2 (1 - exp(-t / 2))
    ((3, 1), [0.0, 0.7869, 1.2642])
    """
    from scipy.signal import StateSpace, lsim
    A = np.atleast_2d(np.asarray(A, float))
    B = np.asarray(B, float).reshape(-1)
    t = np.asarray(t, float)
    drive = np.asarray(drive, float)
    ss = StateSpace(A, B.reshape(-1, 1), np.eye(A.shape[0]), np.zeros((A.shape[0], 1)))
    if is_uniform(t, tol=1e-9) or len(t) < 3:
        _, _, x = lsim(ss, U=drive, T=t - float(t[0]), X0=np.asarray(x0, float))
        return np.asarray(x, float).reshape(len(t), A.shape[0])
    # irregular times (lsim needs equal steps): a uniform grid of a quarter of the median spacing,
    # the drive interpolated on it, the states brought back to ``t`` by cubic Hermite interpolation
    # with their exact derivatives A x + B d (error of order (omega h)^4)
    span = float(t[-1] - t[0])
    m = int(min(np.ceil(4 * span / float(np.median(np.diff(t)))), MAX_GRID)) + 1
    g = np.linspace(0.0, span, m)
    h = g[1]
    dg = np.interp(g, t - t[0], drive)
    _, _, xg = lsim(ss, U=dg, T=g, X0=np.asarray(x0, float))
    xg = np.asarray(xg, float).reshape(m, A.shape[0])
    vg = xg @ A.T + np.outer(dg, B)
    j = np.clip(((t - t[0]) // h).astype(int), 0, m - 2)
    s_ = ((t - t[0]) - g[j]) / h
    s2, s3 = s_ ** 2, s_ ** 3
    h00, h10, h01, h11 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s_, -2 * s3 + 3 * s2, s3 - s2
    return (h00[:, None] * xg[j] + h10[:, None] * h * vg[j] + h01[:, None] * xg[j + 1]
            + h11[:, None] * h * vg[j + 1])
