"""AC power flow over a day of load snapshots with pandapower (MATPOWER cases it ships).

All quantities are per unit on the case's ``sn_mva``; buses are numbered by their position in
``net.bus``. Real power uses the **load convention** of pandapower's ``res_bus`` (consumption
positive): ``p_i = -sum_k v_i v_k (G_ik cos d_ik + B_ik sin d_ik)``.
"""
from __future__ import annotations

import logging
import warnings

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.signals.grid_newton import bus_types, solve_flow
from odnn_sep.signals.optional import require

log = logging.getLogger(__name__)

#: Cases: pandapower network function, description, default measured buses (positions).
CASES = {
    "case14": ("case14", "IEEE 14-bus transmission system", (0, 1, 2, 3, 4, 5, 6, 8)),
    "case33bw": ("case33bw", "Baran-Wu 33-bus radial distribution feeder",
                 (*range(10), 18, 22, 25)),
}


def _pandapower():
    pp = require("pandapower", "grid", "the power_grid dataset")
    pn = require("pandapower.networks", "grid", "the power_grid dataset")
    return pp, pn


def load_case(case: str):
    """The pandapower network of ``case`` (one of :data:`CASES`), solved once at nominal load.

    Parameters
    ----------
    case : str
        ``"case14"`` or ``"case33bw"``.

    Returns
    -------
    pandapowerNet
        With the power-flow results (and the admittance matrix) of the nominal load.

    Raises
    ------
    odnn_sep.errors.InputError
        For a case not in :data:`CASES` or when pandapower (the ``grid`` extra) is not installed.

    Examples
    --------
    >>> import pandapower  # the "grid" extra
    >>> net = load_case("case33bw")
    >>> len(net.bus), bool(net.converged)
    (33, True)
    >>> load_case("case9")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: case 'case9' is not available; choose one of case14, case33bw
    """
    if case not in CASES:
        raise InputError(f"case {case!r} is not available; choose one of {', '.join(CASES)}")
    pp, pn = _pandapower()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pandapower's deprecation chatter
        net = getattr(pn, CASES[case][0])()
        pp.runpp(net, numba=False)
    return net



def three_bus_feeder():
    """A solved three-bus feeder (0 - 1 - 2, 12.66 kV, a 0.5 MW load at bus 2): the small network the
    examples of the grid modules share (needs pandapower).

    Returns
    -------
    pandapowerNet
        The network, with its power flow solved.

    Examples
    --------
    >>> net = three_bus_feeder()
    >>> len(net.bus), len(net.line), bool(net.res_bus.vm_pu.iloc[2] < 1.0)
    (3, 2, True)
    """
    pp, _ = _pandapower()
    net = pp.create_empty_network(sn_mva=1.0)
    buses = [pp.create_bus(net, vn_kv=12.66) for _ in range(3)]
    pp.create_ext_grid(net, buses[0])
    for f, t in ((0, 1), (1, 2)):
        pp.create_line_from_parameters(net, buses[f], buses[t], length_km=1, r_ohm_per_km=0.5,
                                       x_ohm_per_km=0.4, c_nf_per_km=0, max_i_ka=1)
    pp.create_load(net, buses[2], p_mw=0.5, q_mvar=0.2)
    pp.runpp(net, numba=False)
    return net

def admittance(net) -> tuple[np.ndarray, np.ndarray]:
    """True bus admittance matrix (G, B) in ``net.bus`` order, from pandapower's own Ybus.

    Parameters
    ----------
    net : pandapowerNet
        A network on which ``pandapower.runpp`` has run (:func:`load_case`).

    Returns
    -------
    G, B : (nb, nb) ndarray
        Conductance and susceptance matrices, p.u. on ``net.sn_mva``.

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2 (:func:`three_bus_feeder`):

    >>> import numpy as np
    >>> net = three_bus_feeder()
    >>> G, B = admittance(net)
    >>> G.round(3).tolist()
    [[195.458, -195.458, 0.0], [-195.458, 390.916, -195.458], [0.0, -195.458, 195.458]]
    >>> round(float(B[0, 1]), 3)
    156.366
    """
    Y = net._ppc["internal"]["Ybus"].toarray()
    pos = net._pd2ppc_lookups["bus"][net.bus.index.values]
    Y = Y[np.ix_(pos, pos)]
    return Y.real.copy(), Y.imag.copy()


