"""Implicit-orthogonality cases of paper App. C.2 and the Figure 2 / Proposition 1 case.

Subspace classes (Periodic, Even) point-identify theta. Cone classes (Convex, Monotone) only
set-identify it: ``x**2 + c sin 5x`` is still convex for small |c|, so every theta in an interval
fits the data exactly. Those datasets carry ``identified="set"`` and the sub-percent errors the paper
reports for them cannot be guaranteed by any method.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core import Basis, Convex, Even, Monotone, Periodic
from odnn_sep.signals.dataset import Dataset, check_n, check_theta, make, pick, rng_from


def _cone_interval(dg: np.ndarray, ds: np.ndarray, theta: float) -> tuple[float, float]:
    """Exact noise-free identified set of theta on the samples.

    ``y - t s = g + (theta - t) s`` is in the cone iff ``dg + c ds >= 0`` for every difference
    (first differences: monotone; second differences: convex), with ``c = theta - t``.
    """
    pos, neg = ds > 1e-15, ds < -1e-15
    c_lo = float(np.max(-dg[pos] / ds[pos])) if pos.any() else -np.inf
    c_hi = float(np.min(-dg[neg] / ds[neg])) if neg.any() else np.inf
    return theta - c_hi, theta - c_lo


def _sin5(x):
    return np.sin(5 * x)


def _x_sin5(x):
    return x * np.sin(5 * x)


def _x2_sin5(x):
    return x**2 * np.sin(5 * x)


def implicit_convex(*, n: int = 400, snr_db: float = 30.0, theta: dict | None = None,
                    random_state: int | None = None) -> Dataset:
    """Convex disturbance: ``y = g(x) + theta sin 5x`` on x in [-2, 2] (paper: ``x^2 + sin 5x``).

    ``g = a x^2 + b x + c + d exp(x/2)`` with a in [0.5, 1.5], d in [0, 0.5] (convex). Class:
    ``Convex()``. Set-identified: ``g + c sin 5x`` stays convex while ``25 |c| <= min g''`` roughly,
    so a whole interval of theta fits; ``extras["identified_set"]`` is that interval, computed
    exactly on the samples (second differences) for the noise-free data.

    Parameters
    ----------
    n : int
        Samples (uniform on [-2, 2]).
    snr_db : float
        Physics-to-noise power ratio in dB.
    theta : dict, optional
        ``{"theta": value}`` to fix the coefficient of sin 5x (else uniform in [0.5, 1.5]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> implicit_convex(random_state=0).identified
    'set'
    """
    n = check_n(n, 20)
    rng = rng_from(random_state)
    check_theta(theta, ["theta"])
    x = np.linspace(-2.0, 2.0, n)
    th = {"theta": pick(rng, theta, "theta", 0.5, 1.5)}
    a, b, c, d = rng.uniform(0.5, 1.5), rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(0, 0.5)
    g = a * x**2 + b * x + c + d * np.exp(x / 2)
    basis = Basis([_sin5], names=["theta"])
    physics = th["theta"] * _sin5(x)
    lo, hi = _cone_interval(np.diff(g, 2), np.diff(_sin5(x), 2), th["theta"])
    desc = ("implicit convex: y = a x^2 + b x + c + d exp(x/2) + theta sin 5x; class Convex(); "
            f"set-identified (without noise every theta in [{lo:.4f}, {hi:.4f}] fits exactly)")
    return make("implicit_convex", x, basis, Convex(), th, physics, g, snr_db, rng, desc, identified="set",
                extras={"identified_set": (lo, hi)})


def implicit_periodic(*, periods: int = 10, per_period: int = 100, snr_db: float = 30.0,
                      theta: dict | None = None, random_state: int | None = None) -> Dataset:
    """Periodic disturbance: ``y = g(x) + theta x sin 5x`` (paper: ``sin 5x + x sin 5x``).

    ``g`` is a random Fourier series with period 2 pi / 5 (harmonics 1-3 plus an offset), so
    ``Periodic(2 pi / 5)`` is exact; x covers ``periods`` whole periods starting at 0, with
    ``per_period`` samples per period so phase averaging is exact.

    Parameters
    ----------
    periods, per_period : int
        Record length in periods and samples per period.
    snr_db : float
        Physics-to-noise power ratio in dB (``inf``: no noise).
    theta : dict, optional
        ``{"theta": value}`` fixes the coefficient (else drawn uniformly from [0.5, 1.5]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = implicit_periodic(random_state=0)
    >>> round(ds.disturbance.period, 4)
    1.2566
    """
    periods = check_n(periods, 2, "periods")
    per_period = check_n(per_period, 4, "per_period")
    rng = rng_from(random_state)
    check_theta(theta, ["theta"])
    P = 2 * np.pi / 5
    x = np.arange(periods * per_period) * (P / per_period)
    th = {"theta": pick(rng, theta, "theta", 0.5, 1.5)}
    g = rng.uniform(-1, 1) + np.sin(5 * x) * rng.uniform(0.5, 1.5)
    for k in (1, 2, 3):
        g = g + rng.uniform(-0.5, 0.5) / k * np.cos(5 * k * x + rng.uniform(0, 2 * np.pi))
    basis = Basis([_x_sin5], names=["theta"])
    physics = th["theta"] * _x_sin5(x)
    desc = "implicit periodic: y = g + theta x sin 5x, g any 2pi/5-periodic function; class Periodic(2pi/5)"
    return make("implicit_periodic", x, basis, Periodic(P), th, physics, g, snr_db, rng, desc)


def implicit_symmetric(*, n: int = 1001, snr_db: float = 30.0, theta: dict | None = None,
                       random_state: int | None = None) -> Dataset:
    """Even disturbance: ``y = g(x) + theta x^2 sin 5x`` on a grid symmetric about 0 (paper:
    ``cos 5x + x^2 sin 5x``).

    ``g = a cos 5x + b x^2 + c cos x + d`` is even, the physics is odd. Class: ``Even(0)``.

    Parameters
    ----------
    n : int
        Samples on [-pi, pi] (end points included, so the grid is symmetric).
    snr_db : float
        Physics-to-noise power ratio in dB (``inf``: no noise).
    theta : dict, optional
        ``{"theta": value}`` fixes the coefficient (else drawn uniformly from [0.5, 1.5]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = implicit_symmetric(random_state=0)
    >>> bool(abs(ds.x[0] + ds.x[-1]) < 1e-12)
    True
    """
    n = check_n(n, 11)
    rng = rng_from(random_state)
    check_theta(theta, ["theta"])
    x = np.linspace(-np.pi, np.pi, n)
    th = {"theta": pick(rng, theta, "theta", 0.5, 1.5)}
    g = (rng.uniform(0.5, 1.5) * np.cos(5 * x) + rng.uniform(-0.3, 0.3) * x**2 + rng.uniform(-1, 1) * np.cos(x)
         + rng.uniform(-1, 1))
    basis = Basis([_x2_sin5], names=["theta"])
    physics = th["theta"] * _x2_sin5(x)
    desc = "implicit symmetric: y = g + theta x^2 sin 5x, g even (cos 5x, x^2, cos x, const); class Even(0)"
    return make("implicit_symmetric", x, basis, Even(0.0), th, physics, g, snr_db, rng, desc)


def implicit_monotone(*, n: int = 400, snr_db: float = 30.0, theta: dict | None = None,
                      random_state: int | None = None) -> Dataset:
    """Monotone disturbance: ``y = g(x) + theta sin 5x`` on x in [-1, 1.5] (paper: ``exp x + sin 5x``).

    ``g = a exp(x) + b x + c`` with a in [0.5, 2], b in [0, 1] (non-decreasing). Class:
    ``Monotone()``. Set-identified: ``g + c sin 5x`` stays monotone for a range of c, so a whole
    interval of theta fits; ``extras["identified_set"]`` is that interval, computed exactly on the
    samples (first differences) for the noise-free data.

    Parameters
    ----------
    n : int
        Samples (uniform on [-1, 1.5]).
    snr_db : float
        Physics-to-noise power ratio in dB (``inf``: no noise).
    theta : dict, optional
        ``{"theta": value}`` fixes the coefficient (else drawn uniformly from [0.5, 1.5]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> implicit_monotone(random_state=0).identified
    'set'
    """
    n = check_n(n, 20)
    rng = rng_from(random_state)
    check_theta(theta, ["theta"])
    x = np.linspace(-1.0, 1.5, n)
    th = {"theta": pick(rng, theta, "theta", 0.5, 1.5)}
    a, b, c = rng.uniform(0.5, 2.0), rng.uniform(0, 1), rng.uniform(-1, 1)
    g = a * np.exp(x) + b * x + c
    basis = Basis([_sin5], names=["theta"])
    physics = th["theta"] * _sin5(x)
    lo, hi = _cone_interval(np.diff(g), np.diff(_sin5(x)), th["theta"])
    desc = ("implicit monotone: y = a exp(x) + b x + c + theta sin 5x; class Monotone(); "
            f"set-identified (without noise every theta in [{lo:.4f}, {hi:.4f}] fits exactly)")
    return make("implicit_monotone", x, basis, Monotone(), th, physics, g, snr_db, rng, desc, identified="set",
                extras={"identified_set": (lo, hi)})


def figure2(*, n: int = 1001, snr_db: float = 30.0, theta: dict | None = None,
            random_state: int | None = None) -> Dataset:
    """The paper's Figure 2 / Proposition 1 case: ``y = theta x^2 sin 5x + cos x`` on [-pi, pi].

    The physics is odd and the disturbance ``cos x`` even, so ``Even(0)`` point-identifies theta
    (theta* = 0.5 in the paper; pass ``theta={"theta": 0.5}``; random in [0.25, 1] otherwise). An
    unconstrained network (Eq. 2) can absorb ``x^2 sin 5x`` too, so its theta is not determined.

    Parameters
    ----------
    n : int
        Samples on [-pi, pi] (symmetric grid).
    snr_db : float
        Physics-to-noise power ratio in dB (``inf``: no noise).
    theta : dict, optional
        ``{"theta": value}`` fixes the coefficient (else drawn uniformly from [0.25, 1]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> figure2(theta={"theta": 0.5}, random_state=0).theta_true
    {'theta': 0.5}
    """
    n = check_n(n, 11)
    rng = rng_from(random_state)
    check_theta(theta, ["theta"])
    x = np.linspace(-np.pi, np.pi, n)
    th = {"theta": pick(rng, theta, "theta", 0.25, 1.0)}
    basis = Basis([_x2_sin5], names=["theta"])
    physics = th["theta"] * _x2_sin5(x)
    desc = "Figure 2: y = theta x^2 sin 5x + cos x; class Even(0)"
    return make("figure2", x, basis, Even(0.0), th, physics, np.cos(x), snr_db, rng, desc)
