"""Line conductance and susceptance from partial measurements (paper section 4.3 and App. C.7).

An AC power flow (pandapower) is solved for ``snapshots`` load states over several days. Only the
``measured`` buses have meters (voltage magnitude and angle, metered real power). A bus whose every
neighbour is measured gives a complete equation in the unknown admittances of its row,

    p_i = -sum_{k != i} [ G_ik (v_i v_k cos d_ik - v_i^2) + B_ik v_i v_k sin d_ik ] + g_i(v_i) + noise,

(load convention; ``G_ii = -sum_k G_ik``: no shunt conductance, true for both cases shipped), with one
candidate pair (G_ik, B_ik) for every measured bus k within two branches of i in the network model
(open switches included): absent lines must come out as zero.
``g_i`` is behind-the-meter generation that the meter does not see, a convex increasing function of
v_i (boost converter ``c v^2 / (1 - D)^2``, a power-law or an exponential source; see
:mod:`odnn_sep.signals.grid_profiles`). Each row is one separation problem with ``x = v_i`` and the
class ``Convex()`` (the user does not know which buses carry such generation), except at a bus
without customer load (slack or generator bus), which has no behind-the-meter generation and no
disturbance class.

Identifiability: a convex function of v_i can only imitate the part of a column that is a function
of v_i; the cos/sin columns depend on the neighbours' voltages and the angles, which vary with the
independent loads and the tap changer, so the identified set of each coefficient is narrow. The
self-conductance column ``v_i^2`` would be **inside** the convex class (``G_ii`` not identified, only
bounded on one side); that is why the row-sum form is used, and why a shunt conductance could not
be identified together with a convex disturbance.

Noise convention: the metered power has white Gaussian noise at ``snr_db`` relative to the bus's
physics power (as every dataset here); voltage magnitudes and angles carry phasor-measurement noise of
``sigma_v`` p.u. and ``sigma_delta`` rad. Defaults: 0.1 % metering (60 dB) and 1e-6 p.u. / 1e-6 rad,
i.e. one-minute averages of PMU phasors. The equations are errors-in-variables: on the distribution
feeder adjacent voltages differ by ~1e-3 p.u., and voltage noise of 1e-6 biases least squares by tens
of percent; :mod:`odnn_sep.signals.grid_eiv` estimates that bias (see BENCHMARKS.md).
"""
from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.core import Basis, Convex, Orthogonal
from odnn_sep.errors import InputError
from odnn_sep.signals.dataset import Dataset, add_noise, check_n, check_snr, rng_from
from odnn_sep.signals.grid_flow import CASES, adjacency, admittance, candidate_graph, load_case, run_snapshots
from odnn_sep.signals.grid_profiles import (
    BTM_KINDS,
    draw_btm,
    generator_schedule,
    load_profiles,
    substation_voltage,
)

MAX_SNAPSHOTS = 20_000


