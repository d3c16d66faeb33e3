"""Physical-system cases of paper App. C.5, C.8, C.9 and C.10, in versions that are identifiable.

Where the paper's framing is not identifiable we use a sound variant and say why in the docstring.
"""
from __future__ import annotations

from functools import partial

import numpy as np

from odnn_sep.core import Basis, Even, ParametricBasis, Periodic, Subspace
from odnn_sep.signals.dataset import Dataset, check_n, check_theta, make, pick, rng_from


# Basis terms are module functions (bound by partial), not closures, so that a Dataset pickles
# (multiprocessing, joblib); each computes what the closure it replaces computed.
def _resonant_response(t, w):
    return t * np.sin(w * t) / (2 * w)


def _growth(t, xp=np, mu=0.5):
    return xp.exp(mu * t)[:, None]


def _damped(t, xp=np, gamma=0.2, omega=3.0):
    e = xp.exp(-gamma * t)
    return xp.stack([e * xp.cos(omega * t), e * xp.sin(omega * t)], -1)


def _identity(t):
    return t


def _periodic_series(rng, w, t, harmonics=3, scale=1.0):
    """Random Fourier series with fundamental angular frequency ``w`` (arbitrary periodic shape)."""
    g = np.zeros_like(t)
    for k in range(1, harmonics + 1):
        g += scale * rng.uniform(0.2, 1.0) / k * np.cos(k * w * t + rng.uniform(0, 2 * np.pi))
    return g


def pendulum(*, periods: int = 10, per_period: int = 100, snr_db: float = 30.0, theta: dict | None = None,
             random_state: int | None = None) -> Dataset:
    """Resonantly driven pendulum (App. C.9): ``theta(t) = theta0 cos wt + (f / 2w) t sin wt``.

    The paper contrasts the two terms by symmetry, but both are even in t (``t sin wt`` is a
    product of two odd functions), so symmetry cannot separate them. Periodicity can: the free
    response ``theta0 cos wt`` (and anything else with period 2 pi / w, here an unknown initial
    velocity term and a 2w sensor pickup) is periodic, the resonant growth ``t sin wt`` is not.
    Physics column ``t sin(wt) / (2w)`` with unknown force ``f`` (w known); class
    ``Periodic(2 pi / w)``; t covers ``periods`` whole periods with ``per_period`` samples each.

    Parameters
    ----------
    periods, per_period : int
        Record length in periods and samples per period.
    snr_db : float
        Physics-to-noise power ratio in dB.
    theta : dict, optional
        Fix ``f`` (force, default uniform in [0.02, 0.1]) or ``omega`` (rad/s, default in [1.5, 3]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = pendulum(random_state=0)
    >>> ds.basis.names
    ('f',)
    """
    periods = check_n(periods, 2, "periods")
    per_period = check_n(per_period, 4, "per_period")
    rng = rng_from(random_state)
    check_theta(theta, ["f", "omega"])
    w = pick(rng, theta, "omega", 1.5, 3.0)
    f = pick(rng, theta, "f", 0.02, 0.1)
    P = 2 * np.pi / w
    t = np.arange(periods * per_period) * (P / per_period)
    basis = Basis([partial(_resonant_response, w=w)], names=["f"])
    physics = f * t * np.sin(w * t) / (2 * w)
    theta0, v0 = rng.uniform(0.1, 0.5), rng.uniform(-0.3, 0.3)
    g = theta0 * np.cos(w * t) + v0 / w * np.sin(w * t) + rng.uniform(0, 0.05) * np.cos(2 * w * t + rng.uniform(0, 6.3))
    desc = (f"driven pendulum: (f/2w) t sin wt + periodic free response/pickup, w = {w:.4g} rad/s known; "
            "class Periodic(2pi/w) (symmetry cannot separate them: both terms are even in t)")
    return make("pendulum", t, basis, Periodic(P), {"f": f}, physics, g, snr_db, rng, desc,
                extras={"omega": w, "theta0": theta0, "v0": v0})


