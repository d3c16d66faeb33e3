"""A vertical mark (turned 90 degrees) is outside the angles searched: the error says so and what works."""
import numpy as np
import pytest

from odnn_sep.errors import MarkNotFoundError
from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like


def test_vertical_mark_not_found_says_turn_the_image():
    y, _ = add_text_watermark(photo_like((360, 360), random_state=5), "SAMPLE", size=40, angle=90,
                              center=(180, 180), alpha=0.5)
    with pytest.raises(MarkNotFoundError, match=r"angles within \+-45 degrees of level: for a mark turned further "
                                                r"\(vertical text\), turn the image by 90 degrees first"):
        unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    # the advice holds: turned upright, the same mark is found and removed
    r = unwatermark(np.ascontiguousarray(np.rot90(y, -1)), text="SAMPLE", font="DejaVuSans-Bold")
    assert abs(r.alpha - 0.5) < 0.02 and not r.report["residual_mark"]["visible"]