@dataclass(frozen=True)
class GridDataset:
    """A partially observed power grid with known line parameters.

    Attributes
    ----------
    case : str
        pandapower case name.
    G, B : (nb, nb) ndarray
        True bus conductance and susceptance matrices (p.u.).
    measured : tuple of int
        Positions of the measured buses; ``v``, ``delta``, ``p`` columns follow this order.
    rows : tuple of int
        Buses whose equation is complete (all neighbours measured, non-zero injection).
    excluded : dict
        Measured buses that give no usable equation, with the reason.
    v, delta, p : (n, len(measured)) ndarray
        Measured voltage magnitude (p.u.), angle (rad), metered real power (p.u., load convention).
    g : (n, len(measured)) ndarray
        True behind-the-meter generation at the measured buses.
    btm : dict
        Bus -> behind-the-meter unit parameters.
    problems : tuple of Dataset
        One separation problem per bus in ``rows`` (x = v_i, class ``Convex()``).

    Examples
    --------
    :func:`power_grid` simulates one; a hand-made record shows the accessors:

    >>> import numpy as np
    >>> G = np.array([[4.0, -4, 0], [-4, 9, -5], [0, -5, 5]])      # lines 0-1 and 1-2
    >>> z = np.zeros((2, 3))
    >>> ds = GridDataset(name="power_grid", case="toy", G=G, B=-3 * G, measured=(0, 1, 2), rows=(1,),
    ...                  excluded={}, v=z + 1, delta=z, p=z, g=z, btm={}, problems=(), snr_db=60.0,
    ...                  sigma_v=0.0, sigma_delta=0.0, description="three buses")
    >>> ds.lines
    [(0, 1), (1, 2)]
    >>> ds.truth()["lines"][0]
    {'i': 0, 'k': 1, 'G': -4.0, 'B': 12.0}
    >>> sorted(ds.arrays())
    ['B', 'G', 'behind_the_meter', 'delta', 'measured', 'p', 'rows', 'time_h', 'v']
    """

    name: str
    case: str
    G: np.ndarray
    B: np.ndarray
    measured: tuple
    rows: tuple
    excluded: dict
    v: np.ndarray
    delta: np.ndarray
    p: np.ndarray
    g: np.ndarray
    btm: dict
    problems: tuple
    snr_db: float
    sigma_v: float
    sigma_delta: float
    description: str
    step_h: float = 0.25
    extras: dict = field(default_factory=dict)

    @property
    def lines(self) -> list[tuple[int, int]]:
        """True lines (i < k) among the measured buses."""
        a = adjacency(self.G, self.B)
        m = self.measured
        return [(i, k) for x, i in enumerate(m) for k in m[x + 1:] if a[i, k]]

    def truth(self) -> dict:
        """JSON-ready truth: lines among the measured buses with G, B, the usable rows, the BTM units."""
        return {"case": self.case, "measured": list(self.measured), "rows": list(self.rows),
                "excluded": {str(k): v for k, v in self.excluded.items()},
                "lines": [{"i": i, "k": k, "G": float(self.G[i, k]), "B": float(self.B[i, k])} for i, k in self.lines],
                "behind_the_meter": {str(b): u for b, u in self.btm.items()},
                "sigma_v": self.sigma_v, "sigma_delta": self.sigma_delta}

    def arrays(self) -> dict:
        """Everything as plain arrays (for ``np.savez``)."""
        return {"v": self.v, "delta": self.delta, "p": self.p, "behind_the_meter": self.g,
                "measured": np.array(self.measured), "rows": np.array(self.rows), "G": self.G, "B": self.B,
                "time_h": np.arange(self.v.shape[0]) * self.step_h}


def row_columns(v: np.ndarray, delta: np.ndarray, i: int, others) -> tuple[np.ndarray, list[str]]:
    """Columns of bus i's equation (load convention) for candidate neighbours ``others``.

    ``v``, ``delta`` are (n, nb) in bus positions. Column for G_ik: ``-(v_i v_k cos d_ik - v_i^2)``;
    for B_ik: ``-v_i v_k sin d_ik``.

    Parameters
    ----------
    v, delta : (n, nb) ndarray
        Voltage magnitudes (p.u.) and angles (rad) of every bus.
    i : int
        The bus of the equation.
    others : iterable of int
        Candidate neighbours k.

    Returns
    -------
    F : (n, 2 len(others)) ndarray
        The columns, G then B for each candidate.
    names : list of str
        ``G[i,k]``, ``B[i,k]`` for each candidate, in column order.

    Examples
    --------
    >>> import numpy as np
    >>> v = np.array([[1.0, 0.99, 0.98], [1.01, 1.0, 0.99]])
    >>> delta = np.array([[0.0, -0.01, -0.02], [0.0, -0.02, -0.01]])
    >>> F, names = row_columns(v, delta, 1, [0, 2])
    >>> F.shape, names
    ((2, 4), ['G[1,0]', 'B[1,0]', 'G[1,2]', 'B[1,2]'])
    >>> F[0].round(5).tolist()
    [-0.00985, 0.0099, 0.00995, -0.0097]
    """
    cols, names = [], []
    for k in others:
        vv = v[:, i] * v[:, k]
        d = delta[:, i] - delta[:, k]
        cols += [-(vv * np.cos(d) - v[:, i] ** 2), -vv * np.sin(d)]
        names += [f"G[{i},{k}]", f"B[{i},{k}]"]
    return np.stack(cols, axis=1), names


def _check_measured(measured, nb: int, case: str) -> tuple:
    try:
        m = sorted({int(b) for b in measured})
    except (TypeError, ValueError):
        raise InputError(f"measured must be a list of bus indices; got {measured!r}") from None
    bad = [b for b in m if not 0 <= b < nb]
    if bad:
        raise InputError(f"measured bus {bad[0]} does not exist in {case} (buses 0..{nb - 1}); "
                         "give bus positions in that range")
    if len(m) < 2:
        raise InputError(f"measured needs at least 2 buses; got {m}")
    return tuple(m)


