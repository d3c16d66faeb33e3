"""Baselines: OLS, SINDy (STLSQ), regular DNN (Eq. 2), PINN-style penalty."""
import numpy as np
import pytest

from odnn_sep.core.baselines import ols, pinn_penalty, regular_dnn, sindy
from odnn_sep.errors import InputError

X = np.linspace(-np.pi, np.pi, 201)
F2 = np.c_[X**2 * np.sin(5 * X), np.sin(X)]


@pytest.fixture(autouse=True, scope="module")
def _single_thread():
    torch = pytest.importorskip("torch")
    prev = torch.get_num_threads()
    torch.set_num_threads(1)
    yield
    torch.set_num_threads(prev)


def test_ols_exact_on_noise_free_data():
    y = F2 @ [0.5, -2.0]
    np.testing.assert_allclose(ols(F2, y), [0.5, -2.0], rtol=1e-12)
    np.testing.assert_allclose(ols(F2[:, 0], 0.5 * F2[:, 0]), [0.5], rtol=1e-12)  # 1-D F is one column


def test_ols_does_not_mutate_inputs():
    F, y = F2.copy(), F2 @ [1.0, 1.0]
    y0 = y.copy()
    ols(F, y)
    np.testing.assert_array_equal(F, F2)
    np.testing.assert_array_equal(y, y0)


def test_sindy_matches_ols_and_thresholds_small_terms():
    pytest.importorskip("pysindy")
    y = F2 @ [0.5, -2.0]
    np.testing.assert_allclose(sindy(F2, y), [0.5, -2.0], rtol=1e-8)
    rng = np.random.default_rng(0)
    F3 = np.c_[F2, rng.standard_normal(X.size)]
    th = sindy(F3, F2 @ [0.5, -2.0] + 1e-4 * F3[:, 2], threshold=0.05)
    assert th[2] == 0.0 and th[0] == pytest.approx(0.5, rel=1e-3)


def test_torch_baselines_are_deterministic_and_shaped():
    y = 0.5 * F2[:, 0] + np.cos(X)
    a = regular_dnn(X, y, F2[:, :1], epochs=40, random_state=1)
    b = regular_dnn(X, y, F2[:, :1], epochs=40, random_state=1)
    c = regular_dnn(X, y, F2[:, :1], epochs=40, random_state=2)
    assert a.shape == (1,)
    np.testing.assert_array_equal(a, b)
    assert a[0] != c[0]
    p1 = pinn_penalty(X, y, F2[:, :1], epochs=40, random_state=1)
    np.testing.assert_array_equal(p1, pinn_penalty(X, y, F2[:, :1], epochs=40, random_state=1))


def test_pinn_penalty_pulls_towards_least_squares():
    # with an even disturbance and an odd basis on a symmetric grid OLS is unbiased; a strong
    # penalty keeps the physics out of the network, so theta lands near 0.5, unlike Eq. 2 alone
    y = 0.5 * F2[:, 0] + np.cos(X)
    th_pinn = pinn_penalty(X, y, F2[:, :1], lam=10.0, random_state=0)[0]
    th_dnn = regular_dnn(X, y, F2[:, :1], random_state=0)[0]
    assert abs(th_pinn - 0.5) < 0.02
    assert abs(th_pinn - 0.5) < abs(th_dnn - 0.5)


def test_regular_dnn_returns_loss_on_request():
    y = 0.5 * F2[:, 0] + np.cos(X)
    th, mse = regular_dnn(X, y, F2[:, :1], epochs=20, return_loss=True)
    assert th.shape == (1,) and np.isfinite(mse) and mse >= 0


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: ols(F2, np.ones(5)), r"F has 201 rows but y has 5 samples; they must match"),
        (lambda: ols(F2[:2], np.ones(2)), r"F has 2 columns but only 2 rows; need more samples than parameters"),
        (lambda: ols(F2, np.r_[np.nan, np.ones(200)]), r"y contains 1 NaN value\(s\) \(first at index 0\)"),
        (lambda: regular_dnn(X[:5], np.ones(201), F2), r"x has 5 samples but y has 201; they must match"),
        (lambda: regular_dnn(X, np.ones(201), F2, epochs=0), r"epochs must be a positive integer; got 0"),
        (lambda: regular_dnn(X, np.ones(201), F2, theta_init=[1, 2, 3]),
         r"theta_init must be a finite scalar or have 2 entries; got \[1, 2, 3\]"),
        (lambda: pinn_penalty(X, np.ones(201), F2, lam=0.0),
         r"lam must be a finite number > 0; got 0.0 \(use regular_dnn for lam = 0\)"),
        (lambda: pinn_penalty(X, np.ones(201), F2, lr=-1), r"lr must be > 0; got -1"),
    ],
)
def test_bad_inputs_fail_clearly(call, match):
    with pytest.raises(InputError, match=match):
        call()
