"""A mark with an outline (two colours) cannot be inverted by one opacity and colour: what is left is
its glyphs darkened as a whole, with little edge where the tool's shape ends. It must be reported
still visible, not removed."""
import os

import numpy as np
from PIL import Image, ImageDraw, ImageFont

from odnn_sep.image import unwatermark
from odnn_sep.image.render import resolve_font


def _photo(h=160, w=420):
    yy, xx = np.mgrid[0:h, 0:w] / max(h, w)
    rng = np.random.default_rng(0)
    base = np.stack([0.55 + 0.2 * xx, 0.35 + 0.15 * yy, 0.25 + 0.1 * np.sin(6 * xx)], -1)
    return np.clip(base + 0.01 * rng.standard_normal((h, w, 3)), 0, 1)


def _marked(stroke: int):
    photo = Image.fromarray((255 * _photo()).astype(np.uint8)).convert("RGBA")
    layer = Image.new("RGBA", photo.size, (0, 0, 0, 0))
    font = ImageFont.truetype(os.fspath(resolve_font("DejaVuSans-Bold")), 48)
    ImageDraw.Draw(layer).text((40, 50), "SAMPLE 24", font=font, fill=(255, 255, 255, 128),
                               stroke_width=stroke, stroke_fill=(0, 0, 0, 128))
    return np.asarray(Image.alpha_composite(photo, layer).convert("RGB"))


def test_an_outlined_mark_is_reported_still_visible():
    r = unwatermark(_marked(3), text="SAMPLE 24")
    assert r.report["residual_mark"]["visible"]
    assert r.report["residual_mark"]["contrast_levels"] >= 25


def test_the_same_mark_without_outline_is_removed():
    r = unwatermark(_marked(0), text="SAMPLE 24")
    assert not r.report["residual_mark"]["visible"]
