"""Load time series and behind-the-meter injections for the power-grid dataset.

Daily load shapes follow the usual residential (morning and evening peaks) and commercial (office
hours plateau) patterns; each load mixes the two, has its own size and weekday/weekend scaling, and
carries multiplicative AR(1) noise, so that bus loads are not proportional to each other. The
substation voltage follows an on-load tap changer (steps of 0.625 %) around a slow drift: without an
independent source of voltage variation every bus voltage would be a function of one daily profile
and nothing could be separated from a function of voltage.

Behind-the-meter injections are convex, increasing functions of the local voltage magnitude ``v``
(per unit). They are real power generation that the bus meter does not see:

* ``boost``: a DC boost converter feeding a constant-impedance load side,
  ``P = c v^2 / (1 - D)^2`` (the paper's ``V_in^2 / (1 - D)^2``, duty cycle D fixed),
* ``power_law``: a voltage-dependent (exponential-model) source ``P = P0 v^alpha``, alpha in [3, 6],
* ``exponential``: ``P = P0 exp(kappa (v - 1))``, kappa in [4, 12].
"""
from __future__ import annotations

import numpy as np

BTM_KINDS = ("boost", "power_law", "exponential")


def _bump(h: np.ndarray, centre: float, width: float) -> np.ndarray:
    """Periodic Gaussian bump on the 24-h clock."""
    d = (h - centre + 12.0) % 24.0 - 12.0
    return np.exp(-0.5 * (d / width) ** 2)


def residential_shape(hours: np.ndarray) -> np.ndarray:
    """Normalised residential day: night base, morning peak ~7:30, evening peak ~19:00.

    Parameters
    ----------
    hours : ndarray
        Time of day in hours (any real values; the shape repeats every 24 h).

    Returns
    -------
    ndarray
        Load relative to its nominal size, same shape as ``hours`` (about 0.35 to 1.0).

    Examples
    --------
    >>> import numpy as np
    >>> residential_shape(np.array([3.0, 7.5, 19.0])).round(3).tolist()    # night, morning, evening
    [0.352, 0.719, 1.014]
    """
    return 0.35 + 0.35 * _bump(hours, 7.5, 1.3) + 0.65 * _bump(hours, 19.0, 2.2) + 0.1 * _bump(hours, 13.0, 3.0)


def commercial_shape(hours: np.ndarray) -> np.ndarray:
    """Normalised commercial day: low at night, plateau 8:00-18:00 with smooth ramps.

    Parameters
    ----------
    hours : ndarray
        Time of day in hours (0-24).

    Returns
    -------
    ndarray
        Load relative to its nominal size, same shape as ``hours`` (0.3 to 1.0).

    Examples
    --------
    >>> import numpy as np
    >>> commercial_shape(np.array([3.0, 12.0, 23.0])).round(3).tolist()
    [0.301, 0.997, 0.305]
    """
    ramp_up = 1.0 / (1.0 + np.exp(-(hours - 8.0) / 0.7))
    ramp_down = 1.0 / (1.0 + np.exp((hours - 18.5) / 0.9))
    return 0.3 + 0.7 * ramp_up * ramp_down


