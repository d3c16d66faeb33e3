"""Newton-Raphson AC power flow on pandapower's admittance matrix, with voltage-dependent injections.

pandapower builds the network, its bus admittance matrix and the bus types; one ``runpp`` call costs
~0.1 s of DataFrame bookkeeping, and a behind-the-meter injection that depends on the local voltage
needs a fixed point of several such calls per snapshot. Solving the same polar power-flow equations
here (the injection ``g_i(|V_i|)`` and its slope are part of the mismatch and the Jacobian) takes
milliseconds per snapshot, so that weeks of 15-minute snapshots are affordable.
:func:`odnn_sep.signals.grid_flow.run_snapshots` checks the result against ``pandapower.runpp``.

Conventions: complex voltages ``V`` in bus order, injections in generation convention (p.u.),
``S_i = V_i conj((Y V)_i)``.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.signals.grid_profiles import btm_power

#: Largest power mismatch (p.u.) accepted as converged, and the iteration limit.
TOLERANCE = 1e-11
MAX_ITER = 30
#: Step of the central difference for the slope of a behind-the-meter injection.
SLOPE_STEP = 1e-7


@dataclass(frozen=True)
class BusTypes:
    """Positions of the slack bus, the PV (voltage-controlled) buses and the PQ buses.

    Attributes
    ----------
    slack : int
        The slack bus (magnitude and angle given).
    pv : ndarray of int
        Voltage-controlled buses (real power and magnitude given).
    pq : ndarray of int
        Load buses (real and reactive power given).

    Examples
    --------
    >>> import numpy as np
    >>> t = BusTypes(slack=0, pv=np.array([2]), pq=np.array([1, 3]))
    >>> t.angles.tolist()                      # the unknown angles: PV buses, then PQ buses
    [2, 1, 3]
    """

    slack: int
    pv: np.ndarray
    pq: np.ndarray

    @property
    def angles(self) -> np.ndarray:
        """Buses whose angle is unknown (PV and PQ)."""
        return np.r_[self.pv, self.pq]


def bus_types(nb: int, slack: int, gen_buses) -> BusTypes:
    """Slack at ``slack``, PV at every generator bus other than the slack, PQ elsewhere.

    Parameters
    ----------
    nb : int
        Number of buses.
    slack : int
        Position of the slack bus.
    gen_buses : iterable of int
        Positions of the generator buses (the slack may be among them; repeats are merged).

    Returns
    -------
    BusTypes

    Examples
    --------
    >>> t = bus_types(4, 0, [0, 2])
    >>> t.slack, t.pv.tolist(), t.pq.tolist()
    (0, [2], [1, 3])
    """
    pv = np.array(sorted({int(b) for b in gen_buses} - {slack}), dtype=int)
    pq = np.array([b for b in range(nb) if b != slack and b not in set(pv)], dtype=int)
    return BusTypes(slack=slack, pv=pv, pq=pq)


def btm_injection(btm: dict, vm: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Behind-the-meter generation at every bus and its slope d g / d v (central difference).

    Parameters
    ----------
    btm : dict
        Bus position -> behind-the-meter unit (:func:`~odnn_sep.signals.grid_profiles.draw_btm`).
    vm : (nb,) ndarray
        Voltage magnitudes (p.u.).

    Returns
    -------
    g, dg : (nb,) ndarray
        Generation (p.u., zero at buses without a unit) and its derivative with respect to ``vm``.

    Examples
    --------
    >>> import numpy as np
    >>> g, dg = btm_injection({1: {"kind": "power_law", "p0": 0.2, "alpha": 4.0}}, np.ones(3))
    >>> g.round(4).tolist(), dg.round(4).tolist()             # 0.2 v**4 and its slope 0.8 v**3
    ([0.0, 0.2, 0.0], [0.0, 0.8, 0.0])
    """
    g = np.zeros_like(vm)
    dg = np.zeros_like(vm)
    for b, unit in btm.items():
        g[b] = btm_power(unit, vm[b])
        dg[b] = (btm_power(unit, vm[b] + SLOPE_STEP) - btm_power(unit, vm[b] - SLOPE_STEP)) / (2 * SLOPE_STEP)
    return g, dg