def aiba_edwards_mu(S: np.ndarray | float, mu_max: float, K_S: float, K_I: float):
    """Aiba-Edwards specific growth rate ``mu_max S / (K_S + S) exp(-S / K_I)`` (substrate inhibition).

    Parameters
    ----------
    S : array_like
        Substrate concentration.
    mu_max : float
        Largest growth rate without inhibition.
    K_S : float
        Half-saturation constant.
    K_I : float
        Inhibition constant.

    Returns
    -------
    ndarray
        Growth rate, same shape as ``S``.

    Examples
    --------
    >>> round(float(aiba_edwards_mu(1.0, 1.0, 1.0, 10.0)), 6)
    0.452419
    """
    S = np.asarray(S, dtype=float)
    return mu_max * S / (K_S + S) * np.exp(-S / K_I)


def substrate_twin(S: float, mu_max: float, K_S: float, K_I: float) -> float | None:
    """The other substrate level with the same Aiba-Edwards rate as ``S`` (the rate rises then falls in
    S), or None when there is none in range.

    Parameters
    ----------
    S : float
        Substrate concentration.
    mu_max, K_S, K_I : float
        Parameters of :func:`aiba_edwards_mu`.

    Returns
    -------
    float or None

    Examples
    --------
    >>> S2 = substrate_twin(1.0, 1.0, 1.0, 10.0)
    >>> round(S2, 6), bool(np.isclose(aiba_edwards_mu(S2, 1.0, 1.0, 10.0), aiba_edwards_mu(1.0, 1.0, 1.0, 10.0)))
    (6.500583, True)
    """
    from scipy.optimize import brentq

    mu = aiba_edwards_mu(S, mu_max, K_S, K_I)
    S_peak = (-K_S + np.sqrt(K_S**2 + 4 * K_S * K_I)) / 2  # d mu / dS = 0
    f = lambda s: aiba_edwards_mu(s, mu_max, K_S, K_I) - mu  # noqa: E731
    lo, hi = (S_peak, 50 * K_I) if S < S_peak else (1e-9, S_peak)
    return float(brentq(f, lo, hi)) if f(lo) * f(hi) < 0 else None


def biology(*, days: int = 5, per_day: int = 96, snr_db: float = 30.0, theta: dict | None = None,
            random_state: int | None = None) -> Dataset:
    """Bacterial growth with an Aiba-Edwards rate and a daily disturbance (sound version of App. C.9).

    ``y(t) = N0 exp(mu t) + g(t) + noise`` with t in days, ``mu = mu_max S / (K_S + S) exp(-S / K_I)``
    (Aiba-Edwards, substrate inhibition) and ``g`` an additive measurement disturbance of arbitrary
    shape repeating every day (temperature cycle). Class ``Periodic(1.0)``. Identified: ``N0``
    (linear) and the growth rate ``mu`` (nonlinear, variable projection). The substrate level S is
    *not* identified from mu: the Aiba-Edwards rate rises then falls in S, so two substrate levels
    give the same mu (both are listed in ``extras``).

    The paper's formula ``S/(S+K_S) (exp(S/K_S) + cos 2 pi t)`` has no growth in t and would make
    the cosine part scale with the unknown; we use the textbook exponential growth instead.

    Parameters
    ----------
    days, per_day : int
        Record length in days and samples per day.
    snr_db : float
        Physics-to-noise power ratio in dB.
    theta : dict, optional
        Fix ``N0`` (default uniform in [0.5, 2]) or ``mu`` (per day; default from random
        Aiba-Edwards constants, within about [0.2, 1.2]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = biology(random_state=0)
    >>> ds.basis.names, ds.basis.phi_names
    (('N0',), ('mu',))
    """
    days = check_n(days, 2, "days")
    per_day = check_n(per_day, 4, "per_day")
    rng = rng_from(random_state)
    check_theta(theta, ["N0", "mu"])
    mu_max, K_S, K_I = rng.uniform(0.8, 1.5), rng.uniform(0.5, 2.0), rng.uniform(5.0, 20.0)
    S = rng.uniform(0.5, 5.0)
    mu = pick(rng, theta, "mu", 0, 0) if theta and "mu" in theta else float(aiba_edwards_mu(S, mu_max, K_S, K_I))
    # (pick() validates a caller-given mu; otherwise mu follows from the drawn constants)
    N0 = pick(rng, theta, "N0", 0.5, 2.0)
    t = np.arange(days * per_day) / per_day

    basis = ParametricBasis(_growth, phi0={"mu": 0.6}, bounds={"mu": (0.01, 3.0)}, names=["N0"],
                            grid={"mu": np.linspace(0.05, 2.5, 50)})
    physics = N0 * np.exp(mu * t)
    g = _periodic_series(rng, 2 * np.pi, t, harmonics=4, scale=N0)
    S_twin = None if theta and "mu" in theta else substrate_twin(S, mu_max, K_S, K_I)
    desc = (f"biology: N0 exp(mu t) + daily periodic disturbance, Aiba-Edwards mu = {mu:.4g}/day; "
            "class Periodic(1 day); S not identifiable from mu (non-monotone rate)")
    return make("biology", t, basis, Periodic(1.0), {"N0": N0, "mu": mu}, physics, g, snr_db, rng, desc,
                extras={"S": S, "S_same_mu": S_twin, "mu_max": mu_max, "K_S": K_S, "K_I": K_I})