def _usable_rows(measured, adj, p_true, nb):
    rows, excluded = [], {}
    mset = set(measured)
    for i in measured:
        missing = [k for k in range(nb) if adj[i, k] and k not in mset]
        if missing:
            excluded[i] = f"neighbour bus(es) {missing} not measured: equation incomplete"
        elif np.max(np.abs(p_true[:, i])) < 1e-9:
            excluded[i] = "zero injection: the equation is homogeneous, its scale is not determined"
        else:
            rows.append(i)
    return tuple(rows), excluded


def power_grid(*, case: str = "case14", snapshots: int = 288, measured: Sequence[int] | None = None,
               btm_share: float = 0.5, snr_db: float = 60.0, sigma_v: float = 1e-6, sigma_delta: float = 1e-6,
               random_state: int | None = None) -> GridDataset:
    """Simulate a partially observed grid with behind-the-meter generation; one problem per bus row.

    Parameters
    ----------
    case : {"case14", "case33bw"}
        IEEE 14-bus transmission system (default) or the radial 33-bus distribution feeder.
    snapshots : int
        Number of 15-minute load snapshots (288 = three days).
    measured : sequence of int, optional
        Measured bus positions (default: a connected region, see ``grid_flow.CASES``).
    btm_share : float
        Fraction of the loaded buses that get a behind-the-meter unit (kinds drawn at random).
    snr_db : float
        Metered-power-to-noise ratio per bus (dB).
    sigma_v, sigma_delta : float
        Standard deviation of the voltage-magnitude (p.u.) and angle (rad) measurement noise.
    random_state : int or numpy Generator, optional

    Returns
    -------
    GridDataset

    Examples
    --------
    >>> import pandapower  # the "grid" extra
    >>> ds = power_grid(snapshots=48, random_state=0)           # half a day of the IEEE 14-bus system
    >>> ds.measured, ds.rows, ds.v.shape
    ((0, 1, 2, 3, 4, 5, 6, 8), (0, 1, 2, 3, 4), (48, 8))
    >>> ds.problems[0].basis.names[:2], type(ds.problems[0].disturbance).__name__   # bus 0: the slack
    (('G[0,1]', 'B[0,1]'), 'Orthogonal')
    """
    snapshots, snr_db = check_options(snapshots, snr_db, sigma_v, sigma_delta, btm_share)
    rng = rng_from(random_state)
    net = load_case(case)
    nb = len(net.bus)
    measured = _check_measured(CASES[case][2] if measured is None else measured, nb, case)
    G, B = admittance(net)
    adj = adjacency(G, B)
    cand = candidate_graph(net, G, B)
    check_snapshots(snapshots, cand, measured)
    nominal, btm, flows = simulate(net, snapshots, btm_share, rng)
    _v, _d, p_t, g_t = flows
    rows, excluded = _usable_rows(measured, adj, p_t - g_t, nb)
    v_m, d_m, noise_p = measurement_noise(flows, measured, snr_db, sigma_v, sigma_delta, rng)
    p_m = p_t + noise_p
    truth = GridTruth(G=G, B=B, adj=adj, p=p_t, g=g_t, btm=btm, nominal=nominal)
    problems = []
    for i in rows:
        others = [k for k in measured if cand[i, k]]
        problems.append(bus_problem(case, i, others, (v_m, d_m, p_m, noise_p), truth, snr_db))
    mi = list(measured)
    desc = (f"power_grid: {CASES[case][1]} ({case}), {snapshots} snapshots of 15 min, {len(measured)} of {nb} "
            f"buses measured, {len(rows)} complete bus equations, behind-the-meter generation at buses "
            f"{sorted(btm)}; unknown G_ik, B_ik for every measured pair; class Convex() in v_i per bus")
    return GridDataset(
        name="power_grid", case=case, G=G, B=B, measured=measured, rows=rows, excluded=excluded,
        v=v_m[:, mi], delta=d_m[:, mi], p=p_m[:, mi], g=g_t[:, mi], btm=btm, problems=tuple(problems),
        snr_db=snr_db, sigma_v=float(sigma_v), sigma_delta=float(sigma_delta), description=desc)


