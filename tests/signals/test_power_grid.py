"""Power-grid dataset: power-flow physics, partial observability, identification, errors."""
import sys
import warnings

import numpy as np
import pytest

pytest.importorskip("pandapower", reason="the power_grid dataset needs pandapower (extra 'grid')")

from odnn_sep.errors import InputError, MissingDependencyError  # noqa: E402
from odnn_sep.signals import make_dataset  # noqa: E402
from odnn_sep.signals.grid_identify import identify_grid  # noqa: E402


@pytest.fixture(scope="module")
def exact_grid():
    """No measurement noise: the columns evaluated on the data reproduce the physics exactly."""
    return make_dataset("power_grid", case="case14", snapshots=40, snr_db=np.inf, sigma_v=0, sigma_delta=0,
                        random_state=3)


def test_rows_are_the_complete_equations(exact_grid):
    ds = exact_grid
    assert ds.measured == (0, 1, 2, 3, 4, 5, 6, 8)
    assert ds.rows == (0, 1, 2, 3, 4)
    assert "not measured" in ds.excluded[5] and "not measured" in ds.excluded[8]
    assert len(ds.btm) > 0


def test_power_flow_basis_reproduces_metered_power(exact_grid):
    for pr in exact_grid.problems:
        np.testing.assert_allclose(pr.design() @ pr.theta_vector, pr.physics, atol=1e-8)
        np.testing.assert_allclose(pr.y, pr.physics + pr.disturbance_true + pr.noise, atol=1e-12)
        # candidates that are not lines have zero truth; true lines are non-zero
        for k in pr.extras["lines"]:
            assert pr.theta_true[f"B[{pr.extras['bus']},{k}]"] != 0


def test_behind_the_meter_generation_is_a_convex_function_of_voltage(exact_grid):
    from odnn_sep.signals.grid_profiles import btm_power

    kinds = set()
    for pr in exact_grid.problems:
        unit = pr.extras["btm"]
        if unit is None:
            assert np.all(pr.disturbance_true == 0)
            continue
        kinds.add(unit["kind"])
        np.testing.assert_allclose(pr.disturbance_true, btm_power(unit, pr.x), atol=1e-7)
        v = np.linspace(0.9, 1.1, 201)
        assert np.all(np.diff(btm_power(unit, v), 2) > 0)
    assert kinds


def test_identification_recovers_susceptances_and_zero_candidates(exact_grid):
    fit = identify_grid(exact_grid)
    b_err = [abs(e - t) / abs(t) for n, _i, _k, t, e, lo, hi, present, _pt in fit.table if n[0] == "B" and present]
    assert np.median(b_err) < 0.02
    absent = [(lo, hi) for n, _i, _k, t, e, lo, hi, present, _pt in fit.table if not present]
    assert absent and np.mean([lo <= 0 <= hi for lo, hi in absent]) > 0.8


def test_errors():
    with pytest.raises(InputError, match="measured bus 40 does not exist in case14"):
        make_dataset("power_grid", case="case14", snapshots=40, measured=[0, 1, 40])
    with pytest.raises(InputError, match="too few snapshots: 10 for"):
        make_dataset("power_grid", case="case14", snapshots=10)
    with pytest.raises(InputError, match="case 'case9999' is not available"):
        make_dataset("power_grid", case="case9999", snapshots=40)


def test_missing_pandapower_names_the_extra(monkeypatch):
    monkeypatch.setitem(sys.modules, "pandapower", None)
    with pytest.raises(MissingDependencyError, match=r'pip install "odnn-sep\[grid\]"'):
        make_dataset("power_grid", case="case14", snapshots=40)


def test_self_conductance_lies_inside_the_convex_class(exact_grid):
    """With a free G_ii column (v_i^2) the convex class cannot bound it on one side: refused, not a number."""
    from odnn_sep.core import Basis, Convex, Separator
    from odnn_sep.errors import NotIdentifiableError

    pr = exact_grid.problems[0]
    F = np.c_[pr.design(), pr.x**2]
    with warnings.catch_warnings(), pytest.raises(NotIdentifiableError, match="'Gsh'.* on one side"):
        warnings.simplefilter("ignore")
        Separator(Basis.from_matrix(F, [*pr.basis.names, "Gsh"]), disturbance=Convex()).fit(pr.x, pr.y)


@pytest.mark.slow
def test_recipe_quick_runs():
    import subprocess
    from pathlib import Path

    root = Path(__file__).resolve().parents[2]
    proc = subprocess.run([sys.executable, str(root / "recipes" / "power_grid.py"), "--quick", "--cases", "case14"],
                          capture_output=True, text=True, timeout=600, cwd=root)
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "| case14 | 1 |" in proc.stdout


def test_truth_and_arrays_are_writable(exact_grid, tmp_path):
    import json

    from odnn_sep.io_utils import to_jsonable

    truth = json.loads(json.dumps(to_jsonable(exact_grid.truth())))
    assert truth["rows"] == [0, 1, 2, 3, 4]
    assert {(d["i"], d["k"]) for d in truth["lines"]} == set(exact_grid.lines)
    arrays = exact_grid.arrays()
    np.savez(tmp_path / "g.npz", **arrays)
    assert arrays["v"].shape == (40, len(exact_grid.measured))


