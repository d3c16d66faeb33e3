"""Humanoid transitions are recorded round-robin over the policies, so a drift in time cannot imitate
the per-policy level of the action energy."""
import numpy as np
import pytest

pytest.importorskip("gymnasium", reason="the humanoid dataset needs gymnasium[mujoco] (extra 'robotics')")
pytest.importorskip("mujoco", reason="the humanoid dataset needs gymnasium[mujoco] (extra 'robotics')")

from odnn_sep.core import Basis, Subspace  # noqa: E402
from odnn_sep.core.bounds import efficiency_bound  # noqa: E402
from odnn_sep.signals import make_dataset  # noqa: E402
from odnn_sep.signals.humanoid import disturbance_columns  # noqa: E402


@pytest.fixture(scope="module")
def drift_ds():
    return make_dataset("humanoid", disturbance="drift", snr_db=30, random_state=3, policies=4, episodes=3, steps=60)


def test_episodes_interleaved(drift_ds):
    starts = drift_ds.policy_id[::60].tolist()
    assert starts == [0, 1, 2, 3] * 3
    # each (policy, episode) pair once, episodes of one policy spread over the recording
    assert len(set(drift_ds.episode_id[::60].tolist())) == 12


def _ctrl_bound(ds, order):
    """Cramér-Rao standard deviation of the action-energy coefficient with the transitions in ``order``."""
    pr = ds.problem
    F = np.c_[ds.z_after - ds.z_before, ds.ctrl_sq][order]
    step = np.arange(F.shape[0])
    dist = Subspace(disturbance_columns("drift", ds.z_after[order], step))
    cov = efficiency_bound(Basis.from_matrix(F, ["up", "ctrl"]), dist, step.astype(float), pr.theta_vector,
                           sigma=pr.noise_sigma)
    return float(np.sqrt(cov[1, 1]))


def test_interleaving_helps_against_drift(drift_ds):
    # the same transitions, as recorded and re-ordered policy after policy (episodes kept whole)
    n = drift_ds.policy_id.size
    recorded = np.arange(n)
    episodes = [np.arange(s, s + 60) for s in range(0, n, 60)]
    blocks = np.concatenate(sorted(episodes, key=lambda e: drift_ds.policy_id[e[0]]))
    assert _ctrl_bound(drift_ds, recorded) < 0.8 * _ctrl_bound(drift_ds, blocks)