def check_options(snapshots, snr_db, sigma_v, sigma_delta, btm_share) -> tuple[int, float]:
    """Validate the scalar options of :func:`power_grid`; returns the checked snapshot count and SNR.

    Parameters
    ----------
    snapshots : int
        Number of snapshots (2 to ``MAX_SNAPSHOTS``).
    snr_db : float
        Metering signal-to-noise ratio (dB).
    sigma_v, sigma_delta : float
        Voltage noise standard deviations, each in [0, 0.01).
    btm_share : float
        Share of loaded buses with a behind-the-meter unit, in [0, 1].

    Returns
    -------
    snapshots : int
    snr_db : float

    Raises
    ------
    odnn_sep.errors.InputError
        For the first option out of range.

    Examples
    --------
    >>> check_options(96, 60, 1e-6, 1e-6, 0.5)
    (96, 60.0)
    >>> check_options(96, 60, 0.1, 1e-6, 0.5)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: sigma_v must be in [0, 0.01); got 0.1
    """
    snapshots = check_n(snapshots, 2, "snapshots")
    if snapshots > MAX_SNAPSHOTS:
        raise InputError(f"snapshots={snapshots} is above the limit {MAX_SNAPSHOTS}; use fewer")
    snr_db = check_snr(snr_db)
    for nm, val in (("sigma_v", sigma_v), ("sigma_delta", sigma_delta)):
        if not (np.isfinite(val) and 0 <= val < 0.01):
            raise InputError(f"{nm} must be in [0, 0.01); got {val!r}")
    if not 0 <= btm_share <= 1:
        raise InputError(f"btm_share must be in [0, 1]; got {btm_share!r}")
    return snapshots, snr_db


def check_snapshots(snapshots: int, cand: np.ndarray, measured) -> None:
    """Enough snapshots for the largest bus equation (two per unknown).

    Parameters
    ----------
    snapshots : int
        Number of snapshots.
    cand : (nb, nb) bool ndarray
        Candidate lines (:func:`~odnn_sep.signals.grid_flow.candidate_graph`).
    measured : sequence of int
        Measured bus positions.

    Raises
    ------
    odnn_sep.errors.InputError
        When ``snapshots`` is less than twice the unknowns of some bus equation.

    Examples
    --------
    >>> import numpy as np
    >>> cand = ~np.eye(3, dtype=bool)                  # every pair a candidate: 4 unknowns per bus
    >>> check_snapshots(8, cand, (0, 1, 2))
    >>> check_snapshots(6, cand, (0, 1, 2))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: too few snapshots: 6 for 4 unknowns per bus equation (3 measured buses); need at least 8
    """
    n_unknowns = max(2 * sum(cand[i, k] for k in measured) for i in measured)
    if snapshots < 2 * n_unknowns:
        raise InputError(f"too few snapshots: {snapshots} for {n_unknowns} unknowns per bus equation "
                         f"({len(measured)} measured buses); need at least {2 * n_unknowns}")


def simulate(net, snapshots: int, btm_share: float, rng) -> tuple[np.ndarray, dict, tuple]:
    """Behind-the-meter units, load and generator schedules, and the power flows of every snapshot.

    Returns the nominal load per bus (p.u.), the units (bus -> parameters) and the true
    ``(v, delta, p, g)`` arrays of :func:`grid_flow.run_snapshots`.

    Parameters
    ----------
    net : pandapowerNet
        From :func:`~odnn_sep.signals.grid_flow.load_case` (modified by the pandapower check).
    snapshots : int
        Number of 15-minute snapshots.
    btm_share : float
        Share of the loaded buses that get a behind-the-meter unit.
    rng : numpy.random.Generator

    Returns
    -------
    nominal : (nb,) ndarray
    btm : dict
    flows : tuple of (snapshots, nb) ndarray

    Examples
    --------
    A three-bus feeder (0 - 1 - 2) with a load at bus 2:

    >>> import numpy as np
    >>> from odnn_sep.signals.grid_flow import three_bus_feeder
    >>> net = three_bus_feeder()
    >>> nominal, btm, (v, delta, p, g) = simulate(net, 4, 1.0, np.random.default_rng(0))
    >>> nominal.tolist(), sorted(btm), btm[2]["kind"], v.shape
    ([0.0, 0.0, 0.5], [2], 'boost', (4, 3))
    >>> bool((g[:, 2] > 0).all()), bool((g[:, :2] == 0).all())   # generation only behind bus 2's meter
    (True, True)
    """
    nb = len(net.bus)
    pos = {b: i for i, b in enumerate(net.bus.index)}
    load_bus = np.array([pos[b] for b in net.load.bus.values])
    nominal = np.zeros(nb)
    np.add.at(nominal, load_bus, net.load.p_mw.values / net.sn_mva)
    loaded = [b for b in range(nb) if nominal[b] > 0]
    chosen = rng.choice(loaded, size=int(round(btm_share * len(loaded))), replace=False)
    btm = {int(b): draw_btm(BTM_KINDS[j % len(BTM_KINDS)], nominal[b], rng) for j, b in enumerate(sorted(chosen))}
    mult = load_profiles(snapshots, len(net.load), 0.25, rng)
    q_jit = 0.1 * rng.standard_normal((snapshots, len(net.load)))
    gen_vm, gen_mult = generator_schedule(snapshots, len(net.gen), 0.25, rng)
    flows = run_snapshots(net, mult, substation_voltage(snapshots, 0.25, rng), btm, q_jit, gen_vm, gen_mult)
    return nominal, btm, flows


