"""``--mask`` over a filled translucent shape (a banner, a badge, a logo's silhouette): the shape is the
part of the mask pulled towards one colour by one factor, M = 1 inside it; opacity and colour from the
blend fit, with exact, dilated and rough-box masks. The photo's texture under the shape is kept."""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.image import unwatermark
from odnn_sep.image.synth import photo_like

cv2 = pytest.importorskip("cv2", reason="OpenCV is the inpainting reference")


def psnr(a, b, m):
    d = a[m].astype(float) - b[m].astype(float)
    return 10 * np.log10(255.0**2 / max(np.mean(d * d), 1e-12))


def gradient_photo(seed=0, shape=(96, 128)):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]]
    return np.clip((90 + 0.5 * xx + 0.3 * yy)[..., None] + rng.normal(0, 3, shape + (3,)), 0, 255).astype(np.uint8)


def blend(clean, M, alpha, color):
    a = alpha * M[..., None]
    return np.clip(np.round((1 - a) * clean + a * np.array(color, float)), 0, 255).astype(np.uint8)


def grow(shape, px):
    return cv2.dilate(shape.astype(np.uint8), np.ones((2 * px + 1, 2 * px + 1), np.uint8)) > 0


@pytest.mark.parametrize("margin", [0, 1, 5])
def test_filled_rectangle_is_inverted_with_its_opacity(margin):
    clean = gradient_photo()
    M = np.zeros(clean.shape[:2])
    M[40:50, 30:90] = 1
    y = blend(clean, M, 0.4, (255, 255, 255))
    mask = np.zeros(M.shape, np.uint8)
    mask[40 - margin:50 + margin, 30 - margin:90 + margin] = 255
    # the stroke search found nothing in the rectangle ("no watermark found", score 0.000 / 0.182)
    r = unwatermark(y, mask=mask)
    assert not r.report["opaque"] and abs(r.alpha - 0.4) < 0.05 and r.color.min() > 0.9
    assert r.lost.sum() == 0 and not r.report["residual_mark"]["visible"]
    box = grow(M > 0, 4)
    assert psnr(r.image, clean, box) > 45 > psnr(y, clean, box) + 15
    if margin == 5:
        with pytest.raises(InputError, match="no watermark found inside the mask"):
            unwatermark(clean, mask=mask)


@pytest.mark.parametrize("kind", ["ellipse", "logo"])
def test_filled_shapes_in_dilated_masks_and_boxes(kind):
    clean = photo_like((120, 200), random_state=3)
    S = np.zeros((480, 800), np.uint8)                 # drawn at 4x: anti-aliased edges
    if kind == "ellipse":
        cv2.ellipse(S, (400, 240), (260, 120), 0, 0, 360, 255, -1)
        alpha, color = 0.55, (0, 0, 0)
    else:
        cv2.circle(S, (200, 240), 100, 255, -1)
        cv2.rectangle(S, (200, 200), (560, 280), 255, -1)
        cv2.fillPoly(S, [np.array([[560, 150], [680, 240], [560, 330]], np.int32)], 255)
        alpha, color = 0.3, (200, 30, 30)
    M = np.clip(cv2.resize(S.astype(np.float32) / 255, (200, 120), interpolation=cv2.INTER_AREA), 0, 1)
    y = blend(clean, M, alpha, color)
    ys, xs = np.nonzero(M > 0.02)
    box = np.zeros(M.shape, bool)
    box[ys.min() - 6:ys.max() + 7, xs.min() - 6:xs.max() + 7] = True
    # a coloured mark in a rough box is not found yet (its colour is not read from the box)
    for mask in (grow(M > 0.02, 2), box) if kind == "ellipse" else (M > 0.5, grow(M > 0.02, 2)):
        r = unwatermark(y, mask=mask.astype(np.uint8) * 255)
        assert not r.report["opaque"] and abs(r.alpha - alpha) < 0.03
        assert np.abs(r.color * 255 - color).max() < 20
        assert psnr(r.image, clean, box) > psnr(y, clean, box) + 15
