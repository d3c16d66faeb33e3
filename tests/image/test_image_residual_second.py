"""A mark drawn in two colours (a drop shadow, an outline) leaves its second colour beside the letters
once its one-colour blend is inverted. The report must say the mark is still visible and name the
shape left; a plain mark removed well must not be flagged by the same check."""
import os

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from odnn_sep.image import unwatermark
from odnn_sep.image.render import resolve_font
from odnn_sep.image.residual_second import second_colour, second_shapes


def _photo(h=170, w=430, seed=0):
    yy, xx = np.mgrid[0:h, 0:w] / max(h, w)
    rng = np.random.default_rng(seed)
    base = np.stack([0.5 + 0.2 * xx, 0.4 + 0.15 * yy, 0.3 + 0.1 * np.sin(6 * xx)], -1)
    return np.clip(base + 0.01 * rng.standard_normal((h, w, 3)), 0, 1)


def _marked(shadow: int, alpha=110):
    photo = Image.fromarray((255 * _photo()).astype(np.uint8)).convert("RGBA")
    layer = Image.new("RGBA", photo.size, (0, 0, 0, 0))
    font = ImageFont.truetype(os.fspath(resolve_font("DejaVuSans-Bold")), 48)
    d = ImageDraw.Draw(layer)
    if shadow:
        d.text((40 + shadow, 50 + shadow), "SAMPLE 24", font=font, fill=(0, 0, 0, alpha))
    d.text((40, 50), "SAMPLE 24", font=font, fill=(255, 255, 255, alpha))
    return np.asarray(Image.alpha_composite(photo, layer).convert("RGB"))


def test_a_shadowed_mark_is_reported_still_visible_with_its_shadow_named():
    rm = unwatermark(_marked(4), text="SAMPLE 24").report["residual_mark"]
    assert rm["visible"]
    assert rm["second_colour"] is not None and rm["second_colour"]["contrast_levels"] >= 4


def test_the_same_mark_without_shadow_is_removed_and_no_second_colour_is_found():
    rm = unwatermark(_marked(0), text="SAMPLE 24").report["residual_mark"]
    assert not rm["visible"] and rm["second_colour"] is None


def test_no_shape_of_the_family_is_found_on_a_clean_photo():
    M = np.zeros((90, 200))
    M[20:70, 30:40] = 1
    M[20:30, 30:170] = 1
    M[60:70, 60:150] = 1
    assert second_colour(_photo(90, 200, seed=3), M) is None
    shapes = second_shapes(M)
    assert {"ring3", "shift3,3", "shift-3,-3"} <= set(shapes)
    assert all(not (S * M).any() for k, S in shapes.items() if k.startswith(("ring", "shift")))


def test_a_large_mark_is_checked_at_its_working_scale_and_its_shadow_found():
    from odnn_sep.image.synth import text_coverage

    M = np.pad(text_coverage("SAMPLE", "DejaVuSans-Bold", 150, 0), 20)        # strokes ~25 px wide
    photo = _photo(*M.shape, seed=5)
    shadow = np.zeros_like(M)
    shadow[12:, 12:] = M[:-12, :-12]
    shadow = np.clip(shadow - M, 0, 1)
    out = (1 - 0.5 * shadow[..., None]) * photo
    found = second_colour(out, M)
    assert found is not None and found["shape"].startswith("shift") and found["contrast_levels"] > 10
    assert second_colour(photo, M) is None
