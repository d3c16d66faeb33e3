"""The humanoid stand-up reward under disturbance (paper App. C.4), with gymnasium's MuJoCo HumanoidStandup.

Transitions are collected from policies of several qualities (zero, uniformly random, linear gaits
with random weights). The true reward of a step is the upward velocity term and the control cost,

    r = theta_up (z_after - z_before) - theta_ctrl_neg * sum(a^2)   ( theta_up = w_up / dt ),

with unknown coefficients. (The paper writes z/dt; gymnasium's ``reward_linup`` is ``z_after /
timestep``. A reward linear in the height z cannot be separated from *any* shape class of functions
of z: a linear term is convex, concave and monotone at once, and over the reachable heights,
0.05-1.4 m, sin z is itself increasing. The velocity form is what "reward for upward movement"
means, and it is separable.)

The recorded reward is corrupted by a disturbance a user would meet:

* ``sin``: the paper's ``A sin(z_after)`` — a function of height only;
* ``drift``: a sensor drift over the recording, a cubic in wall-clock time;
* ``calibration``: a periodic calibration error, a sawtooth with a known period (50 steps);
* ``all``: the three together.

Contrast: the physics column is a *change* of height between consecutive frames (and the action
energy); the disturbances are smooth functions of the height, of the time, or periodic in time.
Each class is a linear subspace (``Subspace``): Legendre polynomials of z_after up to degree 9
(sin z is inside to better than 1e-6 of its size on the reachable range), of time up to degree 5, and the indicator
columns of the calibration phase. Subspace classes **point-identify** the coefficients.

Noise: white Gaussian on the recorded reward at ``snr_db`` relative to the true reward's power.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from odnn_sep.core import Basis, Subspace
from odnn_sep.errors import InputError, check_option
from odnn_sep.signals.dataset import Dataset, check_n, check_snr, check_theta, make, pick, rng_from
from odnn_sep.signals.humanoid_policies import (
    MAX_STEPS,
    LinearGait,
    make_env,
    random_policy,
    rollout,
    zero_policy,
)

KINDS = ("sin", "drift", "calibration", "all")
CALIBRATION_PERIOD = 50
MAX_TRANSITIONS = 200_000
TIMESTEP = 0.003  # MuJoCo model timestep of HumanoidStandup (s)


def _legendre(u: np.ndarray, degree: int) -> np.ndarray:
    return np.polynomial.legendre.legvander(u, degree)


def _to_unit(v: np.ndarray) -> np.ndarray:
    lo, hi = float(v.min()), float(v.max())
    return 2 * (v - lo) / (hi - lo) - 1 if hi > lo else np.zeros_like(v)


@dataclass(frozen=True)
class Corruption:
    """The disturbance added to the recorded reward; callable on new transitions for policy search.

    Examples
    --------
    >>> c = Corruption(kind="sin", amp_sin=2.0, horizon=10)
    >>> round(float(c(np.array([np.pi / 2]), np.array([0]))[0]), 6)
    2.0
    """

    kind: str
    amp_sin: float = 0.0
    drift: tuple = (0.0, 0.0, 0.0, 0.0)
    amp_cal: float = 0.0
    horizon: int = 1

    def __call__(self, z_after: np.ndarray, step: np.ndarray) -> np.ndarray:
        u = 2 * np.asarray(step, dtype=float) / max(self.horizon - 1, 1) - 1
        g = self.amp_sin * np.sin(z_after)
        g = g + np.polynomial.polynomial.polyval(u, self.drift)
        phase = (np.asarray(step) % CALIBRATION_PERIOD) / CALIBRATION_PERIOD
        return g + self.amp_cal * (phase - 0.5)


def disturbance_columns(kind: str, z_after: np.ndarray, step: np.ndarray) -> np.ndarray:
    """Columns spanning the disturbance class of ``kind`` on these transitions.

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`: ``"sin"``, ``"drift"``, ``"calibration"`` or ``"all"``.
    z_after : (n,) ndarray
        Torso height after each transition.
    step : (n,) ndarray of int
        Step number of each transition within its episode.

    Returns
    -------
    (n, m) ndarray
        A constant, then the columns of the kind (polynomials in height and step, step-periodic indicators).

    Examples
    --------
    >>> disturbance_columns("sin", np.linspace(0.5, 1.5, 50), np.arange(50)).shape   # constant + degrees 0-9
    (50, 11)
    """
    cols = [np.ones((z_after.size, 1))]
    if kind in ("sin", "all"):
        cols.append(_legendre(_to_unit(z_after), 9))
    if kind in ("drift", "all"):
        cols.append(_legendre(_to_unit(step.astype(float)), 5))
    if kind in ("calibration", "all"):
        cols.append(np.eye(CALIBRATION_PERIOD)[step % CALIBRATION_PERIOD])
    return np.hstack(cols)


@dataclass(frozen=True)
class HumanoidDataset:
    """Transitions, true and corrupted rewards, and the separation problem; :func:`humanoid` builds it.

    Examples
    --------
    >>> ds = humanoid(policies=2, episodes=1, steps=70, random_state=1)
    >>> ds.problem.x.shape, ds.z_after.shape == ds.ctrl_sq.shape
    ((140,), True)
    """

    name: str
    problem: Dataset
    kind: str
    dt: float
    policy_names: tuple
    policy_id: np.ndarray
    episode_id: np.ndarray
    z_before: np.ndarray
    z_after: np.ndarray
    ctrl_sq: np.ndarray
    corruption: Corruption
    snr_db: float
    description: str
    extras: dict = field(default_factory=dict)

    @property
    def reward_true(self) -> np.ndarray:
        """The uncorrupted reward of every transition (the physics part)."""
        return self.problem.physics

    @property
    def reward_observed(self) -> np.ndarray:
        """The reward as recorded: true reward + corruption + noise."""
        return self.problem.y

    def truth(self) -> dict:
        """JSON-ready truth: reward coefficients, time step, corruption kind and amplitudes, policy names."""
        return {"theta_true": self.problem.theta_true, "dt": self.dt, "kind": self.kind,
                "policies": list(self.policy_names), "corruption": self.corruption.__dict__}

    def arrays(self) -> dict:
        """Every per-transition array by name (for ``np.savez``)."""
        return {"step": self.problem.x, "z_before": self.z_before, "z_after": self.z_after, "ctrl_sq": self.ctrl_sq,
                "reward_observed": self.problem.y, "reward_true": self.problem.physics,
                "disturbance": self.problem.disturbance_true, "noise": self.problem.noise,
                "policy_id": self.policy_id, "episode_id": self.episode_id}


def default_policies(n: int, rng) -> list:
    """``n`` policies: zero, random, then linear gaits with weights of increasing scale.

    Parameters
    ----------
    n : int
        Number of policies.
    rng : numpy.random.Generator
        Source of the gait weights.

    Returns
    -------
    list of (str, callable)
        Name and policy, as :func:`~odnn_sep.signals.humanoid_policies.rollout` calls it.

    Examples
    --------
    >>> [name for name, _ in default_policies(4, np.random.default_rng(0))]
    ['zero', 'random', 'gait0', 'gait1']
    """
    pols = [("zero", zero_policy), ("random", random_policy)]
    for j, scale in enumerate(np.linspace(0.3, 2.0, max(n - 2, 0))):
        pols.append((f"gait{j}", LinearGait(scale * rng.standard_normal(68))))
    return pols[:n]


def draw_corruption(kind: str, horizon: int, rng) -> Corruption:
    """The reward corruption of ``kind`` with its amplitudes drawn (zero for the parts it lacks).

    Parameters
    ----------
    kind : str
        One of :data:`KINDS`.
    horizon : int
        Steps per episode.
    rng : numpy.random.Generator

    Returns
    -------
    Corruption

    Examples
    --------
    >>> c = draw_corruption("sin", 100, np.random.default_rng(0))
    >>> c.amp_sin > 0, c.amp_cal, c.drift
    (True, 0.0, (0.0, 0.0, 0.0, 0.0))
    """
    return Corruption(kind=kind, horizon=horizon,
                      amp_sin=float(rng.uniform(0.5, 2.0)) if kind in ("sin", "all") else 0.0,
                      drift=tuple(rng.uniform(-0.5, 0.5, 4)) if kind in ("drift", "all") else (0.0,) * 4,
                      amp_cal=float(rng.uniform(0.2, 0.5)) if kind in ("calibration", "all") else 0.0)


def draw_frame_skip(frame_skip, rng) -> int:
    """``frame_skip`` as an int in 1..20, or one drawn from 3..7 when None.

    Parameters
    ----------
    frame_skip : int or None
        The frame skip given, or None to draw one.
    rng : numpy.random.Generator or None
        Needed only when ``frame_skip`` is None.

    Returns
    -------
    int

    Raises
    ------
    odnn_sep.errors.InputError
        For a frame skip outside 1..20.

    Examples
    --------
    >>> draw_frame_skip(5, None), 3 <= draw_frame_skip(None, np.random.default_rng(0)) <= 7
    (5, True)
    """
    fs = int(frame_skip) if frame_skip is not None else int(rng.integers(3, 8))
    if not 1 <= fs <= 20:
        raise InputError(f"frame_skip must be in 1..20; got {frame_skip!r}")
    return fs


def check_sizes(policies, episodes, steps) -> tuple[int, int, int]:
    """``(policies, episodes, steps)`` as ints within their limits, or InputError.

    Parameters
    ----------
    policies, episodes, steps : int
        Numbers of policies, episodes per policy and steps per episode.

    Returns
    -------
    tuple of int

    Raises
    ------
    odnn_sep.errors.InputError
        For sizes beyond the limits, or too few transitions for the fit.

    Examples
    --------
    >>> check_sizes(6, 2, 100)
    (6, 2, 100)
    >>> check_sizes(2, 1, 20)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: too few transitions: 40 for 2 reward coefficients and up to 67 disturbance columns; need at least 138 (more episodes or steps)
    """
    policies = check_n(policies, 2, "policies")
    if policies > 50:
        raise InputError(f"policies={policies} is above the limit 50")
    episodes = check_n(episodes, 1, "episodes")
    steps = check_n(steps, 2, "steps")
    if steps > MAX_STEPS:
        raise InputError(f"steps={steps} is above the episode limit {MAX_STEPS}")
    n = policies * episodes * steps
    if n > MAX_TRANSITIONS:
        raise InputError(f"{n} transitions is above the limit {MAX_TRANSITIONS}; use fewer policies/episodes/steps")
    need = 2 + 1 + 10 + 6 + CALIBRATION_PERIOD
    if n < 2 * need:
        raise InputError(f"too few transitions: {n} for 2 reward coefficients and up to {need - 2} disturbance "
                         f"columns; need at least {2 * need} (more episodes or steps)")
    return policies, episodes, steps


def collect(frame_skip: int, policies, episodes: int, steps: int, rng) -> tuple[list, list, list]:
    """Roll out every ``(name, policy)`` for ``episodes`` episodes of ``steps`` steps in one environment:
    the per-episode records, policy ids and episode ids (needs gymnasium[mujoco]).

    The episodes are recorded round-robin (every policy once, then every policy again, ...), not
    policy after policy: the action energy is mostly a per-policy level, and in blocks of one policy
    it would follow the recording time, which is what a sensor drift (a smooth function of time)
    also does; interleaved, the drift class cannot imitate it (development draws: the action-energy
    coefficient's Cramér-Rao bound 2-3 times smaller at the same number of transitions).

    Parameters
    ----------
    frame_skip : int
        Simulator steps per action.
    policies : list of (str, callable)
        From :func:`default_policies`.
    episodes, steps : int
        Episodes per policy and steps per episode.
    rng : numpy.random.Generator
        Source of the reset seeds and the random actions.

    Returns
    -------
    recs : list of dict
        :func:`~odnn_sep.signals.humanoid_policies.rollout` records, policy by policy.
    pid, eid : list of ndarray
        Policy and episode id of every step, per record.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> recs, pid, eid = collect(5, default_policies(2, rng), 2, 10, rng)
    >>> len(recs), recs[0]["z_after"].shape, [int(p[0]) for p in pid], [int(e[0]) for e in eid]
    (4, (10,), [0, 1, 0, 1], [0, 2, 1, 3])
    """
    env = make_env(frame_skip)
    recs, pid, eid = [], [], []
    try:
        for e in range(episodes):
            for j, (_name, pol) in enumerate(policies):
                recs.append(rollout(env, pol, steps, seed=int(rng.integers(2**31)), rng=rng))
                pid.append(np.full(steps, j))
                eid.append(np.full(steps, j * episodes + e))
    finally:
        env.close()
    return recs, pid, eid


def humanoid(*, disturbance: str = "sin", policies: int = 6, episodes: int = 2, steps: int = 100,
             frame_skip: int | None = None, snr_db: float = 30.0, theta: dict | None = None,
             random_state: int | None = None) -> HumanoidDataset:
    """Collect HumanoidStandup transitions and corrupt their reward.

    Parameters
    ----------
    disturbance : {"sin", "drift", "calibration", "all"}
    policies : int
        Number of policies (zero, random, then random linear gaits), 2-50.
    episodes, steps : int
        Episodes per policy and steps per episode (at most 1000).
    frame_skip : int, optional
        MuJoCo steps per action (frame time ``frame_skip * 0.003`` s); drawn from 3-7 if omitted.
    snr_db : float
        True-reward-to-noise power ratio (dB).
    theta : dict, optional
        ``{"up": ..., "ctrl": ...}``: coefficient of the height change (default ``w/dt`` with w in
        [0.5, 1.5]) and of the action energy (default ``-U(0.05, 0.2)``).
    random_state : int or numpy Generator, optional

    Returns
    -------
    HumanoidDataset

    Examples
    --------
    >>> from odnn_sep.core import Separator
    >>> ds = humanoid(policies=2, episodes=1, steps=70, random_state=0); p = ds.problem
    >>> theta = Separator(p.basis, disturbance=p.disturbance).fit(p.x, p.y).result_.theta_dict()
    >>> ds.policy_names, all(abs(theta[k] / p.theta_true[k] - 1) < 0.05 for k in ("up", "ctrl"))
    (('zero', 'random'), True)
    """
    check_option("disturbance", disturbance, KINDS)
    policies, episodes, steps = check_sizes(policies, episodes, steps)
    n = policies * episodes * steps
    snr_db = check_snr(snr_db)
    check_theta(theta, ["up", "ctrl"])
    rng = rng_from(random_state)
    fs = draw_frame_skip(frame_skip, rng)
    dt = fs * TIMESTEP
    th = {"up": pick(rng, theta, "up", 0.5 / dt, 1.5 / dt), "ctrl": pick(rng, theta, "ctrl", -0.2, -0.05)}
    pols = default_policies(policies, rng)
    recs, pid, eid = collect(fs, pols, episodes, steps, rng)
    zb, za, cs = (np.concatenate([r[k] for r in recs]) for k in ("z_before", "z_after", "ctrl_sq"))
    step = np.arange(n)
    F = np.c_[za - zb, cs]
    physics = F @ np.array([th["up"], th["ctrl"]])
    corr = draw_corruption(disturbance, n, rng)
    g = corr(za, step)
    desc = (f"humanoid ({disturbance}): HumanoidStandup-v5, {policies} policies x {episodes} episodes x {steps} "
            f"steps, frame time {dt:.3f} s; reward = up*(z_after-z_before) + ctrl*|a|^2 + disturbance; "
            "class Subspace (smooth functions of height / time, calibration phase); point-identified")
    dist = Subspace(disturbance_columns(disturbance, za, step))
    prob = make("humanoid", step.astype(float), Basis.from_matrix(F, ["up", "ctrl"]), dist, th, physics, g, snr_db,
                rng, desc, targets=("up", "ctrl"))   # make draws the noise
    return HumanoidDataset(name="humanoid", problem=prob, kind=disturbance, dt=dt,
                           policy_names=tuple(nm for nm, _ in pols), policy_id=np.concatenate(pid),
                           episode_id=np.concatenate(eid), z_before=zb, z_after=za, ctrl_sq=cs, corruption=corr,
                           snr_db=snr_db, description=desc, extras={"policies": pols, "frame_skip": fs})
