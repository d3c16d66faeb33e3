"""The data's coverage may not turn a semi-transparent mark opaque over photo the mark's colour (coverage.py)."""
from pathlib import Path

import numpy as np
import pytest

PHOTO = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "photos_clean_skimage" / "coffee.png"


@pytest.mark.skipif(not PHOTO.is_file(), reason="needs ../shared/data/photos_clean_skimage/coffee.png")
def test_white_mark_over_white_cup_rim_keeps_its_opacity():
    # a white DejaVu mark (the right font) at opacity 0.35 across the cup's white rim: the data's
    # coverage read the rim as fully covered, the opacity went to 0.94 and the rim was inpainted away
    import matplotlib
    from PIL import Image, ImageDraw, ImageFont

    from odnn_sep.image import unwatermark

    font = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans-Bold.ttf"
    photo = Image.open(PHOTO).convert("RGB").resize((400, 266))
    m = Image.new("L", photo.size, 0)
    ImageDraw.Draw(m).text((60, 100), "(c) ACME 2024", font=ImageFont.truetype(str(font), 40), fill=255)
    a = np.asarray(m, float)[..., None] / 255 * 0.35
    clean = np.asarray(photo, float)
    y = np.clip(np.round((1 - a) * clean + a * 255.0), 0, 255).astype(np.uint8)
    r = unwatermark(y, text="(c) ACME 2024")
    assert abs(r.report["alpha"] - 0.35) < 0.05
    assert r.report["lost_pixels"] < 200
    box = np.asarray(m) > 0
    err = r.image.astype(float)[box] - clean[box]
    assert 10 * np.log10(255.0 ** 2 / np.mean(err ** 2)) > 35