def test_newton_flow_agrees_with_pandapower_and_the_check_can_fail():
    """The fast flow is checked against pandapower.runpp; a wrong solution is caught."""
    from odnn_sep.signals.grid_flow import Schedule, check_with_pandapower, load_case, run_snapshots
    from odnn_sep.signals.grid_profiles import draw_btm

    rng = np.random.default_rng(0)
    net = load_case("case33bw")
    n = 3
    btm = {4: draw_btm("boost", 0.01, rng), 7: draw_btm("exponential", 0.01, rng)}
    mult, q = 0.5 + rng.random((n, len(net.load))), 0.1 * rng.standard_normal((n, len(net.load)))
    vs = np.array([1.0, 1.00625, 0.99375])
    v, d, p, g = run_snapshots(net, mult, vs, btm, q)  # checks snapshots 0 and 2 itself
    assert np.all(g[:, 4] > 0) and np.all(g[:, 7] > 0) and np.all(g[:, 5] == 0)
    sched = Schedule(load_case("case33bw"), mult, vs, q, None, None)  # nominal loads (the check edits net)
    check_with_pandapower(net, sched, 1, btm, g[1], v[1], d[1])
    with pytest.raises(RuntimeError, match="disagrees with pandapower"):
        check_with_pandapower(net, sched, 1, btm, g[1], v[1] + 1e-5, d[1])


def test_bus_without_customer_load_has_no_disturbance_class(exact_grid):
    from odnn_sep.core import Convex, Orthogonal

    by_bus = {pr.extras["bus"]: pr for pr in exact_grid.problems}
    assert isinstance(by_bus[0].disturbance, Orthogonal) and by_bus[0].identified == "point"  # slack, no load
    assert all(isinstance(pr.disturbance, Convex) for b, pr in by_bus.items() if b != 0)


def test_combine_weights_by_inverse_variance_and_widens_on_disagreement():
    from odnn_sep.signals.grid_identify import combine, line_key

    z = 1.959963984540054
    # two ends of line (1, 2): standard errors 1 and 2, agreeing within their widths
    rows = [("B[1,2]", 1, 2, 5.0, 5.0, 5.0 - z, 5.0 + z, True, False),
            ("B[2,1]", 2, 1, 5.0, 6.0, 6.0 - 2 * z, 6.0 + 2 * z, True, False)]
    (name, i, k, _t, est, lo, hi, _p, _pt), = combine(rows, line_key)
    assert (name, i, k) == ("B[1-2]", 1, 2)
    assert est == pytest.approx((5.0 + 6.0 / 4) / 1.25)
    assert hi - lo == pytest.approx(2 * z / np.sqrt(1.25))
    # the same estimates with ten times narrower intervals disagree: the interval widens by the Birge ratio
    tight = [(*r[:5], r[4] - (r[4] - r[5]) / 10, r[4] + (r[6] - r[4]) / 10, *r[7:]) for r in rows]
    (*_, lo2, hi2, _p2, _pt2), = combine(tight, line_key)
    chi2 = ((5.0 - est) / 0.1) ** 2 + ((6.0 - est) / 0.2) ** 2
    assert hi2 - lo2 == pytest.approx((hi - lo) / 10 * np.sqrt(chi2))
    # an unbounded piece is left to the bounded ones, and the quantity is then not point-identified
    (*_, est3, lo3, hi3, _p3, pt3), = combine([rows[0], ("B[2,1]", 2, 1, 5.0, 9.0, -np.inf, np.inf, True, False)],
                                                line_key)
    assert (est3, lo3, hi3, pt3) == (pytest.approx(5.0), pytest.approx(5 - z), pytest.approx(5 + z), False)


def test_chunk_option_is_checked(exact_grid):
    with pytest.raises(InputError, match="chunk"):
        identify_grid(exact_grid, chunk=1)


def test_regressor_noise_bias_removes_the_attenuation_of_least_squares():
    """y = 2 u with u measured as u + e (known sigma): least squares shrinks 2 towards 0; the bias
    estimate restores it (corrected normal equations), and the first-order fallback has the right sign."""
    from odnn_sep.core.linalg import solve
    from odnn_sep.signals.grid_eiv import corrected_normal_equations, regressor_noise_bias

    rng = np.random.default_rng(1)
    n, sigma = 20000, 0.5
    u = rng.standard_normal(n)
    um = u + sigma * rng.standard_normal(n)
    theta_hat = solve(um[:, None], 2 * u)
    assert theta_hat[0] == pytest.approx(2 / 1.25, rel=0.03)  # attenuation 1 / (1 + sigma^2)
    J = np.zeros((n, 1, 2))
    J[:, 0, 0] = 1.0  # d(column)/d(measured quantity); the second quantity does not enter
    b = regressor_noise_bias(um[:, None], um, J, sigma, 0.0, theta_hat, free_part=False)
    assert theta_hat[0] - b[0] == pytest.approx(2.0, rel=0.03)
    gram = np.array([[1.0]])
    assert corrected_normal_equations(gram, np.array([[0.9]]), np.array([1.0])) is None  # noise dominates


def test_identify_grid_shifts_by_the_voltage_noise_bias(exact_grid):
    """Without voltage noise there is no bias; with it, every equation's coefficients get one."""
    fit = identify_grid(exact_grid)
    assert fit.bias == {}
    noisy = make_dataset("power_grid", case="case14", snapshots=40, sigma_v=1e-4, sigma_delta=1e-4, random_state=3)
    names = {nm for pr in noisy.problems for nm in pr.basis.names}
    assert set(identify_grid(noisy).bias) == names
