"""Search behaviour: faint marks, marks running to the image's edge, and the float view of the input."""
import numpy as np
import pytest

from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like


def test_faint_mark_found():
    clean = photo_like((240, 360), random_state=21)
    y, M = add_text_watermark(clean, "PROOF copy", size=34, angle=12.0, center=(190.0, 120.0), alpha=0.22,
                              color=(255, 255, 255))
    r = unwatermark(y, text="PROOF copy", font="DejaVuSans-Bold", max_marks=1)
    assert abs(r.report["font_size_px"] - 34) < 0.5 and abs(r.report["angle_deg"] - 12.0) < 0.5
    assert abs(r.alpha - 0.22) / 0.22 < 0.03


def test_mark_touching_the_image_edge_found():
    clean = photo_like((200, 320), random_state=22)
    # the top of the glyphs is cut off by the border: templates must be allowed to hang over it
    y, M = add_text_watermark(clean, "SAMPLE", size=40, angle=0.0, center=(160.0, 12.0), alpha=0.5,
                              color=(0, 0, 0))
    assert M[0].max() > 0.3
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold", max_marks=1)
    assert abs(r.alpha - 0.5) < 0.02
    assert np.hypot(r.report["center"][0] - 160.0, r.report["center"][1] - 12.0) < 3


def test_float_view_converts_crops_only():
    from odnn_sep.image.io import paste, split

    a = np.arange(4 * 5 * 3, dtype=np.uint16).reshape(4, 5, 3) * 1000
    p = split(a)
    assert p.view[1:3, 2:4].dtype == np.float64
    assert np.allclose(p.view[1:3, 2:4], a[1:3, 2:4] / 65535.0)
    out = paste(p, np.zeros((2, 2, 3)), (2, 1, 4, 3))
    assert out.dtype == np.uint16 and (out[1:3, 2:4] == 0).all()
    out[1:3, 2:4] = a[1:3, 2:4]
    assert np.array_equal(out, a)  # the rest is bit-identical


@pytest.mark.parametrize("shape", [(30, 40), (30, 40, 4)])
def test_paste_keeps_grey_and_alpha(shape):
    from odnn_sep.image.io import paste, split

    a = np.random.default_rng(0).integers(0, 256, shape).astype(np.uint8)
    p = split(a)
    out = paste(p, p.view[5:10, 5:10], (5, 5, 10, 10))
    assert np.array_equal(out, a)


@pytest.mark.parametrize("angle", [-30.0, 25.0])
def test_long_text_found_by_its_middle_part(angle):
    """The coarse grid matches only the middle of a long text; the whole text's centre follows."""
    from odnn_sep.image.locate import coarse_chunk, search
    from odnn_sep.image.render import resolve_font

    text = "ata acquisition and representation."
    font = resolve_font("DejaVuSans-Bold")
    assert coarse_chunk(text, font, 900.0)[1] is not None  # the coarse grid sees a part only
    y, _ = add_text_watermark(photo_like((300, 420), random_state=1), text, size=20, center=(210.0, 150.0),
                              angle=angle, alpha=0.4)
    best = search(y / 255.0, text, [font], max_hypotheses=4)[0]
    assert np.hypot(best.center[0] - 210.0, best.center[1] - 150.0) < 1.5
    assert abs(best.angle - angle) < 1.0 and abs(best.size - 20.0) < 1.0