def _jacobian(Y: np.ndarray, V: np.ndarray, types: BusTypes, dg: np.ndarray) -> np.ndarray:
    """d(mismatch)/d(angles of PV+PQ, magnitudes of PQ), the injection's slope included."""
    current = Y @ V
    vn = V / np.abs(V)
    dS_dvm = np.diag(V) @ np.conj(Y * vn[None, :]) + np.diag(np.conj(current) * vn)
    dS_dva = 1j * np.diag(V) @ np.conj(np.diag(current) - Y * V[None, :])
    dS_dvm = dS_dvm - np.diag(dg)  # the specified injection grows with |V|
    a, q = types.angles, types.pq
    return np.block([[dS_dva[np.ix_(a, a)].real, dS_dvm[np.ix_(a, q)].real],
                     [dS_dva[np.ix_(q, a)].imag, dS_dvm[np.ix_(q, q)].imag]])


def solve_flow(Y: np.ndarray, s_spec: np.ndarray, vm_set: np.ndarray, va_slack: float, types: BusTypes,
               btm: dict, V0: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """One power flow: complex bus voltages and the behind-the-meter generation it settles at.

    Parameters
    ----------
    Y : (nb, nb) complex ndarray
        Bus admittance matrix (p.u.).
    s_spec : (nb,) complex ndarray
        Specified injection without the behind-the-meter units (generation convention, p.u.).
    vm_set : (nb,) ndarray
        Voltage magnitude set-points; read at the slack and PV buses.
    va_slack : float
        Slack-bus angle (rad).
    types : BusTypes
    btm : dict
        Bus position -> behind-the-meter unit (:func:`grid_profiles.btm_power`).
    V0 : (nb,) complex ndarray
        Start (the previous snapshot's solution).

    Returns
    -------
    V : (nb,) complex ndarray
    g : (nb,) ndarray
        Behind-the-meter generation at the solution.

    Raises
    ------
    odnn_sep.errors.InputError
        When Newton's method does not converge in ``MAX_ITER`` steps.

    Examples
    --------
    Two buses joined by one line, a load of 0.5 + 0.2j p.u. at bus 1:

    >>> import numpy as np
    >>> y = 1 / (0.01 + 0.1j)
    >>> Y = np.array([[y, -y], [-y, y]])
    >>> s_spec = np.array([0, -(0.5 + 0.2j)])                  # generation convention: a load is negative
    >>> V, g = solve_flow(Y, s_spec, np.ones(2), 0.0, bus_types(2, 0, []), {}, np.ones(2, complex))
    >>> np.abs(V).round(4).tolist(), np.angle(V).round(4).tolist()
    ([1.0, 0.9731], [0.0, -0.0493])

    A behind-the-meter unit at bus 1 offsets part of the load and lifts its voltage:

    >>> unit = {"kind": "power_law", "p0": 0.2, "alpha": 4.0}
    >>> V, g = solve_flow(Y, s_spec, np.ones(2), 0.0, bus_types(2, 0, []), {1: unit}, np.ones(2, complex))
    >>> np.abs(V).round(4).tolist(), g.round(4).tolist()
    ([1.0, 0.9758], [0.0, 0.1813])
    """
    vm, va = np.abs(V0).copy(), np.angle(V0).copy()
    fixed = np.r_[types.slack, types.pv]
    vm[fixed] = vm_set[fixed]
    va[types.slack] = va_slack
    a, q = types.angles, types.pq
    for _ in range(MAX_ITER):
        V = vm * np.exp(1j * va)
        g, dg = btm_injection(btm, vm)
        mis = V * np.conj(Y @ V) - (s_spec + g)
        f = np.r_[mis.real[a], mis.imag[q]]
        if np.max(np.abs(f)) < TOLERANCE:
            return V, g
        dx = np.linalg.solve(_jacobian(Y, V, types, dg), -f)
        va[a] += dx[:len(a)]
        vm[q] += dx[len(a):]
    raise InputError("the AC power flow did not converge; reduce the load scale or the behind-the-meter share")
