"""Marks in a font the tool does not try: letter-spaced renderings, the data's coverage in the
detection score, and the fast path of the core's batched solve that the opacity profile uses."""
import numpy as np
import pytest

from odnn_sep.core.linalg import solve_batched
from odnn_sep.image.register import refine
from odnn_sep.image.render import render_text, spaced, split_tracking
from odnn_sep.image.synth import photo_like
from odnn_sep.image.textmode import placement_score


def test_spaced_font_renders_wider_by_the_tracking():
    plain = render_text("SAMPLE", "DejaVuSans", 40)
    tight = render_text("SAMPLE", spaced("DejaVuSans", 1e-4), 40)  # letter by letter, no spacing
    wide = render_text("SAMPLE", spaced("DejaVuSans", 0.2), 40)
    assert wide.shape[0] == plain.shape[0] == tight.shape[0]
    # five gaps of 0.2 em (8 px) more; letter by letter loses the string's kerning (a few px)
    assert abs((wide.shape[1] - tight.shape[1]) - 5 * 8) <= 1
    assert abs(tight.shape[1] - plain.shape[1]) <= 8
    assert split_tracking(spaced("DejaVuSans", 0.2)) == (split_tracking(spaced("DejaVuSans", 0))[0], 0.2)
    assert spaced("DejaVuSans", 0) == split_tracking(spaced("DejaVuSans", 0.2))[0]


def test_solve_batched_fast_path_agrees_with_checked_solve():
    rng = np.random.default_rng(0)
    A = rng.standard_normal((50, 16, 3))
    G = A.transpose(0, 2, 1) @ A
    r = rng.standard_normal((50, 3, 4))
    np.testing.assert_allclose(solve_batched(G, r, check=False), solve_batched(G, r), rtol=1e-10, atol=1e-12)
    v = rng.standard_normal(3)
    np.testing.assert_allclose(solve_batched(G[0], v, check=False), solve_batched(G[0], v), rtol=1e-10)


def _stix_mark(shape, spacing):
    """'SAMPLE' in STIX bold (a serif face the tool does not try), letter-spaced, centred."""
    from PIL import Image, ImageDraw, ImageFont

    from odnn_sep.image.render import resolve_font

    f = ImageFont.truetype(str(resolve_font("STIXGeneralBol")), 44)
    H, W = shape
    im = Image.new("L", (W, H), 0)
    d = ImageDraw.Draw(im)
    x = 40.0
    for ch in "SAMPLE":
        d.text((x, 30), ch, fill=255, font=f)
        x += f.getlength(ch) + spacing
    return np.asarray(im, dtype=np.float64) / 255.0


@pytest.fixture(scope="module")
def stix_case():
    pytest.importorskip("matplotlib", reason="matplotlib ships the STIX fonts")
    clean = photo_like((120, 420), random_state=3).astype(np.float64) / 255
    M = _stix_mark(clean.shape[:2], 9.0)
    a = 0.5
    y = np.round(((1 - a * M[..., None]) * clean + a * M[..., None]) * 255) / 255
    return y, clean, M


def test_data_coverage_scores_a_mark_the_rendering_misses(stix_case):
    y, clean, M = stix_case
    rr, cc = np.nonzero(M > 0.5)
    centre = ((cc.min() + cc.max()) / 2, (rr.min() + rr.max()) / 2)
    p = refine(y, "SAMPLE", spaced("DejaVuSans-Bold", 0.18), 44.0, 0.0, centre, iterations=40)
    with_data = placement_score(y, p, from_data=True)
    assert with_data >= 0.19
    assert with_data >= placement_score(y, p, from_data=False)
    # the same placement on the clean photo: nothing there, in the rendering nor in the data
    q = refine(clean, "SAMPLE", spaced("DejaVuSans-Bold", 0.18), 44.0, 0.0, centre, iterations=40)
    assert placement_score(clean, q, from_data=True) < 0.19
