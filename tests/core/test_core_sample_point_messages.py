"""The errors for sample points a class cannot take say what is wrong with them and what to do."""
import numpy as np
import pytest

from odnn_sep.core.disturbance import Band, Even
from odnn_sep.errors import InputError


def test_shuffled_uniform_points_are_told_to_be_sorted_not_resampled():
    x = np.random.default_rng(0).permutation(np.linspace(-1, 1, 50))
    with pytest.raises(InputError, match="not sorted; sort the rows by x") as err:
        Band(0, 0.5).projector(x)
    assert "resample" not in str(err.value)


def test_points_uneven_after_sorting_are_still_told_to_resample():
    x = np.r_[np.linspace(-1, 0, 20), np.linspace(0.1, 1, 40)]
    with pytest.raises(InputError, match="resample onto a uniform grid"):
        Band(0, 0.5).projector(x)


def test_repeated_point_is_named_with_its_rows_and_value():
    x = np.r_[np.linspace(-1, 1, 41), 0.5]
    with pytest.raises(InputError, match=r"rows 30 and 41 \(x = 0.5\), and 1 row\(s\) in all repeat one; average"):
        Even().projector(x)
