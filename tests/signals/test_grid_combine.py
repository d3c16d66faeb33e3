"""Combining pieces of a grid record: the part of an interval the disturbance class leaves open is
not averaged away by more pieces, so an absent candidate with a consistent small offset stays absent."""
import numpy as np
import pytest

from odnn_sep.core.linalg import Z95
from odnn_sep.signals.grid_identify import GridFit, combine, line_key, split_half_width


def _pieces(m, est, half, ratio, name="B[1,2]", true=0.0, present=False):
    return [(name, 1, 2, true, est, est - half, est + half, present, ratio) for _ in range(m)]


def test_split_half_width():
    noise, rest = split_half_width([3.0, 1.0], [1.5, 0.5])
    np.testing.assert_allclose(noise, [2.0, 1.0])
    np.testing.assert_allclose(rest, [1.0, 0.0])


def test_noise_part_shrinks_class_part_does_not():
    # pieces limited by noise only (ratio 1): 16 pieces give a 4 times narrower interval
    (*_, lo1, hi1, _p, _pt), = combine(_pieces(1, 0.0, 1.0, 1.0), line_key)
    (*_, lo16, hi16, _p, _pt), = combine(_pieces(16, 0.0, 1.0, 1.0), line_key)
    assert (hi16 - lo16) == pytest.approx((hi1 - lo1) / 4)
    # half of each half-width left open by the class (ratio 2): that half stays whatever the pieces
    (*_, lo, hi, _p, _pt), = combine(_pieces(16, 0.0, 1.0, 2.0), line_key)
    assert (hi - lo) / 2 == pytest.approx(0.5 / 4 + 0.5)


def test_consistent_offset_inside_the_class_range_is_not_a_line():
    # an absent candidate: every piece 0.3 off zero, each interval +-1 of which 0.5 is the class's range
    rows = _pieces(16, 0.3, 1.0, 2.0)
    fit = GridFit(table=combine(rows, line_key), seconds=0.0)
    assert fit.lines_found() == set() and fit.topology_exact()
    # the same offset with noise-limited pieces is significant: there the data do pin it down
    fit_noise = GridFit(table=combine(_pieces(16, 0.3, 1.0, 1.0), line_key), seconds=0.0)
    assert fit_noise.lines_found() == {(1, 2)}


def test_point_identified_needs_a_narrow_combined_interval():
    z = Z95
    tight = combine(_pieces(4, 10.0, 0.1 * z, 1.0, true=10.0, present=True), line_key)
    assert tight[0][8] is True
    loose = combine(_pieces(4, 10.0, 0.2, 2.5, true=10.0, present=True), line_key)  # ratio above NOISE_RATIO
    assert loose[0][8] is False


def test_voltage_noise_correction_holds_where_the_noise_is_over_half_the_spread():
    """y = 2 u with u measured as u + e, the noise 60 % of the measured spread (the feeder's worst
    equations): the corrected normal equations still apply and restore the slope; at 90 % they do not."""
    from odnn_sep.core.linalg import solve
    from odnn_sep.signals.grid_eiv import MAX_NOISE_SHARE, corrected_normal_equations, regressor_noise_bias

    rng = np.random.default_rng(2)
    n, sigma = 40000, np.sqrt(1.5)
    u = rng.standard_normal(n)
    um = u + sigma * rng.standard_normal(n)
    theta_hat = solve(um[:, None], 2 * u)
    J = np.zeros((n, 1, 2))
    J[:, 0, 0] = 1.0
    b = regressor_noise_bias(um[:, None], um, J, sigma, 0.0, theta_hat, free_part=False)
    assert theta_hat[0] == pytest.approx(0.8, rel=0.03)  # attenuated to 2 / 2.5
    assert theta_hat[0] - b[0] == pytest.approx(2.0, rel=0.04)
    assert 0.6 < MAX_NOISE_SHARE < 0.9
    assert corrected_normal_equations(np.array([[1.0]]), np.array([[0.9]]), np.array([1.0])) is None
