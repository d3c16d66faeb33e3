"""Rims along the mark's contours (residual_rims.py): a dark mark removed with a shape one pixel off,
over a photo crossed by strong thin lines, keeps its letters as outlines. The band-over-ring edge
energy is dominated by the lines and calls that removed; the edge strength across the contours sees
the rims, and sees nothing in the clean photo."""
import numpy as np
import pytest

from odnn_sep.image.residual import measure
from odnn_sep.image.residual_rims import RIM_SHARE, rim_levels, rims_left
from odnn_sep.image.synth import add_text_watermark, photo_like


def _lattice_case(seed: int, period: int = 11, amp: float = 0.5):
    """(watermarked, clean, true coverage, a coverage one pixel off) of a black mark at opacity 0.75
    over a photo crossed by a lattice of bright thin lines (strong edges all around the mark)."""
    H, W = 100, 360
    photo = photo_like((H, W), random_state=seed).astype(np.float64) / 255
    xx, yy = np.meshgrid(np.arange(W), np.arange(H))
    lines = ((np.abs(xx % period - period // 2) < 1) | (np.abs(yy % period - period // 2) < 1)) * amp
    clean = np.clip(0.5 * photo + 0.3 + lines[:, :, None] * np.array([1.0, 0.9, 0.7]), 0, 1)
    y8, M = add_text_watermark((clean * 255).round().astype(np.uint8), "knowledge based", size=40,
                               center=(180, 50), alpha=0.75, color=(0, 0, 0))
    return y8 / 255.0, (clean * 255).round() / 255.0, M, np.roll(M, 1, axis=1)


@pytest.mark.parametrize("seed", [0, 1])
def test_outlines_left_by_a_shape_one_pixel_off_are_visible(seed):
    y, clean, M, est = _lattice_case(seed)
    # removed with the shape one pixel off: the true glyphs' part outside the estimate stays dark,
    # the estimate's part outside them is lightened
    out = np.clip(clean + 0.75 * (M - est)[..., None] * (0.0 - clean), 0, 1)
    assert not measure(out, y, est, M)["visible"]           # the band's edge energy alone misses it
    r = measure(out, y, est, M, rims=True)
    assert r["visible"] and r["rim_left"] >= RIM_SHARE and r["rim_levels"] > 20


@pytest.mark.parametrize("seed", [0, 1])
def test_a_perfect_removal_over_the_same_lines_is_not_called_visible(seed):
    y, clean, M, est = _lattice_case(seed)
    r = measure(clean, y, est, M, rims=True)
    assert not r["visible"] and r["rim_left"] < RIM_SHARE


def test_detail_running_every_way_has_no_rim_strength():
    rng = np.random.default_rng(3)
    import cv2

    tex = cv2.GaussianBlur(rng.standard_normal((80, 200)).astype(np.float32), (0, 0), 1.2)
    photo = np.clip(0.5 + 0.2 * tex, 0, 1)[..., None].astype(np.float64)
    _, M = add_text_watermark(np.zeros((80, 200, 3), np.uint8), "SAMPLE", size=40, center=(100, 40), alpha=0.5)
    marked = (1 - 0.5 * M[..., None]) * photo + 0.5 * M[..., None]
    assert abs(rim_levels(photo, M)) < 0.1 * rim_levels(marked, M)
    assert rims_left(photo, marked, [M])[2] is False


def test_text_mode_reports_the_rims():
    from odnn_sep.image import make_watermark_demo, unwatermark

    y, clean, truth = make_watermark_demo(random_state=2)
    rep = unwatermark(y, text=truth["text"], font="DejaVuSans-Bold").report["residual_mark"]
    assert {"rim_left", "rim_levels"} <= set(rep)
    assert rep["rim_left"] < RIM_SHARE and not rep["visible"]   # the right font: removed, no rims
