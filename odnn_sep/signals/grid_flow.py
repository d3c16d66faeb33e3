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
from odnn_sep.signals._optional import require
from odnn_sep.signals.grid_profiles import btm_power

log = logging.getLogger(__name__)

#: Cases: pandapower network function, description, default measured buses (positions).
CASES = {
    "case14": ("case14", "IEEE 14-bus transmission system", (0, 1, 2, 3, 4, 5, 6, 8)),
    "case33bw": ("case33bw", "Baran-Wu 33-bus radial distribution feeder",
                 (*range(10), 18, 22, 25)),
}
#: Fixed-point tolerance (p.u. voltage; the recorded generation is the one the flow used) for the voltage-dependent behind-the-meter injections.
BTM_TOL = 1e-8


def _pandapower():
    pp = require("pandapower", "grid", "the power_grid dataset")
    pn = require("pandapower.networks", "grid", "the power_grid dataset")
    return pp, pn


def load_case(case: str):
    """The pandapower network of ``case`` (one of :data:`CASES`), solved once at nominal load."""
    if case not in CASES:
        raise InputError(f"case {case!r} is not available; choose one of {', '.join(CASES)}")
    pp, pn = _pandapower()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # pandapower's deprecation chatter
        net = getattr(pn, CASES[case][0])()
        pp.runpp(net, numba=False)
    return net


def admittance(net) -> tuple[np.ndarray, np.ndarray]:
    """True bus admittance matrix (G, B) in ``net.bus`` order, from pandapower's own Ybus."""
    Y = net._ppc["internal"]["Ybus"].toarray()
    pos = net._pd2ppc_lookups["bus"][net.bus.index.values]
    Y = Y[np.ix_(pos, pos)]
    return Y.real.copy(), Y.imag.copy()


def adjacency(G: np.ndarray, B: np.ndarray, tol: float = 1e-9) -> np.ndarray:
    """Boolean (nb, nb) matrix of the lines (non-zero off-diagonal admittance)."""
    a = (np.abs(G) > tol) | (np.abs(B) > tol)
    np.fill_diagonal(a, False)
    return a


def candidate_graph(net, G: np.ndarray, B: np.ndarray, hops: int = 2) -> np.ndarray:
    """Pairs within ``hops`` branches of each other in the network model, open switches included.

    This is what a utility's network model offers as candidate lines: the branches it knows
    about (in service or not) and their near neighbours. Which of them are really connected, and
    with which parameters, is what the data must tell.
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

    Parameters
    ----------
    net : pandapowerNet
        From :func:`load_case` (modified in place: loads, slack voltage and the BTM static generators).
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
    """
    pp, _ = _pandapower()
    n, nb = load_mult.shape[0], len(net.bus)
    sn = float(net.sn_mva)
    p0, q0 = net.load.p_mw.values.copy(), net.load.q_mvar.values.copy()
    pg0 = net.gen.p_mw.values.copy()
    btm_buses = sorted(btm)
    sgen_idx = [pp.create_sgen(net, net.bus.index[b], p_mw=0.0, name=f"btm{b}") for b in btm_buses]
    v = np.empty((n, nb))
    delta = np.empty((n, nb))
    p_load = np.empty((n, nb))
    g = np.zeros((n, nb))
    v_guess = np.ones(nb)
    for t in range(n):
        net.load["p_mw"] = p0 * load_mult[t]
        net.load["q_mvar"] = q0 * load_mult[t] * (1 + q_jitter[t])
        net.ext_grid["vm_pu"] = vm_slack[t]
        if gen_vm is not None and len(net.gen):
            net.gen["vm_pu"] = gen_vm[t]
            net.gen["p_mw"] = pg0 * gen_mult[t]
        for it in range(50):
            gen = np.array([btm_power(btm[b], v_guess[b]) for b in btm_buses])
            if sgen_idx:
                net.sgen.loc[sgen_idx, "p_mw"] = gen * sn
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    pp.runpp(net, init="results" if t or it else "auto", tolerance_mva=1e-10, numba=False)
            except Exception as exc:  # pandapower raises its own LoadflowNotConverged
                raise InputError(f"the AC power flow did not converge at snapshot {t} ({exc}); "
                                 "reduce the load scale or the behind-the-meter share") from None
            vm = net.res_bus.vm_pu.values
            if not btm_buses or np.max(np.abs(vm - v_guess)) < BTM_TOL:
                break
            v_guess = vm.copy()
        else:
            raise InputError(f"the behind-the-meter injections did not settle at snapshot {t}; "
                             "reduce their share of the load")
        v_guess = vm.copy()
        v[t] = vm
        delta[t] = np.deg2rad(net.res_bus.va_degree.values)
        g[t, btm_buses] = gen
        # res_bus counts the BTM sgen as negative consumption; the meter does not see it.
        p_load[t] = net.res_bus.p_mw.values / sn + g[t]
    return v, delta, p_load, g