def load_profiles(n: int, n_loads: int, step_h: float, rng: np.random.Generator, *, spread: float = 0.2
                  ) -> np.ndarray:
    """Multipliers (n, n_loads) of each load's nominal size, around 0.4-1.2.

    Each load is a random mix of residential and commercial shape, with a random size factor,
    a weekend factor for its commercial part, and AR(1) multiplicative noise (15-min correlation,
    ``spread`` log-standard deviation: appliances, heat pumps, EV charging switching on and off) so
    that loads vary independently of each other.

    Parameters
    ----------
    n : int
        Number of snapshots.
    n_loads : int
        Number of loads.
    step_h : float
        Time between snapshots in hours (0.25 for 15 minutes).
    rng : numpy.random.Generator
        Source of the random mixes, sizes and noise.
    spread : float, optional
        Log-standard deviation of the multiplicative AR(1) noise.

    Returns
    -------
    (n, n_loads) ndarray
        Positive multipliers of each load's nominal power.

    Examples
    --------
    >>> import numpy as np
    >>> m = load_profiles(96, 3, 0.25, np.random.default_rng(0))    # one day of 15-minute snapshots
    >>> m.shape, bool((m > 0).all())
    ((96, 3), True)
    """
    t_h = np.arange(n) * step_h
    hours = t_h % 24.0
    weekend = ((t_h // 24.0) % 7 >= 5).astype(float)
    res, com = residential_shape(hours), commercial_shape(hours)
    out = np.empty((n, n_loads))
    phi = np.exp(-step_h / 0.25)
    for j in range(n_loads):
        mix = rng.uniform(0.0, 1.0)
        size = rng.uniform(0.7, 1.1)
        shape = (1 - mix) * res + mix * com * (1 - 0.5 * weekend)
        eps = np.empty(n)
        eps[0] = rng.standard_normal()
        for i in range(1, n):
            eps[i] = phi * eps[i - 1] + np.sqrt(1 - phi**2) * rng.standard_normal()
        out[:, j] = size * shape * np.exp(spread * eps)
    return out


def substation_voltage(n: int, step_h: float, rng: np.random.Generator, *, centre: float = 1.0) -> np.ndarray:
    """Slack-bus voltage (p.u.): tap steps of 0.625 % around a slow random drift, within +-3 %.

    Parameters
    ----------
    n : int
        Number of snapshots.
    step_h : float
        Time between snapshots in hours.
    rng : numpy.random.Generator
        Source of the drift, the daily phase and the offset.
    centre : float, optional
        Nominal voltage (p.u.).

    Returns
    -------
    (n,) ndarray
        ``centre`` plus a whole number of 0.625 % tap steps.

    Examples
    --------
    >>> import numpy as np
    >>> v = substation_voltage(96, 0.25, np.random.default_rng(0))
    >>> v.shape, bool((np.abs(v - 1) <= 0.03 + 1e-12).all())
    ((96,), True)
    >>> steps = (v - 1) / 0.00625
    >>> bool(np.allclose(steps, np.round(steps)))                     # whole tap steps
    True
    """
    drift = np.cumsum(rng.standard_normal(n)) * 0.004 * np.sqrt(step_h)
    drift = drift - np.linspace(drift[0], drift[-1], n)  # no net trend over the record
    daily = 0.01 * np.sin(2 * np.pi * (np.arange(n) * step_h) / 24.0 + rng.uniform(0, 2 * np.pi))
    target = np.clip(centre + drift + daily + rng.uniform(-0.01, 0.01), centre - 0.03, centre + 0.03)
    step = 0.00625
    return centre + np.round((target - centre) / step) * step


def draw_btm(kind: str, nominal_p: float, rng: np.random.Generator) -> dict:
    """Parameters of one behind-the-meter unit producing 10-40 % of ``nominal_p`` at v = 1 p.u.

    Parameters
    ----------
    kind : str
        One of :data:`BTM_KINDS`: ``"boost"``, ``"power_law"`` or ``"exponential"``.
    nominal_p : float
        Nominal real power of the bus (p.u.).
    rng : numpy.random.Generator
        Source of the share and the unit's parameters.

    Returns
    -------
    dict
        ``kind`` and its parameters (``c`` and ``duty``; ``p0`` and ``alpha``; ``p0`` and ``kappa``),
        as read by :func:`btm_power`.

    Raises
    ------
    ValueError
        For an unknown ``kind``.

    Examples
    --------
    >>> import numpy as np
    >>> unit = draw_btm("power_law", 1.0, np.random.default_rng(0))
    >>> sorted(unit), unit["kind"]
    (['alpha', 'kind', 'p0'], 'power_law')
    >>> 0.1 <= float(btm_power(unit, 1.0)) <= 0.4                      # 10-40 % of nominal_p at v = 1
    True
    """
    share = rng.uniform(0.1, 0.4) * nominal_p
    if kind == "boost":
        duty = rng.uniform(0.2, 0.6)
        return {"kind": kind, "c": share * (1 - duty) ** 2, "duty": duty}
    if kind == "power_law":
        return {"kind": kind, "p0": share, "alpha": rng.uniform(3.0, 6.0)}
    if kind == "exponential":
        return {"kind": kind, "p0": share, "kappa": rng.uniform(4.0, 12.0)}
    raise ValueError(f"unknown behind-the-meter kind {kind!r}; choose one of {BTM_KINDS}")


def btm_power(unit: dict, v: np.ndarray) -> np.ndarray:
    """Real power (p.u.) generated by a behind-the-meter unit at voltage magnitude ``v`` (p.u.).

    Parameters
    ----------
    unit : dict
        A unit from :func:`draw_btm`.
    v : array_like
        Voltage magnitude(s), p.u.

    Returns
    -------
    ndarray
        Generated real power, same shape as ``v``; convex and increasing in ``v``.

    Examples
    --------
    >>> import numpy as np
    >>> btm_power({"kind": "boost", "c": 0.09, "duty": 0.4}, np.array([1.0, 1.1])).round(4).tolist()
    [0.25, 0.3025]
    >>> btm_power({"kind": "power_law", "p0": 0.2, "alpha": 4.0}, np.array([1.0, 1.1])).round(4).tolist()
    [0.2, 0.2928]
    """
    v = np.asarray(v, dtype=float)
    kind = unit["kind"]
    if kind == "boost":
        return unit["c"] * v**2 / (1 - unit["duty"]) ** 2
    if kind == "power_law":
        return unit["p0"] * v ** unit["alpha"]
    return unit["p0"] * np.exp(unit["kappa"] * (v - 1.0))


def generator_schedule(n: int, n_gen: int, step_h: float, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Voltage set-points (p.u., 1.00-1.06 in 0.5 % steps, changed every few hours) and real-power
    multipliers (0.6-1.2, following the daily demand with a unit-specific offset) of PV generators.

    Parameters
    ----------
    n : int
        Number of snapshots.
    n_gen : int
        Number of PV generators.
    step_h : float
        Time between snapshots in hours.
    rng : numpy.random.Generator
        Source of the set-point changes and the dispatch offsets.

    Returns
    -------
    vm, mult : (n, n_gen) ndarray
        Voltage set-points (p.u.) and real-power multipliers.

    Examples
    --------
    >>> import numpy as np
    >>> vm, mult = generator_schedule(8, 2, 1.0, np.random.default_rng(0))
    >>> vm.shape, mult.shape
    ((8, 2), (8, 2))
    >>> bool(((vm >= 1.0) & (vm <= 1.06)).all()), bool(np.allclose(vm / 0.005, np.round(vm / 0.005)))
    (True, True)
    """
    hours = np.arange(n) * step_h % 24.0
    demand = commercial_shape(hours) / 1.0
    vm = np.empty((n, n_gen))
    mult = np.empty((n, n_gen))
    for j in range(n_gen):
        level = rng.uniform(1.0, 1.06)
        for t in range(n):
            if t == 0 or rng.random() < step_h / 3.0:
                level = rng.uniform(1.0, 1.06)
            vm[t, j] = np.round(level / 0.005) * 0.005
        mult[:, j] = np.clip(0.6 + 0.6 * demand * rng.uniform(0.8, 1.2) + 0.05 * rng.standard_normal(n), 0.5, 1.3)
    return vm, mult
