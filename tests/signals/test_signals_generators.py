"""Synthetic generators: reproducible, truth adds up, each disturbance really is in its class,
the physics is not, and the exact separator recovers the truth."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import Band, Convex, Even, Monotone, Orthogonal, Periodic, Separator, Subspace
from odnn_sep.errors import InputError
from odnn_sep.signals import (
    GENERATORS,
    aiba_edwards_mu,
    biology,
    explicit_1d,
    heat2d,
    make_dataset,
    population,
)

NAMES = list(GENERATORS)


@pytest.mark.parametrize("name", NAMES)
def test_same_seed_same_data_and_truth_adds_up(name):
    a, b = make_dataset(name, random_state=3), make_dataset(name, random_state=3)
    c = make_dataset(name, random_state=4)
    np.testing.assert_array_equal(a.y, b.y)
    np.testing.assert_array_equal(a.x, b.x)
    assert a.theta_true == b.theta_true
    assert not np.array_equal(a.y, c.y)
    np.testing.assert_allclose(a.y, a.physics + a.disturbance_true + a.noise, rtol=0, atol=1e-12)
    # physics really is the basis at the true parameters
    np.testing.assert_allclose(a.design() @ a.theta_vector, a.physics, rtol=1e-12, atol=1e-12)
    assert set(a.targets) <= set(a.theta_true)
    assert a.identified == ("set" if isinstance(a.disturbance, (Convex, Monotone)) else "point")


@pytest.mark.parametrize("name", NAMES)
def test_noise_is_at_the_stated_snr(name):
    ds = make_dataset(name, snr_db=20.0, random_state=0)
    snr = 10 * np.log10(np.mean(ds.physics**2) / np.mean(ds.noise**2))
    assert abs(snr - 20.0) < 1.0
    clean = make_dataset(name, snr_db=np.inf, random_state=0)
    assert not clean.noise.any()


def _in_class(ds) -> None:
    """Assert the true disturbance belongs to the dataset's class, checked from first principles."""
    g, x, d = ds.disturbance_true, ds.x, ds.disturbance
    scale = np.max(np.abs(g))
    if isinstance(d, Band):
        freqs = np.fft.rfftfreq(x.size, x[1] - x[0])
        spec = np.abs(np.fft.rfft(g))
        outside = (freqs < d.lo) | (freqs > d.hi)
        assert spec[outside].max() < 1e-9 * spec.max()
    elif isinstance(d, Orthogonal):
        F = ds.design()
        assert np.max(np.abs(F.T @ g)) < 1e-9 * np.linalg.norm(F) * np.linalg.norm(g)
    elif isinstance(d, Even):
        if x.ndim == 1:
            np.testing.assert_allclose(x, -x[::-1], atol=1e-12)
            np.testing.assert_allclose(g, g[::-1], atol=1e-12 * scale)
        else:  # heat2d: grid flattened with indexing="ij"
            nx, ny = np.unique(x[:, 0]).size, np.unique(x[:, 1]).size
            G = g.reshape(nx, ny)
            np.testing.assert_allclose(G, G[::-1, :], atol=1e-12 * scale)
            np.testing.assert_allclose(G, G[:, ::-1], atol=1e-12 * scale)
    elif isinstance(d, Periodic):
        step = x[1] - x[0]
        m = int(round(d.period / step))
        assert abs(m * step - d.period) < 1e-9 * d.period     # whole samples per period
        np.testing.assert_allclose(g[m:], g[:-m], atol=1e-10 * scale)
    elif isinstance(d, Subspace):
        G = np.asarray(d.G)
        coef, *_ = np.linalg.lstsq(G, g, rcond=None)
        np.testing.assert_allclose(G @ coef, g, atol=1e-10 * scale)
    elif isinstance(d, Convex):
        assert np.all(np.diff(g, 2) >= -1e-12 * scale)
    elif isinstance(d, Monotone):
        assert np.all(np.diff(g) * (1 if d.increasing else -1) >= -1e-12 * scale)
    else:  # pragma: no cover
        raise AssertionError(f"no membership check for {d!r}")


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("seed", [0, 1, 2])
def test_disturbance_is_in_its_class(name, seed):
    _in_class(make_dataset(name, random_state=seed))


