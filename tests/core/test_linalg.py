"""The core's numerics (odnn_sep.core.linalg): solves, projectors, standard errors, variable projection.

Several tests replay, line for line, the hand-written algebra the front-ends used before calling the
core, and require the core function to give the same bits: those are the drop-in guarantees.
"""
import numpy as np
import pytest
from scipy import linalg as sla
from scipy import stats

from odnn_sep.core import linalg
from odnn_sep.core.linear import lstsq
from odnn_sep.errors import InputError


def _design(n=200, p=4, seed=0, complex_=False):
    rng = np.random.default_rng(seed)
    F = rng.standard_normal((n, p))
    if complex_:
        F = F + 1j * rng.standard_normal((n, p))
    theta = rng.standard_normal(p) * (1 + 1j if complex_ else 1)
    return F, theta, rng


def test_z95_is_the_normal_quantile():
    assert linalg.Z95 == float(stats.norm.ppf(0.975))


@pytest.mark.parametrize("method", ["auto", "cholesky", "qr", "lstsq"])
def test_solve_methods_recover_theta_weighted_and_multi_rhs(method):
    F, theta, rng = _design()
    w = 0.5 + rng.random(F.shape[0])
    y = F @ theta + 0.01 * rng.standard_normal(F.shape[0])
    ref = np.linalg.lstsq(F * np.sqrt(w)[:, None], y * np.sqrt(w), rcond=None)[0]
    np.testing.assert_allclose(linalg.solve(F, y, weights=w, method=method), ref, rtol=1e-10, atol=1e-12)
    Y = np.c_[y, 2 * y]
    np.testing.assert_allclose(linalg.solve(F, Y, weights=w, method=method), np.c_[ref, 2 * ref], rtol=1e-10)


def test_solve_complex_and_covariance():
    F, theta, rng = _design(complex_=True)
    y = F @ theta
    for method in ("auto", "qr", "lstsq"):
        np.testing.assert_allclose(linalg.solve(F, y, method=method), theta, rtol=1e-10)
    th, cov, rank = linalg.solve(F, y, method="auto", return_cov=True)
    assert rank == 4
    np.testing.assert_allclose(cov, np.linalg.inv(F.conj().T @ F), rtol=1e-9)
    _, cov_qr, _ = linalg.solve(F, y, method="qr", return_cov=True)
    np.testing.assert_allclose(cov_qr, cov, rtol=1e-9)


def test_solve_falls_back_to_pivoted_qr_on_collinear_columns():
    x = np.linspace(0, 1, 100)
    F = np.c_[x, 2 * x, np.ones_like(x)]           # exactly rank 2
    y = 3 * x + 1
    theta, cov, rank = linalg.solve(F, y, return_cov=True)   # Cholesky refuses, QR takes over
    assert rank == 2
    np.testing.assert_allclose(F @ theta, y, atol=1e-12)
    assert linalg.factor_gram(F.T @ F).rcond < 1 / linalg.MAX_COND


def test_lstsq_is_solve_by_qr_bit_for_bit():
    F, theta, rng = _design(seed=3)
    y = F @ theta + rng.standard_normal(F.shape[0])
    w = rng.random(F.shape[0])
    a = lstsq(F, y, w)
    b = linalg.solve(F, y, weights=w, method="qr", return_cov=True)
    assert np.array_equal(a.theta, b.theta) and np.array_equal(a.cov_unscaled, b.cov_unscaled) and a.rank == b.rank
    assert np.array_equal(linalg.solve(F, y, weights=w, method="qr"), a.theta)


def _audio_block_solve(G, rhs):
    """The Cholesky-with-check block of odnn_sep/audio/fit.py and audio/fullblock.py, as written there."""
    d = np.sqrt(np.maximum(np.diag(G), 1e-300))
    try:
        c, low = sla.cho_factor(G / np.outer(d, d), check_finite=False)
        rc = np.diag(c).min() / np.diag(c).max()
    except sla.LinAlgError:
        return None, 0.0
    return sla.cho_solve((c, low), rhs / d[:, None], check_finite=False) / d[:, None], rc ** 2


