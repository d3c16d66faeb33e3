"""The registration's two ways to get the rendering at its patches agree: the whole crop warped and
cut into patches, and the rendering sampled at the patches' pixels (``coverage_at``)."""
import numpy as np
import pytest

from odnn_sep.image import register
from odnn_sep.image.register import coverage_at, refine
from odnn_sep.image.render import place, render_text
from odnn_sep.image.synth import add_text_watermark


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_coverage_at_matches_the_whole_warp(seed):
    rng = np.random.default_rng(seed)
    size, angle = rng.uniform(10, 60), rng.uniform(-45, 45)
    center = (rng.uniform(90, 130), rng.uniform(70, 90))
    m = render_text("Studio 2024", "DejaVuSans", size)
    crop, (x0, y0, x1, y1) = place(m, (160, 220), center, angle)
    whole = np.zeros((160, 220))
    whole[y0:y1, x0:x1] = crop
    rr, cc = np.mgrid[0:160, 0:220]
    assert np.abs(coverage_at(m, center, angle, rr, cc) - whole).max() < 1e-3


def test_refine_same_placement_either_way(monkeypatch):
    clean = np.repeat(np.linspace(60, 140, 96)[:, None, None], 160, 1).repeat(3, 2).astype(np.uint8)
    y = add_text_watermark(clean, "Proof", size=30, angle=8.0, center=(80, 48), alpha=0.45)[0] / 255.0
    out = []
    for ratio in (0.0, 1e9):  # always sampled, never sampled
        monkeypatch.setattr(register, "SAMPLE_RATIO", ratio)
        p = refine(y, "Proof", "DejaVuSans-Bold", 29.4, 7.0, (80.6, 47.5), iterations=40)
        out.append((p.center[0], p.center[1], p.angle, p.size, p.fit.alpha))
    assert np.allclose(out[0], out[1], atol=2e-3), out
