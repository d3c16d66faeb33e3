"""Greedy peak picking of the search's score maps: same peaks as clearing a copy, map left as it was."""
import numpy as np
import pytest

from odnn_sep.image.features import peaks


def _reference(r, n, radius, floor):
    r = r.copy()
    out = []
    for _ in range(n):
        yy, xx = divmod(int(np.argmax(r)), r.shape[1])
        v = float(r[yy, xx])
        if v < floor:
            break
        out.append((v, yy, xx))
        r[max(0, yy - radius):yy + radius + 1, max(0, xx - radius):xx + radius + 1] = -1.0
    return out


@pytest.mark.parametrize("seed", range(5))
def test_peaks_as_on_a_copy_and_map_unchanged(seed):
    rng = np.random.default_rng(seed)
    r = rng.random((40, 57)).astype(np.float32)
    before = r.copy()
    for n, radius, floor in ((1, 2, 0.0), (3, 4, 0.5), (8, 1, 0.9), (50, 3, 0.0)):
        assert peaks(r, n, radius, floor) == _reference(r, n, radius, floor)
        assert np.array_equal(r, before)
