"""The edge rule of the residual-mark check needs edges along the mark's contours (residual.py)."""
import numpy as np

from odnn_sep.image.residual import aligned_share, measure
from odnn_sep.image.synth import add_text_watermark


def _photo_busy_under_mark(h=120, w=300, seed=0):
    """Smooth sky with a patch of texture that runs every way, just where the mark will be."""
    import cv2

    rng = np.random.default_rng(seed)
    sky = np.linspace(0.55, 0.7, w)[None, :, None] * np.ones((h, w, 3))
    tex = cv2.GaussianBlur(rng.standard_normal((h, w)).astype(np.float32), (0, 0), 1.2)
    box = np.zeros((h, w), np.float32)
    box[30:90, 30:270] = 1
    box = cv2.GaussianBlur(box, (0, 0), 3)
    return np.clip(sky + 0.25 * (tex * box)[..., None], 0, 1)


def test_clean_photo_with_detail_under_the_mark_is_not_a_mark_left():
    photo = _photo_busy_under_mark()
    y8, M = add_text_watermark((photo * 255).round().astype(np.uint8), "SAMPLE", size=48, center=(150, 60),
                               alpha=0.45)
    y = y8 / 255.0
    clean = (photo * 255).round() / 255.0
    r = measure(clean, y, M, M)
    assert not r["visible"]
    assert aligned_share(clean, y, M) < 0.2


def test_rims_along_the_glyph_edges_are_still_visible():
    import cv2

    photo = _photo_busy_under_mark(seed=1)
    y8, M = add_text_watermark((photo * 255).round().astype(np.uint8), "SAMPLE", size=48, center=(150, 60),
                               alpha=0.45)
    y = y8 / 255.0
    # a removal with glyphs a pixel thinner than the true ones: the true glyphs' rims stay
    thin = cv2.erode((M > 0.5).astype(np.uint8), np.ones((3, 3), np.uint8)).astype(float)
    rim = np.clip(M - thin, 0, 1)[..., None]
    out = (1 - 0.45 * rim) * photo + 0.45 * rim
    assert aligned_share(out, y, M) > 0.2
    assert measure(out, y, M, M)["visible"]


def test_tiny_image_with_a_mask_covering_its_middle_runs(tmp_path, capsys):
    # an 8x8 photo: the residual check's crop had no uncovered pixel, and the stroke width overflowed
    from PIL import Image

    from odnn_sep.cli import main

    rng = np.random.default_rng(0)
    Image.fromarray(rng.integers(0, 255, (8, 8, 3), dtype=np.uint8)).save(tmp_path / "t.png")
    m = np.zeros((8, 8), np.uint8)
    m[2:5, 2:5] = 255
    Image.fromarray(m).save(tmp_path / "m.png")
    rc = main(["unwatermark", str(tmp_path / "t.png"), "-o", str(tmp_path / "o.png"), "--mask", str(tmp_path / "m.png")])
    err = capsys.readouterr().err
    assert rc == 1 and "no watermark found inside the mask" in err   # noise holds no blend: not found
    assert "Traceback" not in err and not (tmp_path / "o.png").exists()