@pytest.mark.parametrize("name", NAMES)
def test_physics_is_not_in_the_class(name):
    ds = make_dataset(name, random_state=0)
    d = ds.disturbance
    F = ds.design()
    if isinstance(d, Convex):
        assert np.any(np.diff(ds.physics, 2) < 0) and np.any(np.diff(ds.physics, 2) > 0)
    elif isinstance(d, Monotone):
        assert np.any(np.diff(ds.physics) < 0)
    elif isinstance(d, Orthogonal):
        assert np.linalg.matrix_rank(F) == F.shape[1]
    else:
        P = d.prepare(ds.x)
        outside = np.linalg.norm(F - P.apply(F), axis=0) / np.linalg.norm(F, axis=0)
        assert np.all(outside > 0.05), outside


@pytest.mark.parametrize("name", NAMES)
def test_exact_separator_recovers_truth_without_noise(name):
    ds = make_dataset(name, snr_db=np.inf, random_state=5)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
    est = {**r.theta_dict(), **r.phi}
    if ds.identified == "set":
        for k, (lo, hi) in zip(r.names, r.interval, strict=True):
            assert lo - 1e-6 <= ds.theta_true[k] <= hi + 1e-6
    else:
        for k, v in ds.theta_true.items():
            assert est[k] == pytest.approx(v, rel=1e-5), k


def test_explicit_1d_plain_least_squares_is_biased_but_band_is_not():
    ds = explicit_1d(snr_db=np.inf, random_state=0)
    F = ds.design()
    ols, *_ = np.linalg.lstsq(F, ds.y, rcond=None)
    assert np.max(np.abs(ols - ds.theta_vector) / np.abs(ds.theta_vector)) > 0.005  # leakage bias
    r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
    np.testing.assert_allclose(r.theta, ds.theta_vector, rtol=1e-8)


def test_biology_substrate_is_not_identified_from_mu():
    ds = biology(random_state=2)
    e = ds.extras
    assert e["S_same_mu"] is not None and abs(e["S_same_mu"] - e["S"]) > 0.1
    for S in (e["S"], e["S_same_mu"]):
        assert aiba_edwards_mu(S, e["mu_max"], e["K_S"], e["K_I"]) == pytest.approx(ds.theta_true["mu"], rel=1e-8)


def test_population_log_transform():
    ds = population(snr_db=np.inf, random_state=0)
    N = np.exp(ds.y)
    e = ds.extras
    # the seasonal factor repeats every year, so N grows by exactly (1 + r) per year
    per_year = int(round(1 / (ds.x[1] - ds.x[0])))
    np.testing.assert_allclose(N[per_year:] / N[:-per_year], 1 + e["r"], rtol=1e-10)


def test_theta_override_and_heat_grid_is_symmetric():
    ds = heat2d(theta={"Q0": 1.25}, random_state=0)
    assert ds.theta_true["Q0"] == 1.25
    assert ds.x.shape == (41 * 33, 2)


@pytest.mark.parametrize(
    "call, match",
    [
        (lambda: make_dataset("nope"), r"dataset must be one of 'explicit_1d', .*; got 'nope'"),
        (lambda: explicit_1d(n=10), r"n must be an integer >= 64; got 10"),
        (lambda: explicit_1d(snr_db="loud"), r"snr_db must be a number in dB \(or inf for no noise\); got 'loud'"),
        (lambda: explicit_1d(snr_db=float("nan")), r"snr_db must be a number in dB"),
        (lambda: explicit_1d(theta={"zz": 1.0}), r"theta has unknown parameter\(s\) \['zz'\]; allowed:"),
        (lambda: explicit_1d(theta={"a0": float("inf")}), r"theta\['a0'\] must be finite; got inf"),
        (lambda: explicit_1d(random_state=-1), r"random_state must be None, a non-negative int or a numpy"),
        (lambda: heat2d(nx=3), r"nx must be an integer >= 5; got 3"),
    ],
)
def test_bad_options_fail_clearly(call, match):
    with pytest.raises(InputError, match=match):
        call()


@pytest.mark.parametrize("name", ["implicit_convex", "implicit_monotone"])
def test_cone_cases_identified_set(name):
    ds = make_dataset(name, snr_db=np.inf, random_state=1)
    lo, hi = ds.extras["identified_set"]
    t = ds.theta_true["theta"]
    assert lo < t < hi and hi - lo > 0.05 * t  # a real interval, not a point
    s = ds.design()[:, 0]
    order = 2 if name == "implicit_convex" else 1
    for edge, inside in ((lo, True), (hi, True), (lo - 1e-3, False), (hi + 1e-3, False)):
        d = np.diff(ds.y - edge * s, order)
        assert bool(np.all(d >= -1e-9)) is inside
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
    np.testing.assert_allclose(r.interval[0], [lo, hi], atol=0.01 * t)
