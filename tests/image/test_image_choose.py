"""Font choice by the blend model's likelihood, and the detection thresholds by mode."""
import numpy as np

from odnn_sep.image import unwatermark
from odnn_sep.image.api import MIN_SCORE
from odnn_sep.image.choose import most_likely
from odnn_sep.image.register import refine
from odnn_sep.image.render import resolve_font
from odnn_sep.image.synth import add_text_watermark, photo_like


def _marked(font, random_state=31):
    clean = photo_like((200, 320), random_state=random_state)
    y, M = add_text_watermark(clean, "Preview", font=font, size=36, angle=-8.0, center=(160.0, 100.0), alpha=0.45,
                              color=(255, 255, 255))
    return y, clean


def test_most_likely_prefers_the_true_font_at_the_same_place():
    y, _ = _marked("DejaVuSerif")
    yf = y / 255.0
    rivals = [refine(yf, "Preview", resolve_font(f), 36, -8.0, (160.0, 100.0))
              for f in ("DejaVuSans", "DejaVuSerif", "DejaVuSerif-Bold")]
    assert most_likely(yf, rivals) == 1
    assert most_likely(yf, rivals[1:2]) == 0


def test_font_found_without_a_pinned_font():
    y, _ = _marked("DejaVuSerif")
    r = unwatermark(y, text="Preview", max_marks=1)
    assert r.report["font"].endswith("DejaVuSerif.ttf")
    assert abs(r.alpha - 0.45) / 0.45 < 0.02
    assert r.report["match_score_threshold"] == MIN_SCORE


def test_detection_score_low_for_a_wrong_place():
    from odnn_sep.image.detect import detection_score
    from odnn_sep.image.register import render_at

    y, _ = _marked("DejaVuSans-Bold")
    yf = y / 255.0
    m, (x0, y0, x1, y1) = render_at("Preview", resolve_font("DejaVuSans-Bold"), 36, -8.0, (160.0, 100.0), yf.shape[:2])
    assert detection_score(yf[y0:y1, x0:x1], m) > MIN_SCORE
    m, (x0, y0, x1, y1) = render_at("Preview", resolve_font("DejaVuSans-Bold"), 36, 20.0, (150.0, 60.0), yf.shape[:2])
    assert detection_score(yf[y0:y1, x0:x1], m) < MIN_SCORE
    assert np.isfinite(detection_score(yf[y0:y1, x0:x1], m))
