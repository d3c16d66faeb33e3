"""The registration tries the whole font sizes one further each way from its continuous optimum: a
search that hands over the wrong whole size (41 px for a mark drawn at 40 px) left the optimum stuck
there and the letters as outlines (``register._whole_size``)."""
import numpy as np
import pytest

from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like


@pytest.mark.parametrize("photo", [1, 3])
def test_a_mark_registered_one_whole_size_off_is_moved_to_its_size(photo):
    # the version before registered these at 41.0 px: 34 dB, reported still visible
    clean = photo_like((300, 400), random_state=photo)
    y, _ = add_text_watermark(clean, "SAMPLE", size=40, center=(200, 150), alpha=0.5)
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    assert r.report["font_size_px"] == pytest.approx(40.0, abs=0.05)
    psnr = 10 * np.log10(255.0 ** 2 / np.mean((r.image.astype(float) - clean.astype(float)) ** 2))
    assert psnr > 55.0
    assert not r.report["residual_mark"]["visible"]