def oscillator(*, n: int = 1000, duration: float = 10.0, snr_db: float = 30.0, theta: dict | None = None,
               random_state: int | None = None) -> Dataset:
    """Damped oscillator (App. C.5) with unknown decay and frequency plus a slow drift.

    ``y = exp(-gamma t) (A cos wt + B sin wt) + drift + noise``. ``A, B`` linear, ``gamma, omega``
    nonlinear (variable projection with a grid start). The drift is a random cubic in t (sensor
    drift), so the class is ``Subspace`` of the Legendre polynomials of degree <= 3 on the record.

    (The paper splits ``A cos`` from ``B sin`` by "symmetry axes", which the decaying envelope breaks;
    we identify both amplitudes together and separate the oscillation from the drift instead.)

    Parameters
    ----------
    n : int
        Samples, uniform on [0, duration).
    duration : float
        Record length (s).
    snr_db : float
        Physics-to-noise power ratio in dB.
    theta : dict, optional
        Fix any of ``A``, ``B`` (|.| in [0.5, 1.5], random sign), ``gamma`` ([0.1, 0.4] 1/s),
        ``omega`` ([2, 5] rad/s).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> oscillator(random_state=0).basis.phi_names
    ('gamma', 'omega')
    """
    n = check_n(n, 32)
    rng = rng_from(random_state)
    check_theta(theta, ["A", "B", "gamma", "omega"])
    t = np.arange(n) * (duration / n)
    th = {"A": pick(rng, theta, "A", 0.5, 1.5, signed=True), "B": pick(rng, theta, "B", 0.5, 1.5, signed=True),
          "gamma": pick(rng, theta, "gamma", 0.1, 0.4), "omega": pick(rng, theta, "omega", 2.0, 5.0)}

    basis = ParametricBasis(_damped, phi0={"gamma": 0.25, "omega": 3.5}, bounds={"gamma": (0.0, 1.0),
                            "omega": (1.0, 7.0)}, names=["A", "B"],
                            grid={"gamma": np.linspace(0.05, 0.6, 12), "omega": np.linspace(1.5, 6.0, 46)})
    physics = _damped(t, gamma=th["gamma"], omega=th["omega"]) @ np.array([th["A"], th["B"]])
    u = 2 * t / duration - 1
    G = np.polynomial.legendre.legvander(u, 3)
    g = G @ (rng.uniform(-0.5, 0.5, 4) * [1, 1, 0.5, 0.25])
    desc = "damped oscillator: exp(-gamma t)(A cos wt + B sin wt) + cubic drift; class Subspace(Legendre deg<=3)"
    return make("oscillator", t, basis, Subspace(G), th, physics, g, snr_db, rng, desc)


