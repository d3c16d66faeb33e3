"""Humanoid stand-up reward: MuJoCo transitions, disturbance classes, identification, errors."""
import sys
import warnings

import numpy as np
import pytest

pytest.importorskip("gymnasium", reason="the humanoid dataset needs gymnasium[mujoco] (extra 'robotics')")
pytest.importorskip("mujoco", reason="the humanoid dataset needs gymnasium[mujoco] (extra 'robotics')")

from odnn_sep.core import Basis, Separator, Subspace  # noqa: E402
from odnn_sep.core.baselines import ols  # noqa: E402
from odnn_sep.errors import (  # noqa: E402
    InputError,
    MissingDependencyError,  # noqa: E402
    NotIdentifiableError,
)
from odnn_sep.signals import make_dataset  # noqa: E402
from odnn_sep.signals.humanoid import disturbance_columns  # noqa: E402

SMALL = dict(policies=3, episodes=1, steps=60)


@pytest.fixture(scope="module")
def all_kinds():
    return make_dataset("humanoid", disturbance="all", snr_db=40, random_state=5, **SMALL)


def test_transitions_and_truth(all_kinds):
    ds = all_kinds
    pr = ds.problem
    assert pr.y.shape == (180,) and ds.policy_names == ("zero", "random", "gait0")
    np.testing.assert_allclose(pr.y, pr.physics + pr.disturbance_true + pr.noise, atol=1e-12)
    # the physics is the upward velocity reward plus the control cost, at the frame time dt
    np.testing.assert_allclose(pr.physics, pr.theta_true["up"] * (ds.z_after - ds.z_before)
                               + pr.theta_true["ctrl"] * ds.ctrl_sq, rtol=1e-12)
    assert 0.5 / ds.dt <= pr.theta_true["up"] <= 1.5 / ds.dt
    assert np.all(ds.z_before[1:60] == ds.z_after[:59])  # consecutive frames of one episode


def test_disturbance_lies_in_its_class(all_kinds):
    ds = all_kinds
    G = disturbance_columns("all", ds.z_after, ds.problem.x.astype(int))
    coef, *_ = np.linalg.lstsq(G, ds.problem.disturbance_true, rcond=None)
    resid = ds.problem.disturbance_true - G @ coef
    assert np.abs(resid).max() < 1e-6 * np.abs(ds.problem.disturbance_true).max()


def test_odnn_point_identifies_where_ols_fails(all_kinds):
    pr = all_kinds.problem
    r = Separator(pr.basis, disturbance=pr.disturbance).fit(pr.x, pr.y).result_
    assert r.identified == "point"
    err = np.abs(r.theta - pr.theta_vector) / np.abs(pr.theta_vector)
    assert err.max() < 0.02
    assert np.all((r.interval[:, 0] < pr.theta_vector) & (pr.theta_vector < r.interval[:, 1]))
    err_ols = np.abs(ols(pr.design(), pr.y) - pr.theta_vector) / np.abs(pr.theta_vector)
    assert err_ols.max() > 5 * err.max()


def test_literal_height_reward_is_not_separable_from_sin_z(all_kinds):
    """The paper's z/dt reward is a function of z, like sin z: no class of functions of z separates it."""
    ds = all_kinds
    cols = disturbance_columns("sin", ds.z_after, ds.problem.x.astype(int))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        with pytest.raises(NotIdentifiableError, match="lies inside the disturbance class"):
            Separator(Basis.from_matrix(ds.z_after[:, None] / ds.dt, ["z_over_dt"]),
                      disturbance=Subspace(cols)).fit(ds.problem.x, ds.z_after / ds.dt + np.sin(ds.z_after))


def test_errors(monkeypatch):
    with pytest.raises(InputError, match="disturbance must be one of 'sin', 'drift', 'calibration', 'all'"):
        make_dataset("humanoid", disturbance="wind")
    with pytest.raises(InputError, match="too few transitions: 40"):
        make_dataset("humanoid", policies=2, episodes=1, steps=20)
    with pytest.raises(InputError, match="steps=5000 is above the episode limit"):
        make_dataset("humanoid", steps=5000)
    monkeypatch.setitem(sys.modules, "gymnasium", None)
    with pytest.raises(MissingDependencyError, match=r'pip install "odnn-sep\[robotics\]"'):
        make_dataset("humanoid", **SMALL)


def test_simulate_writes_npz(tmp_path):
    from odnn_sep.cli import main

    out = tmp_path / "h.npz"
    assert main(["simulate", "humanoid", "-o", str(out), "--truth", str(tmp_path / "t.json")]) == 0
    d = np.load(out)
    np.testing.assert_allclose(d["reward_observed"], d["reward_true"] + d["disturbance"] + d["noise"], atol=1e-12)
    assert main(["simulate", "humanoid", "-o", str(tmp_path / "h.csv")]) == 1


@pytest.mark.slow
def test_recipe_quick_runs():
    import subprocess
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    proc = subprocess.run([sys.executable, str(root / "recipes" / "humanoid.py"), "--quick"],
                          capture_output=True, text=True, timeout=600, cwd=root)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "| sin | 1 |" in proc.stdout and "Kendall" in proc.stdout