def test_factor_gram_reproduces_the_audio_block_solve_bit_for_bit():
    t = np.arange(4000) / 4000
    F = np.stack([f(2 * np.pi * k * 50 * t) for k in (1, 2, 3) for f in (np.cos, np.sin)], 1)
    w = np.sin(np.pi * np.arange(4000) / 4000) ** 2
    rng = np.random.default_rng(1)
    Y = F @ rng.standard_normal((6, 2)) + rng.standard_normal((4000, 2))
    G = (F * w[:, None]).T @ F
    rhs = F.T @ (Y * w[:, None])
    ref, rc2 = _audio_block_solve(G, rhs)
    fac = linalg.factor_gram(G)
    assert fac.rcond == rc2
    assert np.array_equal(fac.solve(rhs), ref)
    assert np.array_equal(linalg.solve_batched(G, rhs), ref)
    bad = linalg.factor_gram(np.array([[1.0, 1.0], [1.0, 1.0 - 1e-17]]))
    assert bad.rcond == 0.0 and not bad.ok


def test_solve_batched_stack_with_per_system_fallback():
    rng = np.random.default_rng(2)
    A = rng.standard_normal((50, 30, 4))
    G = A.transpose(0, 2, 1) @ A
    G[7] = np.outer([1, 2, 3, 4.0], [1, 2, 3, 4.0])        # singular: minimum-norm fallback
    r = rng.standard_normal((50, 4, 3))
    x = linalg.solve_batched(G, r)
    for i in range(50):
        ref = np.linalg.lstsq(G[i], r[i], rcond=None)[0] if i == 7 else np.linalg.solve(G[i], r[i])
        np.testing.assert_allclose(x[i], ref, rtol=1e-9, atol=1e-12)
    xv = linalg.solve_batched(G[:3], r[:3, :, 0][..., None])[..., 0]
    np.testing.assert_allclose(xv, x[:3, :, 0], rtol=1e-12)
    with pytest.raises(InputError, match="stack of square"):
        linalg.solve_batched(np.ones((3, 2)), np.ones(3))


def test_projector_properties_real_complex_weighted():
    x = np.linspace(-1, 1, 40)
    A = np.c_[np.ones_like(x), x, x + 1]                  # rank 2
    P = linalg.Projector(A)
    assert P.rank == 2
    v = np.cos(3 * x)
    np.testing.assert_allclose(P.project(P.project(v)), P.project(v), atol=1e-13)
    assert abs(A[:, :2].T @ P.project_out(v)).max() < 1e-12
    Pc = linalg.Projector(A[:, :2] * (1 + 2j))
    np.testing.assert_allclose(Pc.project(v * 1j), P.project(v) * 1j, atol=1e-13)
    w = np.r_[np.zeros(5), 1 + np.random.default_rng(0).random(35)]
    Pw = linalg.Projector(A, weights=w)
    beta = np.linalg.lstsq(A[:, :2] * np.sqrt(w)[:, None], v * np.sqrt(w), rcond=None)[0]
    np.testing.assert_allclose(Pw.project(v), A[:, :2] @ beta, atol=1e-12)
    np.testing.assert_allclose(Pw.project(np.c_[v, v]), np.c_[A[:, :2] @ beta, A[:, :2] @ beta], atol=1e-12)
    np.testing.assert_allclose(linalg.project_out(v, A, w), v - A[:, :2] @ beta, atol=1e-12)