def measurement_noise(flows, measured, snr_db: float, sigma_v: float, sigma_delta: float, rng):
    """Measured voltages and angles, and the metering noise of the real power (zero at unmetered buses).

    Parameters
    ----------
    flows : tuple of (n, nb) ndarray
        True ``(v, delta, p, g)`` from :func:`~odnn_sep.signals.grid_flow.run_snapshots`.
    measured : iterable of int
        Metered bus positions.
    snr_db : float
        Metering signal-to-noise ratio, relative to each bus's physics power ``p - g``.
    sigma_v, sigma_delta : float
        Standard deviations of the voltage magnitude (p.u.) and angle (rad) noise.
    rng : numpy.random.Generator

    Returns
    -------
    v_m, d_m, noise_p : (n, nb) ndarray
        Measured magnitudes and angles (every bus), and the real-power metering noise.

    Examples
    --------
    >>> import numpy as np
    >>> ones, zeros = np.ones((4, 3)), np.zeros((4, 3))
    >>> v_m, d_m, noise = measurement_noise((ones, zeros, ones, zeros), (0, 1), 40.0, 1e-3, 1e-3,
    ...                                     np.random.default_rng(0))
    >>> v_m.shape, bool((noise[:, 2] == 0).all()), bool((noise[:, :2] != 0).all())
    ((4, 3), True, True)
    """
    v_t, d_t, p_t, g_t = flows
    v_m = v_t + sigma_v * rng.standard_normal(v_t.shape)
    d_m = d_t + sigma_delta * rng.standard_normal(d_t.shape)
    noise_p = np.zeros_like(p_t)
    for i in measured:  # meter noise relative to each bus's own physics power
        noise_p[:, i] = add_noise(p_t[:, i] - g_t[:, i], snr_db, rng)
    return v_m, d_m, noise_p


@dataclass(frozen=True)
class GridTruth:
    """What the simulation knows and a bus problem needs: line parameters, adjacency, the true
    metered power ``p`` and behind-the-meter generation ``g`` (n, nb), the units, the nominal loads.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.signals.grid_flow import adjacency
    >>> G = np.array([[4.0, -4, 0], [-4, 9, -5], [0, -5, 5]])      # lines 0-1 and 1-2
    >>> B = -3 * G
    >>> rng = np.random.default_rng(0)
    >>> v, delta = 1 + 0.01 * rng.standard_normal((6, 3)), 0.01 * rng.standard_normal((6, 3))
    >>> zero = np.zeros((6, 3))
    >>> truth = GridTruth(G=G, B=B, adj=adjacency(G, B), p=zero, g=zero, btm={},
    ...                   nominal=np.array([0.0, 0.5, 0.3]))           # no customer load at bus 0
    >>> truth.adj.astype(int).tolist()
    [[0, 1, 0], [1, 0, 1], [0, 1, 0]]
    """

    G: np.ndarray
    B: np.ndarray
    adj: np.ndarray
    p: np.ndarray
    g: np.ndarray
    btm: dict
    nominal: np.ndarray


