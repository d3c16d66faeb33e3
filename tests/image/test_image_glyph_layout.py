"""Marks whose glyphs sit elsewhere than in the tool's font (another font's advance widths, irregular
letter spacing): the glyph-by-glyph look moves the rendering's glyphs onto the image's."""
import numpy as np
import pytest
from PIL import Image, ImageDraw

from odnn_sep.image.detect import THRESHOLD
from odnn_sep.image.layout import split_layout, with_layout
from odnn_sep.image.layoutlook import layout_look
from odnn_sep.image.render import _load, render_text, resolve_font
from odnn_sep.image.synth import photo_like
from odnn_sep.image.textmode import LAYOUT_LOOK_FACTOR, best_match

TEXT = "PROOF COPY"


def _irregular(size, gaps):
    """Pillow draws the text letter by letter with its own gap after each letter (not the tool's
    renderer)."""
    f = _load(str(resolve_font("DejaVuSans")), float(size))
    im = Image.new("L", (int(sum(f.getlength(c) for c in TEXT) + sum(gaps) + 2 * size), int(2 * size)), 0)
    d = ImageDraw.Draw(im)
    x = size / 2
    for ch, g in zip(TEXT, gaps):
        d.text((x, size / 3), ch, fill=255, font=f)
        x += f.getlength(ch) + g
    a = np.asarray(im, float) / 255
    rr, cc = np.nonzero(a > 0)
    return a[rr.min():rr.max() + 1, cc.min():cc.max() + 1]


@pytest.fixture(scope="module")
def images():
    cov = _irregular(30, [0, 12] * 5)      # gaps no single letter spacing reproduces
    clean = photo_like((120, 400), random_state=2).astype(float)
    M = np.zeros(clean.shape[:2])
    M[40:40 + cov.shape[0], 30:30 + cov.shape[1]] = cov
    y = np.clip(np.round((1 - 0.5 * M[..., None]) * clean + 0.5 * M[..., None] * 255), 0, 255) / 255.0
    rr, cc = np.nonzero(M > 0)
    return y, clean / 255.0, ((cc.min() + cc.max()) / 2, (rr.min() + rr.max()) / 2)


def test_moved_glyphs_find_a_mark_the_whole_string_misses(images):
    y, _, centre = images
    tried = []
    _, _, score, _, _ = best_match(y, TEXT, [resolve_font("DejaVuSans")], None, 0.0, 0, tried=tried)
    assert score < THRESHOLD and tried          # the rendering of the whole string explains nothing
    q, moved = layout_look(y, TEXT, [tried], 0)
    assert moved >= LAYOUT_LOOK_FACTOR * THRESHOLD
    assert abs(q.center[0] - centre[0]) < 3 and abs(q.center[1] - centre[1]) < 3
    shifts = split_layout(q.font)[1]
    steps = np.diff([dx for dx, _ in shifts])[:6]
    assert np.ptp(steps) > 0.2                  # the moved layout follows the alternating gaps


def test_moved_glyphs_stay_below_the_threshold_on_the_clean_photo(images):
    _, clean, _ = images
    tried = []
    best_match(clean, TEXT, [resolve_font("DejaVuSans")], None, 0.0, 0, tried=tried)
    _, moved = layout_look(clean, TEXT, [tried], 0)
    assert moved < THRESHOLD


def test_a_moved_layout_renders_at_any_size():
    font = with_layout("DejaVuSans", [(0.0, 0.0), (0.3, 0.0), (0.6, 0.05)])
    small, big = render_text("ABC", font, 20), render_text("ABC", font, 40)
    plain = render_text("ABC", "DejaVuSans", 20)
    assert abs((small.shape[1] - plain.shape[1]) - 0.6 * 20) <= 2
    assert abs((big.shape[1] - 4) - 2 * (small.shape[1] - 4)) <= 3


def test_a_low_score_without_font_warns_to_check_the_output(monkeypatch, caplog):
    import odnn_sep.image.api as api
    from odnn_sep.image import make_watermark_demo, unwatermark

    y, _, truth = make_watermark_demo(random_state=2)
    monkeypatch.setattr(api, "LOW_CONFIDENCE_SCORE", 5.0)   # every score counts as low here
    with caplog.at_level("WARNING", logger="odnn_sep.image.api"):
        unwatermark(y, text=truth["text"], font="DejaVuSans-Bold")
    assert "check the output" not in caplog.text            # the font was given: its rendering is the mark
    with caplog.at_level("WARNING", logger="odnn_sep.image.api"):
        unwatermark(y, text=truth["text"])
    assert "check the output" in caplog.text