def population(*, years: int = 10, per_year: int = 52, snr_db: float = 30.0, theta: dict | None = None,
               random_state: int | None = None) -> Dataset:
    """Multiplicative population growth (App. C.10), separated after a log transform.

    ``N(t) = N0 (1 + r)^t (1 + a sin(2 pi t + psi)) * exp(noise)``; ``y = log N(t) =
    t log(1+r) + [log N0 + log(1 + a sin(2 pi t + psi))] + noise``. The bracket has period one year
    (offset included), so the class is ``Periodic(1.0)``; the basis is the single column ``t`` with
    coefficient ``log1p_r = log(1 + r)`` (``extras["r"]`` holds r). Noise is multiplicative on N,
    i.e. additive on y, at ``snr_db`` relative to the log-growth term ``t log(1 + r)``.

    Parameters
    ----------
    years, per_year : int
        Record length in years and samples per year.
    snr_db : float
        Physics-to-noise power ratio in dB (on the log scale).
    theta : dict, optional
        ``{"r": value}`` fixes the yearly growth rate (else uniform in [0.03, 0.2]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = population(random_state=0)
    >>> bool(abs(ds.theta_true["log1p_r"] - __import__("numpy").log1p(ds.extras["r"])) < 1e-12)
    True
    """
    years = check_n(years, 2, "years")
    per_year = check_n(per_year, 4, "per_year")
    rng = rng_from(random_state)
    check_theta(theta, ["r"])
    r = pick(rng, theta, "r", 0.03, 0.2)
    a, psi, N0 = rng.uniform(0.2, 0.6), rng.uniform(0, 2 * np.pi), rng.uniform(50, 500)
    t = np.arange(years * per_year) / per_year
    basis = Basis([_identity], names=["log1p_r"])
    physics = t * np.log1p(r)
    g = np.log(N0) + np.log1p(a * np.sin(2 * np.pi * t + psi))
    desc = "population: log of N0 (1+r)^t (1 + a sin 2pi t); class Periodic(1 year) after the log transform"
    ds = make("population", t, basis, Periodic(1.0), {"log1p_r": float(np.log1p(r))}, physics, g, snr_db, rng,
              desc, extras={"r": r, "a": a, "N0": N0})
    return ds


#: Known (x/L, y/H) positions of the physics heat sources in :func:`heat2d`: no two are mirror
#: images about the centre lines, so their asymmetric parts are linearly independent.
HEAT_SOURCES = ((0.22, 0.30), (0.70, 0.58), (0.38, 0.80))


def heat_kernel(X, x0, y0, alpha_t):
    """Free-space 2-D heat kernel of a unit instantaneous source at (x0, y0) after time t.

    Parameters
    ----------
    X : (n, 2) ndarray
        Points (x, y).
    x0, y0 : float
        The source.
    alpha_t : float
        Diffusivity times time.

    Returns
    -------
    (n,) ndarray

    Examples
    --------
    >>> g = heat_kernel(np.array([[0.5, 0.5], [0.6, 0.5], [0.5, 0.4]]), 0.5, 0.5, 0.01)
    >>> bool(g[0] > g[1]), bool(np.isclose(g[1], g[2]))       # radial, largest at the source
    (True, True)
    """
    r2 = (X[:, 0] - x0) ** 2 + (X[:, 1] - y0) ** 2
    return np.exp(-r2 / (4 * alpha_t)) / (4 * np.pi * alpha_t)


def symmetric_heat(X, L: float, H: float, alpha_t: float, rng) -> tuple[np.ndarray, float, float]:
    """A disturbance even about the plate's centre in both axes: balanced sources on opposite edges
    (strengths drawn) and a symmetric ambient field; returns ``(g, Q_left_right, Q_top_bottom)``.

    Parameters
    ----------
    X : (n, 2) ndarray
        Points on the plate.
    L, H : float
        Plate width and height.
    alpha_t : float
        Diffusivity times time.
    rng : numpy.random.Generator
        Source of the strengths and the ambient field.

    Returns
    -------
    g : (n,) ndarray
    Q_left_right, Q_top_bottom : float
        Strengths of the edge sources.

    Examples
    --------
    >>> X = np.array([[0.2, 0.3], [0.8, 0.7]])       # mirror images about the centre (0.5, 0.5)
    >>> g, _, _ = symmetric_heat(X, 1.0, 1.0, 0.01, np.random.default_rng(0))
    >>> bool(np.isclose(g[0], g[1]))
    True
    """
    Q_lr, Q_tb = rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0)
    g = (Q_lr * (heat_kernel(X, 0, H / 2, alpha_t) + heat_kernel(X, L, H / 2, alpha_t))
         + Q_tb * (heat_kernel(X, L / 2, 0, alpha_t) + heat_kernel(X, L / 2, H, alpha_t))
         + rng.uniform(0, 2) + rng.uniform(0, 1) * np.cos(2 * np.pi * (X[:, 0] - L / 2) / L)
         * np.cos(np.pi * (X[:, 1] - H / 2) / H))
    return g, Q_lr, Q_tb


