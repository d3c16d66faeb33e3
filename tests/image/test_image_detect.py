"""Detection statistic: one vote per edge patch, measured out of sample."""
import numpy as np

from odnn_sep.image.detect import CLIP, THRESHOLD, detection_score
from odnn_sep.image.render import resolve_font


def _scene(alpha, textured_share, seed=0):
    """A smooth photo with strong texture over the left ``textured_share`` of the mark, and the mark."""
    from odnn_sep.image.register import render_at

    rng = np.random.default_rng(seed)
    H, W = 120, 360
    yy, xx = np.mgrid[0:H, 0:W] / W
    photo = np.dstack([0.35 + 0.2 * xx, 0.4 + 0.1 * yy, 0.45 + 0.1 * xx * yy])
    tex = 0.12 * rng.standard_normal((H, W, 1))
    photo[:, : int(textured_share * W)] += tex[:, : int(textured_share * W)]
    photo = np.clip(photo, 0.02, 0.98)
    m, (x0, y0, x1, y1) = render_at("Preview", resolve_font("DejaVuSans-Bold"), 60, 0.0, (180.0, 60.0), (H, W))
    M = np.zeros((H, W))
    M[y0:y1, x0:x1] = m
    y = (1 - alpha * M[..., None]) * photo + alpha * M[..., None] * 0.9
    return y[y0:y1, x0:x1], photo[y0:y1, x0:x1], m


def test_faint_mark_half_on_texture_is_detected_and_the_clean_photo_is_not():
    # half of the mark lies on texture far stronger than its contrast there: a pooled share of
    # variance is dominated by those patches, one vote per patch is not
    y, photo, m = _scene(alpha=0.25, textured_share=0.5)
    assert detection_score(y, m) > 2 * THRESHOLD
    assert detection_score(photo, m) < THRESHOLD


def test_score_bounded_and_zero_without_edges():
    y, photo, m = _scene(alpha=0.6, textured_share=0.0)
    s = detection_score(y, m)
    assert THRESHOLD < s <= CLIP
    assert detection_score(y, np.zeros_like(m)) == 0.0
    # deterministic for a given random_state
    assert detection_score(y, m, random_state=3) == detection_score(y, m, random_state=3)
