"""Small policies for gymnasium's MuJoCo ``HumanoidStandup`` and the rollouts that record transitions.

A policy maps (observation, step) to a 17-dimensional action in [-0.4, 0.4]. Besides the zero and
uniformly random policies we use a tiny **linear gait policy** ``a = 0.4 tanh(W phi)`` on four
features ``phi = [1, sin(2 pi t / T), cos(2 pi t / T), 10 (z - z0)]`` (68 parameters), which a
cross-entropy search can optimise in a minute on a CPU.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.signals.optional import require

ACT_DIM, N_FEAT, GAIT_STEPS = 17, 4, 40
MAX_STEPS = 1000


def make_env(frame_skip: int = 5):
    """``HumanoidStandup-v5`` with the given frame skip (the model ships with the mujoco wheel).

    Parameters
    ----------
    frame_skip : int, optional
        Simulator steps per action.

    Returns
    -------
    gymnasium.Env

    Raises
    ------
    odnn_sep.errors.MissingDependencyError
        Without gymnasium or mujoco (the ``robotics`` extra).

    Examples
    --------
    >>> env = make_env(5)
    >>> env.action_space.shape
    (17,)
    >>> env.close()
    """
    gym = require("gymnasium", "robotics", "the humanoid dataset")
    require("mujoco", "robotics", "the humanoid dataset")
    return gym.make("HumanoidStandup-v5", frame_skip=int(frame_skip), max_episode_steps=MAX_STEPS)


class LinearGait:
    """``a = 0.4 tanh(W phi(obs, t))`` with ``W`` of shape (17, 4).

    Examples
    --------
    >>> a = LinearGait(np.ones(68))(z=1.0, z0=1.0, t=0, rng=None)
    >>> a.shape, bool(np.all(np.abs(a) <= 0.4))
    ((17,), True)
    """

    def __init__(self, W: np.ndarray):
        self.W = np.asarray(W, dtype=float).reshape(ACT_DIM, N_FEAT)

    def __call__(self, z: float, z0: float, t: int, rng) -> np.ndarray:
        w = 2 * np.pi * t / GAIT_STEPS
        phi = np.array([1.0, np.sin(w), np.cos(w), 10.0 * (z - z0)])
        return 0.4 * np.tanh(self.W @ phi)


def zero_policy(z, z0, t, rng):
    """No action (the humanoid lies still).

    Parameters
    ----------
    z, z0 : float
        Current and initial torso height.
    t : int
        Step within the episode.
    rng : numpy.random.Generator or None
        Source of random actions.

    Returns
    -------
    (17,) ndarray
        Zeros.

    Examples
    --------
    >>> zero_policy(1.0, 1.0, 0, None).shape
    (17,)
    """
    return np.zeros(ACT_DIM)


def random_policy(z, z0, t, rng):
    """Uniform random actions in [-0.4, 0.4].

    Parameters
    ----------
    z, z0 : float
        Current and initial torso height.
    t : int
        Step within the episode.
    rng : numpy.random.Generator or None
        Source of random actions.

    Returns
    -------
    (17,) ndarray
        Uniform in [-0.4, 0.4].

    Examples
    --------
    >>> bool(np.all(np.abs(random_policy(1.0, 1.0, 0, np.random.default_rng(0))) <= 0.4))
    True
    """
    return rng.uniform(-0.4, 0.4, ACT_DIM)


def rollout(env, policy, steps: int, seed: int, rng) -> dict:
    """One episode of ``steps`` steps; arrays z_before, z_after, ctrl_sq (sum of squared actions).

    Parameters
    ----------
    env : gymnasium.Env
        From :func:`make_env`.
    policy : callable
        ``policy(z, z0, t, rng) -> (17,) action``.
    steps : int
        Steps of the episode.
    seed : int
        Seed of ``env.reset``.
    rng : numpy.random.Generator
        Passed to the policy.

    Returns
    -------
    dict
        ``z_before``, ``z_after``, ``ctrl_sq``: (steps,) arrays.

    Examples
    --------
    >>> env = make_env(5)
    >>> rec = rollout(env, zero_policy, 5, seed=0, rng=np.random.default_rng(0))
    >>> env.close()
    >>> sorted(rec), rec["ctrl_sq"].tolist()
    (['ctrl_sq', 'z_after', 'z_before'], [0.0, 0.0, 0.0, 0.0, 0.0])
    """
    env.reset(seed=int(seed))
    data = env.unwrapped.data
    z0 = float(data.qpos[2])
    zb, za, cs = np.empty(steps), np.empty(steps), np.empty(steps)
    z = z0
    for t in range(steps):
        a = np.clip(policy(z, z0, t, rng), -0.4, 0.4)
        zb[t] = z
        env.step(a)
        z = float(data.qpos[2])
        za[t] = z
        cs[t] = float(np.square(data.ctrl).sum())
    return {"z_before": zb, "z_after": za, "ctrl_sq": cs}


def cem(score, *, iters: int, pop: int, elite: int, rng, sigma0: float = 0.5, init=None) -> tuple[np.ndarray, list]:
    """Cross-entropy search over the 68 gait weights maximising ``score(LinearGait)``.

    Returns the final mean weights and the best score per iteration.

    Parameters
    ----------
    score : callable
        ``LinearGait -> float``, to maximise.
    iters : int
        Iterations.
    pop : int
        Candidates per iteration.
    elite : int
        Best candidates kept to refit the search distribution.
    rng : numpy.random.Generator
    sigma0 : float, optional
        Initial standard deviation of each weight.
    init : array_like, optional
        Initial mean weights (68,), default zeros.

    Returns
    -------
    mu : (68,) ndarray
    history : list of float

    Examples
    --------
    >>> target = np.linspace(-1, 1, 68)
    >>> score = lambda gait: -float(np.sum((gait.W.ravel() - target) ** 2))
    >>> mu, history = cem(score, iters=15, pop=40, elite=8, rng=np.random.default_rng(0))
    >>> bool(history[-1] > history[0])
    True
    """
    mu = np.zeros(ACT_DIM * N_FEAT) if init is None else np.asarray(init, dtype=float).ravel()
    sd = np.full_like(mu, sigma0)
    history = []
    for _ in range(iters):
        cand = mu + sd * rng.standard_normal((pop, mu.size))
        scores = np.array([score(LinearGait(c)) for c in cand])
        best = cand[np.argsort(scores)[::-1][:elite]]
        mu, sd = best.mean(0), best.std(0) + 0.02
        history.append(float(scores.max()))
    return mu, history