def heat2d(*, nx: int = 41, ny: int = 33, L: float = 1.0, H: float = 0.8, alpha_t: float = 0.01,
           snr_db: float = 30.0, theta: dict | None = None, random_state: int | None = None) -> Dataset:
    """Inverse heat-source problem (App. C.8) in an identifiable form.

    The paper takes a symmetric field (four edge sources) as the physics and an asymmetric corner
    source as the disturbance. That is not identifiable: "asymmetric" is not a class that excludes
    symmetric functions, and the corner source's symmetric part would be attributed to the edge
    sources. We use the sound reverse. Disturbance: any field symmetric about both centre lines
    (the balanced four edge sources - left/right and top/bottom pairs of equal strength - plus a
    symmetric ambient profile) -> ``Even(center=(L/2, H/2), axes=(0, 1))``. Physics: sources at the
    known, asymmetric positions :data:`HEAT_SOURCES` with unknown strengths ``Q0, Q1, Q2``.

    Samples: ``nx x ny`` grid with end points on [0, L] x [0, H] (symmetric about the centre),
    flattened to ``x`` of shape (nx*ny, 2). ``alpha_t`` is diffusivity times time (kernel variance
    ``2 alpha_t`` per axis).

    Parameters
    ----------
    nx, ny : int
        Grid points along x and y.
    L, H : float
        Domain length and height.
    alpha_t : float
        Thermal diffusivity times elapsed time.
    snr_db : float
        Physics-to-noise power ratio in dB.
    theta : dict, optional
        Fix any of ``Q0, Q1, Q2`` (else uniform in [0.5, 2]).
    random_state : int or numpy Generator, optional

    Returns
    -------
    Dataset

    Examples
    --------
    >>> ds = heat2d(random_state=0)
    >>> ds.x.shape, ds.basis.names
    ((1353, 2), ('Q0', 'Q1', 'Q2'))
    """
    nx, ny = check_n(nx, 5, "nx"), check_n(ny, 5, "ny")
    rng = rng_from(random_state)
    names = [f"Q{i}" for i in range(len(HEAT_SOURCES))]
    check_theta(theta, names)
    gx, gy = np.linspace(0, L, nx), np.linspace(0, H, ny)
    X = np.stack(np.meshgrid(gx, gy, indexing="ij"), -1).reshape(-1, 2)

    def source(px, py):
        return partial(heat_kernel, x0=px * L, y0=py * H, alpha_t=alpha_t)

    basis = Basis([source(px, py) for px, py in HEAT_SOURCES], names=names)
    th = {nm: pick(rng, theta, nm, 0.5, 2.0) for nm in names}
    physics = basis.evaluate(X) @ np.array([th[k] for k in names])
    g, Q_lr, Q_tb = symmetric_heat(X, L, H, alpha_t, rng)
    desc = (f"heat 2-D: sources at known asymmetric positions {HEAT_SOURCES} (x L, x H) with unknown strengths + "
            "balanced edge sources and symmetric ambient; class Even(center, axes=(0,1))")
    return make("heat2d", X, basis, Even(center=(L / 2, H / 2), axes=(0, 1)), th, physics, g, snr_db, rng, desc,
                extras={"Q_left_right": Q_lr, "Q_top_bottom": Q_tb, "alpha_t": alpha_t})
