"""A cone fit that absorbs the noise (few points left to estimate it) says its set may be too narrow."""
import warnings

import numpy as np

from odnn_sep.core import Separator
from odnn_sep.signals import make_dataset


def _warnings(ds):
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y)
    return [str(w.message) for w in caught]


def test_twenty_point_convex_record_is_warned():
    # 20 points: the convex fit leaves 0-2 residual degrees of freedom; sets held the truth in 21 of 30 draws
    msgs = _warnings(make_dataset("implicit_convex", n=20, random_state=7))
    assert any("too narrow" in m and "kinks or steps on 20 points" in m for m in msgs)


def test_noise_free_record_in_the_class_is_called_exact_if_noise_free():
    msgs = _warnings(make_dataset("implicit_convex", snr_db=np.inf, random_state=0))
    assert any("residual at rounding level" in m and "exact if they are noise-free" in m for m in msgs)


def test_paper_sized_records_are_not_warned():
    for name in ("implicit_convex", "implicit_monotone"):
        for seed in (0, 1):
            assert not [m for m in _warnings(make_dataset(name, random_state=seed)) if "too narrow" in m]
