import numpy as np
import pytest

from odnn_sep.image.estimate import fit_blend, invert
from odnn_sep.image.synth import make_watermark_demo


@pytest.mark.parametrize("rs", [0, 1])
def test_known_mask_recovers_alpha_color_and_photo(rs):
    from skimage.metrics import peak_signal_noise_ratio as psnr

    y, clean, t = make_watermark_demo(rs)
    M = t["mask"]
    fit = fit_blend(y / 255.0, M)
    assert abs(fit.alpha - t["alpha"]) / t["alpha"] < 0.02
    out, lost = invert(y / 255.0, M, fit.alpha, fit.color)
    o8 = np.clip(np.round(out * 255), 0, 255).astype(np.uint8)
    assert psnr(clean, o8) > 55
    assert psnr(clean, o8) > psnr(clean, y) + 20


def test_invert_marks_opaque_pixels_lost():
    y = np.full((20, 20, 3), 0.5)
    M = np.zeros((20, 20))
    M[5:15, 5:15] = 1.0
    y = (1 - 0.95 * M[..., None]) * y + 0.95 * M[..., None] * 1.0
    out, lost = invert(y, M, 0.95, np.ones(3))
    assert lost.sum() == 100
    assert np.allclose(out[~lost], 0.5)
