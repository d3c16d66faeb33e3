"""Frame times of a heat field (NPZ with z (frames, ny, nx) and t): the refusal says which rule failed.

Frame times counted from the recording's start (t = 0, 1, 2, ...) were refused as "must be 4
positive, increasing, evenly spaced values", which the user's times look like they are.
"""
import numpy as np
import pytest

from odnn_sep.errors import FormatError
from odnn_sep.mismatch.io import read_npz


@pytest.mark.parametrize("t, why", [([0.0, 1.0, 2.0, 3.0], "the first is not after 0"),
                                    ([1.0, 2.0, 4.0, 8.0], "they do not increase evenly"),
                                    ([1.0, 2.0, 3.0], "it has 3 values for 4 frames")])
def test_frame_time_rule_named(tmp_path, t, why):
    z = np.zeros((4, 6, 8))
    path = tmp_path / "field.npz"
    np.savez(path, x=np.linspace(0, 1, 8), y=np.linspace(0, 1, 6), z=z, t=np.array(t))
    with pytest.raises(FormatError, match=why):
        read_npz(path)
