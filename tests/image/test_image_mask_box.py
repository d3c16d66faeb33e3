"""``--mask`` as a rough box: the coverage inside is estimated from the data (M unknown in [0, 1]),
not taken as 1; nothing found in the box is said, and a removal too far is not called a removal."""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like

pytest.importorskip("cv2", reason="OpenCV is the inpainting reference")


def psnr(a, b, m):
    d = a[m].astype(float) - b[m].astype(float)
    return 10 * np.log10(255.0**2 / max(np.mean(d * d), 1e-12))


@pytest.fixture(scope="module")
def boxed():
    clean = photo_like((160, 320), random_state=11)
    y, M = add_text_watermark(clean, "SAMPLE", size=44, center=(160, 80), alpha=0.45, color=(255, 255, 255))
    ys, xs = np.nonzero(M > 0.02)
    box = np.zeros(M.shape, bool)
    box[ys.min() - 5:ys.max() + 6, xs.min() - 5:xs.max() + 6] = True
    return clean, y, M, box


def test_rough_box_around_a_translucent_mark_is_inverted_not_inpainted(boxed):
    clean, y, M, box = boxed
    r = unwatermark(y, mask=box.astype(np.uint8) * 255)
    # the old mask mode read the box as M = 1 (alpha 1.000, the whole box inpainted)
    assert not r.report["opaque"] and abs(r.alpha - 0.45) < 0.05
    assert r.lost.sum() < 0.1 * box.sum() and not r.report["residual_mark"]["visible"]
    assert psnr(r.image, clean, box) > psnr(y, clean, box) + 10


def test_rough_box_on_a_clean_photo_is_not_found(boxed):
    clean, _, _, box = boxed
    with pytest.raises(InputError, match="no watermark found inside the mask"):
        unwatermark(clean, mask=box.astype(np.uint8) * 255)


def test_exact_stroke_mask_gives_the_true_opacity(boxed):
    clean, y, M, box = boxed
    r = unwatermark(y, mask=(M > 0.5).astype(np.uint8) * 255)
    # the opacity was read as the 0.9 quantile of the per-pixel a M (0.60 for a true 0.45 on a face)
    assert abs(r.alpha - 0.45) < 0.03
    assert psnr(r.image, clean, box) > psnr(y, clean, box) + 10


def test_uniform_strip_with_a_mask_is_not_found():
    y = np.full((1, 50, 3), (81, 67, 63), np.uint8)
    mask = np.zeros((1, 50), np.uint8)
    mask[0, 10:20] = 255
    with pytest.raises(InputError, match="no watermark found inside the mask"):
        unwatermark(y, mask=mask)


def test_a_removal_too_far_is_seen():
    from odnn_sep.image.residual import step_left

    clean = photo_like((120, 240), random_state=4).astype(float) / 255
    _, M = add_text_watermark((clean * 255).astype(np.uint8), "GHOST", size=44, center=(120, 60), alpha=0.45)
    a = 0.45 * M[..., None]
    y = (1 - a) * clean + a
    over = np.clip((y - 0.6 * M[..., None]) / (1 - 0.6 * M[..., None]), 0, 1)   # opacity read as 0.6
    share, levels = step_left(over, y, M)
    assert share < -0.15 and levels > 4
    assert abs(step_left(clean, y, M)[0]) < 0.05
