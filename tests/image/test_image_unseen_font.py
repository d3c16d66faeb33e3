"""Marks in a font the tool does not try: letter-spaced renderings, and the fast path of the core's
batched solve that the opacity profile uses."""
import numpy as np

from odnn_sep.core.linalg import solve_batched
from odnn_sep.image.render import render_text, spaced, split_tracking


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