def adjacency(G: np.ndarray, B: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Boolean (nb, nb) matrix of the lines (non-zero off-diagonal admittance).

    Parameters
    ----------
    G, B : (nb, nb) ndarray
        Conductance and susceptance matrices.
    tol : float, optional
        Admittances at most this large count as no line.

    Returns
    -------
    (nb, nb) bool ndarray
        Symmetric, False on the diagonal.

    Examples
    --------
    >>> import numpy as np
    >>> G = np.array([[4.0, -4, 0], [-4, 9, -5], [0, -5, 5]])
    >>> adjacency(G, -3 * G).astype(int).tolist()
    [[0, 1, 0], [1, 0, 1], [0, 1, 0]]
    """
    a = (np.abs(G) > tol) | (np.abs(B) > tol)
    np.fill_diagonal(a, False)
    return a


def candidate_graph(net, G: np.ndarray, B: np.ndarray, hops: int = 2) -> np.ndarray:
    """Pairs within ``hops`` branches of each other in the network model, open switches included.

    This is what a utility's network model offers as candidate lines: the branches it knows
    about (in service or not) and their near neighbours. Which of them are really connected, and
    with which parameters, is what the data must tell.

    Parameters
    ----------
    net : pandapowerNet
        The network model (its out-of-service lines count as candidates).
    G, B : (nb, nb) ndarray
        Admittance matrices (:func:`admittance`).
    hops : int, optional
        Largest number of branches between two candidate ends.

    Returns
    -------
    (nb, nb) bool ndarray
        Candidate pairs, symmetric, False on the diagonal.

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2 (:func:`three_bus_feeder`):

    >>> import numpy as np
    >>> net = three_bus_feeder()
    >>> G, B = admittance(net)
    >>> candidate_graph(net, G, B).astype(int).tolist()         # 0 and 2 are two branches apart
    [[0, 1, 1], [1, 0, 1], [1, 1, 0]]
    >>> candidate_graph(net, G, B, hops=1).astype(int).tolist()
    [[0, 1, 0], [1, 0, 1], [0, 1, 0]]
    """
    a = adjacency(G, B)
    pos = {b: i for i, b in enumerate(net.bus.index)}
    for f, t in net.line.loc[~net.line.in_service, ["from_bus", "to_bus"]].values:
        a[pos[f], pos[t]] = a[pos[t], pos[f]] = True
    reach = a.copy()
    step = a.astype(int)
    for _ in range(hops - 1):
        step = (step @ a.astype(int) > 0).astype(int)
        reach |= step.astype(bool)
    np.fill_diagonal(reach, False)
    return reach


def run_snapshots(net, load_mult: np.ndarray, vm_slack: np.ndarray, btm: dict, q_jitter: np.ndarray,
                  gen_vm: np.ndarray | None = None, gen_mult: np.ndarray | None = None):
    """Solve the AC power flow for every snapshot.

    The flows are solved by :func:`odnn_sep.signals.grid_newton.solve_flow` on pandapower's admittance
    matrix; the first and the last snapshot are solved again by ``pandapower.runpp`` (behind-the-meter
    units as static generators at the settled output) and must agree to ``CHECK_TOL``.

    Parameters
    ----------
    net : pandapowerNet
        From :func:`load_case` (modified in place by the check: loads, set-points, the BTM static generators).
    load_mult : (n, n_loads) array
        Multiplier of each load's nominal P (and Q).
    vm_slack : (n,) array
        Slack-bus voltage magnitude (p.u.).
    btm : dict
        Bus position -> behind-the-meter unit (see :func:`grid_profiles.btm_power`), p.u. power.
    q_jitter : (n, n_loads) array
        Relative change of each load's reactive power (power-factor variation).
    gen_vm, gen_mult : (n, n_gen) arrays, optional
        Voltage set-point (p.u.) and multiplier of the nominal real power of each PV generator
        (transmission cases: the dispatch and the voltage schedule change through the day).

    Returns
    -------
    v, delta, p_load, g : (n, nb) arrays
        Voltage magnitude (p.u.), angle (rad), metered real power in load convention (p.u.; the
        behind-the-meter generation is *not* in it) and the behind-the-meter generation (p.u.).

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2 (:func:`three_bus_feeder`):

    >>> import numpy as np
    >>> net = three_bus_feeder()
    >>> v, delta, p_load, g = run_snapshots(net, np.ones((2, 1)), np.array([1.0, 1.02]), {}, np.zeros((2, 1)))
    >>> v.round(4).tolist()                                      # the slack voltage steps up by 2 %
    [[1.0, 0.9979, 0.9959], [1.02, 1.018, 1.0159]]
    >>> p_load[:, 2].round(4).tolist(), bool(g.any())
    ([0.5, 0.5], False)
    """
    n, nb = load_mult.shape[0], len(net.bus)
    G, B = admittance(net)
    Y = G + 1j * B
    sched = Schedule(net, load_mult, vm_slack, q_jitter, gen_vm, gen_mult)
    types = bus_types(nb, sched.slack, sched.gen_bus)
    v, delta, p_load, g = (np.empty((n, nb)) for _ in range(4))
    V = np.ones(nb, dtype=complex)
    for t in range(n):
        s_spec, vm_set = sched.injection(t)
        V, g[t] = solve_flow(Y, s_spec, vm_set, sched.va_slack, types, btm, V)
        v[t], delta[t] = np.abs(V), np.angle(V)
        # consumption minus generation, without the behind-the-meter units the meter does not see
        p_load[t] = -(V * np.conj(Y @ V)).real + g[t]
    for t in sorted({0, n - 1}):
        check_with_pandapower(net, sched, t, btm, g[t], v[t], delta[t])
    return v, delta, p_load, g


class Schedule:
    """Per-snapshot loads, generator dispatch and voltage set-points of ``net`` in bus positions (p.u.).

    Parameters
    ----------
    net : pandapowerNet
        The network (nominal loads, generators, slack).
    load_mult, vm_slack, q_jitter, gen_vm, gen_mult : ndarray or None
        As for :func:`run_snapshots`.

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2 (:func:`three_bus_feeder`):

    >>> import numpy as np
    >>> net = three_bus_feeder()
    >>> sched = Schedule(net, np.full((1, 1), 2.0), np.array([1.01]), np.zeros((1, 1)), None, None)
    >>> sched.slack, sched.load_bus.tolist()
    (0, [2])
    >>> s, vm_set = sched.injection(0)                          # twice the nominal load at bus 2
    >>> s.round(3).tolist(), vm_set.tolist()
    ([0j, 0j, (-1-0.4j)], [1.01, 1.0, 1.0])
    """

    def __init__(self, net, load_mult, vm_slack, q_jitter, gen_vm, gen_mult):
        pos = {b: i for i, b in enumerate(net.bus.index)}
        self.sn = float(net.sn_mva)
        self.nb = len(net.bus)
        self.load_bus = np.array([pos[b] for b in net.load.bus.values], dtype=int)
        self.p0, self.q0 = net.load.p_mw.values / self.sn, net.load.q_mvar.values / self.sn
        self.gen_bus = np.array([pos[b] for b in net.gen.bus.values], dtype=int)
        self.pg0 = net.gen.p_mw.values / self.sn
        self.vg0 = net.gen.vm_pu.values.astype(float)
        self.slack = pos[net.ext_grid.bus.values[0]]
        self.va_slack = float(np.deg2rad(net.ext_grid.va_degree.values[0]))
        self.load_mult, self.vm_slack, self.q_jitter = load_mult, vm_slack, q_jitter
        self.gen_vm, self.gen_mult = gen_vm, gen_mult

    def gen_setting(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        """Real power (p.u.) and voltage set-point of each generator at snapshot t."""
        if self.gen_vm is None or not len(self.gen_bus):
            return self.pg0, self.vg0
        return self.pg0 * self.gen_mult[t], self.gen_vm[t]

    def injection(self, t: int) -> tuple[np.ndarray, np.ndarray]:
        """Specified complex injection (generation convention) and voltage set-points at snapshot t."""
        s = np.zeros(self.nb, dtype=complex)
        m = self.load_mult[t]
        np.add.at(s, self.load_bus, -(self.p0 * m + 1j * self.q0 * m * (1 + self.q_jitter[t])))
        pg, vg = self.gen_setting(t)
        np.add.at(s, self.gen_bus, pg)
        vm_set = np.ones(self.nb)
        vm_set[self.gen_bus] = vg
        vm_set[self.slack] = self.vm_slack[t]
        return s, vm_set


#: Largest disagreement with ``pandapower.runpp`` (p.u. voltage, rad) accepted by the check.
CHECK_TOL = 1e-7


def check_with_pandapower(net, sched: Schedule, t: int, btm: dict, g: np.ndarray, v: np.ndarray,
                          delta: np.ndarray) -> None:
    """Solve snapshot t with ``pandapower.runpp`` and compare; a disagreement is a bug, not bad input.

    Parameters
    ----------
    net : pandapowerNet
        Modified in place: loads, set-points and the behind-the-meter static generators of snapshot t.
    sched : Schedule
    t : int
        The snapshot.
    btm : dict
        Bus position -> behind-the-meter unit.
    g, v, delta : (nb,) ndarray
        Behind-the-meter generation, voltage magnitudes and angles found for snapshot t.

    Raises
    ------
    RuntimeError
        When pandapower's solution differs by more than :data:`CHECK_TOL`.

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2 (:func:`three_bus_feeder`):

    >>> import numpy as np
    >>> net = three_bus_feeder()
    >>> sched = Schedule(net, np.ones((1, 1)), np.array([1.0]), np.zeros((1, 1)), None, None)
    >>> v, delta = net.res_bus.vm_pu.values.copy(), np.deg2rad(net.res_bus.va_degree.values)
    >>> check_with_pandapower(net, sched, 0, {}, np.zeros(3), v, delta)      # agrees: nothing happens
    >>> check_with_pandapower(net, sched, 0, {}, np.zeros(3), v + 1e-3, delta)
    Traceback (most recent call last):
    ...
    RuntimeError: power flow of snapshot 0 disagrees with pandapower.runpp by 0.001 p.u., 0 rad
    """
    pp, _ = _pandapower()
    m = sched.load_mult[t]
    net.load["p_mw"] = sched.p0 * sched.sn * m
    net.load["q_mvar"] = sched.q0 * sched.sn * m * (1 + sched.q_jitter[t])
    net.ext_grid["vm_pu"] = sched.vm_slack[t]
    if len(net.gen):
        pg, vg = sched.gen_setting(t)
        net.gen["p_mw"], net.gen["vm_pu"] = pg * sched.sn, vg
    net.sgen.drop(net.sgen.index[net.sgen.name.astype(str).str.startswith("btm")], inplace=True)
    for b in sorted(btm):
        pp.create_sgen(net, net.bus.index[b], p_mw=float(g[b]) * sched.sn, name=f"btm{b}")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pandapower's deprecation chatter
        pp.runpp(net, tolerance_mva=1e-10, numba=False)
    dv = np.max(np.abs(net.res_bus.vm_pu.values - v))
    dd = np.max(np.abs(np.deg2rad(net.res_bus.va_degree.values) - delta))
    if max(dv, dd) > CHECK_TOL:
        raise RuntimeError(f"power flow of snapshot {t} disagrees with pandapower.runpp by {dv:.2g} p.u., "
                           f"{dd:.2g} rad")