def bus_problem(case: str, i: int, others, measured_arrays, truth: GridTruth, snr_db: float) -> Dataset:
    """The separation problem of bus i's complete equation (candidates ``others``).

    ``measured_arrays`` = (v, delta, p, metering noise) as measured. Behind-the-meter generation sits
    behind customers' meters: a bus without customer load (slack or generator bus) has none, and its
    equation needs no disturbance class.

    Parameters
    ----------
    case : str
        Case name (for the description).
    i : int
        The bus of the equation.
    others : list of int
        Candidate neighbours (measured buses).
    measured_arrays : tuple of (n, nb) ndarray
        ``(v, delta, p, metering noise)`` as measured.
    truth : GridTruth
    snr_db : float

    Returns
    -------
    Dataset
        ``x = v_i``, ``y`` the metered power; class ``Convex()``, or ``Orthogonal()`` without customer load.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.signals.grid_flow import adjacency
    >>> G = np.array([[4.0, -4, 0], [-4, 9, -5], [0, -5, 5]])      # lines 0-1 and 1-2
    >>> B = -3 * G
    >>> rng = np.random.default_rng(0)
    >>> v, delta = 1 + 0.01 * rng.standard_normal((6, 3)), 0.01 * rng.standard_normal((6, 3))
    >>> zero = np.zeros((6, 3))
    >>> truth = GridTruth(G=G, B=B, adj=adjacency(G, B), p=zero, g=zero, btm={},
    ...                   nominal=np.array([0.0, 0.5, 0.3]))           # no customer load at bus 0
    >>> pr = bus_problem("toy", 1, [0, 2], (v, delta, zero, zero), truth, 60.0)
    >>> pr.basis.names, type(pr.disturbance).__name__, pr.extras["lines"]
    (('G[1,0]', 'B[1,0]', 'G[1,2]', 'B[1,2]'), 'Convex', [0, 2])
    >>> pr.theta_true["B[1,2]"]
    15.0
    >>> type(bus_problem("toy", 0, [1, 2], (v, delta, zero, zero), truth, 60.0).disturbance).__name__
    'Orthogonal'
    """
    v_m, d_m, p_m, noise_p = measured_arrays
    G, B, unit, served = truth.G, truth.B, truth.btm.get(i), truth.nominal[i] > 0
    F, names = row_columns(v_m, d_m, i, others)
    theta = {f"{s}[{i},{k}]": float(M[i, k]) for k in others for s, M in (("G", G), ("B", B))}
    desc = (f"{case} bus {i}: metered real power = power flow + "
            f"{'behind-the-meter ' + unit['kind'] if unit else 'no behind-the-meter'} generation; "
            + ("class Convex() in v_i" if served else "no customer load: no disturbance class"))
    return Dataset(
        name="power_grid", x=v_m[:, i].copy(), y=p_m[:, i].copy(), basis=Basis.from_matrix(F, names),
        disturbance=Convex() if served else Orthogonal(), theta_true=theta,
        physics=truth.p[:, i] - truth.g[:, i], disturbance_true=truth.g[:, i].copy(), noise=noise_p[:, i],
        snr_db=snr_db, description=desc, targets=tuple(names), identified="set" if served else "point",
        extras={"bus": i, "btm": unit, "lines": [k for k in others if truth.adj[i, k]]})


def three_bus_chain(sigma_meter: float = 0.0) -> tuple[GridDataset, list[str]]:
    """A small record for examples: a three-bus chain (lines 0-1, 1-2), 60 snapshots, with only bus
    1's equation complete (candidates 0 and 2) and 1e-4 p.u. noise on its metered power.

    Parameters
    ----------
    sigma_meter : float
        The voltage meters' stated noise (``sigma_v`` and ``sigma_delta``); the voltages themselves
        are exact.

    Returns
    -------
    ds : GridDataset
    names : list of str
        Bus 1's coefficient names, in column order.

    Examples
    --------
    >>> ds, names = three_bus_chain()
    >>> ds.v.shape, ds.rows, names
    ((60, 3), (1,), ['G[1,0]', 'B[1,0]', 'G[1,2]', 'B[1,2]'])
    """
    G = np.array([[4.0, -4, 0], [-4, 9, -5], [0, -5, 5]])
    B, n, rng = -3 * G, 60, np.random.default_rng(0)
    v, delta = 1 + 0.01 * rng.standard_normal((n, 3)), 0.01 * rng.standard_normal((n, 3))
    F, names = row_columns(v, delta, 1, [0, 2])
    p, noise, zero = np.zeros((n, 3)), np.zeros((n, 3)), np.zeros((n, 3))
    p[:, 1] = F @ np.array([G[1, 0], B[1, 0], G[1, 2], B[1, 2]])
    noise[:, 1] = 1e-4 * rng.standard_normal(n)
    truth = GridTruth(G=G, B=B, adj=adjacency(G, B), p=p, g=zero, btm={}, nominal=np.array([0, 0.5, 0.3]))
    problem = bus_problem("toy", 1, [0, 2], (v, delta, p + noise, noise), truth, 60.0)
    ds = GridDataset(name="power_grid", case="toy", G=G, B=B, measured=(0, 1, 2), rows=(1,), excluded={},
                     v=v, delta=delta, p=p + noise, g=zero, btm={}, problems=(problem,), snr_db=60.0,
                     sigma_v=sigma_meter, sigma_delta=sigma_meter, description="toy")
    return ds, names
