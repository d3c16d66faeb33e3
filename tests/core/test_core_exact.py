"""Ground-truth recovery with the exact solver, for every disturbance class."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import (
    Band,
    Basis,
    Convex,
    Even,
    Monotone,
    Orthogonal,
    ParametricBasis,
    Periodic,
    Separator,
    Subspace,
)
from odnn_sep.errors import IdentifiabilityWarning

rng = np.random.default_rng(1)


def fit(basis, dist, x, y, **kw):
    return Separator(basis, disturbance=dist, **kw).fit(x, y).result_


def test_orthogonal_recovers_theta_with_disjoint_frequencies():
    x = np.arange(2000) / 1000.0
    y = 1.7 * np.sin(2 * np.pi * 50 * x) - 0.4 * np.cos(2 * np.pi * 53 * x) + 3 * np.sin(2 * np.pi * 47 * x)
    b = Basis([lambda x: np.sin(2 * np.pi * 50 * x), lambda x: np.cos(2 * np.pi * 53 * x)], names=["s50", "c53"])
    r = fit(b, Orthogonal(), x, y)
    np.testing.assert_allclose(r.theta, [1.7, -0.4], atol=1e-10)
    np.testing.assert_allclose(r.physics + r.disturbance + r.residual, y, atol=1e-12)


def test_even_2d_symmetric_disturbance():
    g = np.linspace(-1, 1, 41)
    X, Y = np.meshgrid(g, g)
    pts = np.c_[X.ravel(), Y.ravel()]
    dist_field = np.exp(-(pts[:, 0] ** 2 + pts[:, 1] ** 2)) + pts[:, 0] ** 2 * np.cos(3 * pts[:, 1])
    src = np.exp(-((pts[:, 0] + 1) ** 2 + (pts[:, 1] - 1) ** 2) / 0.2)
    y = 2.5 * src + dist_field
    r = fit(Basis.from_matrix(src[:, None], ["corner"]), Even(center=(0.0, 0.0)), pts, y)
    assert r.theta[0] == pytest.approx(2.5, rel=1e-9)
    # the disturbance estimate is itself even about both axes
    g2 = r.disturbance.reshape(41, 41)
    np.testing.assert_allclose(g2, g2[::-1, :], atol=1e-10)
    np.testing.assert_allclose(g2, g2[:, ::-1], atol=1e-10)


def test_periodic_exact_phase_average_and_fourier():
    t = np.arange(0, 10, 0.01)
    phase = np.arange(t.size) % 100  # exactly 100 samples per period
    per = np.where(phase < 37, 1.0, -0.5) + 0.3 * np.cos(6 * np.pi * phase / 100)  # any shape with period 1
    y = per + 0.8 * t * np.exp(-t / 5)
    b = Basis([lambda t: t * np.exp(-t / 5)], names=["a"])
    assert fit(b, Periodic(1.0), t, y).theta[0] == pytest.approx(0.8, rel=1e-9)
    t2 = np.linspace(0, 20, 1500)
    y2 = np.sin(5 * t2) + 0.7 * t2 * np.sin(5 * t2)
    r2 = fit(Basis([lambda t: t * np.sin(5 * t)], names=["a"]), Periodic(2 * np.pi / 5), t2, y2)
    assert r2.theta[0] == pytest.approx(0.7, rel=1e-6)


def test_band_disturbance_projected_out():
    n, sr = 4096, 1000.0
    t = np.arange(n) / sr
    low = np.cumsum(rng.normal(size=n))
    low = np.fft.irfft(np.fft.rfft(low) * (np.fft.rfftfreq(n, 1 / sr) <= 20), n=n)
    y = low + 0.9 * np.sin(2 * np.pi * 120 * t + 0.3)
    b = Basis([lambda t: np.sin(2 * np.pi * 120 * t + 0.3)], names=["line"])
    r = fit(b, Band(0, 20), t, y)
    assert r.theta[0] == pytest.approx(0.9, rel=1e-3)


def test_subspace_nuisance():
    t = np.linspace(0, 5, 500)
    G = np.c_[np.exp(-t) * np.sin(3 * t)]
    y = 2.0 * np.exp(-t) * np.cos(3 * t) + 5 * G[:, 0]
    r = fit(Basis([lambda t: np.exp(-t) * np.cos(3 * t)], names=["A"]), Subspace(G), t, y)
    assert r.theta[0] == pytest.approx(2.0, rel=1e-9)


def test_convex_identified_interval_matches_analysis():
    # y = x^2 + sin 5x on [-2, 2]: x^2 + c sin 5x is convex iff |c| <= 2/25 = 0.08 (appendix C.2)
    x = np.linspace(-2, 2, 401)
    with pytest.warns(IdentifiabilityWarning, match="set-identified"):
        r = fit(Basis([lambda x: np.sin(5 * x)], names=["a"]), Convex(), x, x ** 2 + np.sin(5 * x))
    lo, hi = r.interval[0]
    assert r.identified == "set"
    assert lo == pytest.approx(0.92, abs=0.01) and hi == pytest.approx(1.08, abs=0.01)
    assert lo <= 1.0 <= hi
    # the disturbance part is convex (non-negative second differences)
    assert np.diff(r.disturbance, 2).min() > -1e-9


def test_monotone_interval_contains_truth_and_g_is_monotone():
    x = np.linspace(-1, 1, 300)
    y = np.exp(x) + 1.3 * np.sin(5 * x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdentifiabilityWarning)
        r = fit(Basis([lambda x: np.sin(5 * x)], names=["a"]), Monotone(), x, y)
    lo, hi = r.interval[0]
    assert lo <= 1.3 <= hi
    assert np.diff(r.disturbance).min() > -1e-9


def test_stderr_is_calibrated_under_white_noise():
    # coverage of the 95 % interval over repeated noise draws
    x = np.linspace(-1, 1, 201)
    b = Basis([lambda x: x ** 3], names=["a"])
    hits = 0
    for s in range(200):
        y = 0.3 * x ** 3 + np.cos(2 * x) + np.random.default_rng(s).normal(scale=0.05, size=x.size)
        lo, hi = fit(b, Even(), x, y).interval[0]
        hits += lo <= 0.3 <= hi
    assert 0.90 <= hits / 200 <= 0.99


def test_parametric_frequency_with_grid_search():
    t = np.arange(0, 2, 1 / 500)
    y = 0.8 * np.sin(2 * np.pi * 60.3 * t) + 0.2 * np.cos(2 * np.pi * 60.3 * t) + 0.5 * np.sin(2 * np.pi * 13 * t)
    pb = ParametricBasis(
        lambda t, xp=np, f=60.0: xp.stack([xp.sin(2 * np.pi * f * t), xp.cos(2 * np.pi * f * t)], 1),
        phi0={"f": 60.0}, bounds={"f": (55.0, 65.0)}, names=["s", "c"], grid={"f": np.arange(55, 65, 0.25)},
    )
    r = fit(pb, Orthogonal(), t, y)
    assert r.phi["f"] == pytest.approx(60.3, abs=1e-3)
    np.testing.assert_allclose(r.theta, [0.8, 0.2], atol=2e-3)
    assert r.phi_stderr["f"] >= 0


def test_weighted_orthogonal_downweights_outliers():
    x = np.linspace(0, 1, 100)
    y = 2 * x + 1
    y[10] += 100
    w = np.ones_like(x)
    w[10] = 0
    r = Separator(Basis([np.ones_like, lambda x: x], names=["c", "m"])).fit(x, y, weights=w).result_
    np.testing.assert_allclose(r.theta, [1, 2], atol=1e-10)


def test_parametric_basis_is_differentiable_by_torch():
    torch = pytest.importorskip("torch")
    pb = ParametricBasis(lambda t, xp=np, f=1.0: xp.stack([xp.sin(2 * np.pi * f * t), xp.cos(2 * np.pi * f * t)], 1),
                         phi0={"f": 1.0}, names=["s", "c"])
    t = torch.linspace(0, 1, 50, dtype=torch.float64)
    f = torch.tensor(1.3, dtype=torch.float64, requires_grad=True)
    F = pb.evaluate(t, {"f": f}, xp=torch)
    F.sum().backward()
    expected = (2 * np.pi * t * (torch.cos(2 * np.pi * 1.3 * t) - torch.sin(2 * np.pi * 1.3 * t))).sum()
    assert float(f.grad) == pytest.approx(float(expected), rel=1e-9)