def test_orthonormal_basis_qr_is_the_mismatch_rules_bit_for_bit():
    rng = np.random.default_rng(4)
    G = rng.standard_normal((100, 5))
    G[:, 4] = G[:, 0] + G[:, 1]
    q, r = np.linalg.qr(G)                                         # mismatch/fitting.py: orthonormal
    keep = np.abs(np.diag(r)) > 1e-10 * max(1.0, np.abs(np.diag(r)).max())
    assert np.array_equal(linalg.orthonormal_basis(G, method="qr", rtol=1e-10, min_scale=1.0), q[:, keep])
    keep8 = np.abs(np.diag(r)) > 1e-8 * np.abs(np.diag(r)).max()    # mismatch/calibrate.py: slow modes
    assert np.array_equal(linalg.orthonormal_basis(G, method="qr", rtol=1e-8), q[:, keep8])
    assert linalg.orthonormal_basis(G).shape == (100, 4)
    Q = linalg.Projector(G, method="qr", rtol=1e-10, min_scale=1.0).Q
    y = rng.standard_normal(100)
    assert np.array_equal(linalg.Projector(G, method="qr", rtol=1e-10, min_scale=1.0).project_out(y),
                          y - Q @ (Q.T @ y))


def test_standard_errors_match_the_pinv_formula_bit_for_bit():
    rng = np.random.default_rng(5)
    J = rng.standard_normal((80, 3))
    r = rng.standard_normal(80)
    rss, dof = float(np.sum(r ** 2)), 77
    cov = rss / dof * np.linalg.pinv(J.T @ J)                       # mismatch/fitting.py
    ref = [float(np.sqrt(max(cov[i, i], 0.0))) for i in range(3)]
    assert linalg.standard_errors(J, sigma2=rss / dof).tolist() == ref
    s2 = float(r @ r / dof)                                         # Separator's phi errors
    assert np.array_equal(linalg.standard_errors(J, r, dof), np.sqrt(np.maximum(np.diag(np.linalg.pinv(J.T @ J) * s2), 0)))
    with pytest.raises(InputError, match="resid and dof"):
        linalg.standard_errors(J)


def test_intervals_noise_variance_stderr():
    iv = linalg.intervals([1.0, 2.0], [0.1, 0.2])
    np.testing.assert_allclose(iv[:, 1] - iv[:, 0], 2 * linalg.Z95 * np.array([0.1, 0.2]))
    np.testing.assert_allclose(linalg.intervals([0.0], [1.0], level=0.9), [[-1.6448536269514722, 1.6448536269514722]])
    with pytest.raises(InputError, match="level"):
        linalg.intervals([0.0], [1.0], level=1.5)
    assert np.isnan(linalg.noise_variance([1.0], 0))
    assert linalg.noise_variance([1.0, 2.0], 1, weights=[2.0, 0.5]) == 4.0
    np.testing.assert_allclose(linalg.stderr_from_cov(np.diag([4.0, 9.0]), 1.0), [2.0, 3.0])


def test_varpro_recovers_a_frequency_with_a_periodic_disturbance_projected_out():
    t = np.arange(400.0)
    design = lambda v: np.c_[np.sin(v[0] * t), np.cos(v[0] * t)]   # noqa: E731
    P = linalg.Projector(np.c_[np.ones_like(t), np.cos(2 * np.pi * t / 100), np.sin(2 * np.pi * t / 100)])
    y = design([0.3]) @ [1.0, -0.5] + 2 * np.cos(2 * np.pi * t / 100) + 0.5
    resid = linalg.varpro_residual(design, y, project_out=P.project_out)
    fit = linalg.varpro(resid, [np.array([0.29]), np.array([0.31])], (np.array([0.2]), np.array([0.4])))
    assert abs(fit.phi[0] - 0.3) < 1e-9 and fit.cost < 1e-15 and fit.n_starts == 2 and fit.jac.shape == (400, 1)
    scalar = linalg.varpro(resid, [np.array([0.299])], (np.array([0.2]), np.array([0.4])), scalar=True)
    assert abs(scalar.phi[0] - 0.3) < 1e-5 and scalar.jac is None


def test_bad_options_are_one_line_errors():
    with pytest.raises(InputError, match="method must be one of 'auto', 'cholesky', 'qr', 'lstsq'; got 'svd'"):
        linalg.solve(np.eye(3), np.ones(3), method="svd")
    with pytest.raises(InputError, match="same n"):
        linalg.solve(np.eye(3), np.ones(4))
    with pytest.raises(InputError, match="weights must be 3"):
        linalg.Projector(np.eye(3), weights=[1.0, -1.0, 1.0])
