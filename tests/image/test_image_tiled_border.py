"""A text mark tiled over the photo: the copies the border cuts are found and removed too.

Before, the search placed whole copies only; the cut ones stayed, the residual check rightly called the
mark still visible, and a diagonal tile on a 300 x 450 photo (one whole copy, eight cut) could not be
removed at all (exit 3, PSNR 22.9 dB as the input). Copies are not invented on photos with one mark.
"""
import numpy as np

from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like


def _psnr(a, b):
    return 10 * np.log10(255 ** 2 / np.mean((np.asarray(a, float) - np.asarray(b, float)) ** 2))


def test_diagonal_tile_cut_by_the_border_is_removed():
    clean = photo_like((300, 450), random_state=4)
    y, _ = add_text_watermark(clean, "SAMPLE", size=28, angle=30, center=(225, 150), alpha=0.5, tile=(200, 120))
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    assert not r.report["residual_mark"]["visible"]
    assert len(r.report["marks"]) >= 9
    assert _psnr(r.image, clean) > 45 > _psnr(y, clean) + 15


def test_one_mark_gets_no_copies():
    clean = photo_like((300, 450), random_state=5)
    y, _ = add_text_watermark(clean, "SAMPLE", size=36, angle=-10, center=(200, 140), alpha=0.5)
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    assert len(r.report["marks"]) == 1 and not r.report["residual_mark"]["visible"]


def test_lattice_from_copies_a_pixel_off_and_one_misplaced():
    """Copies registered to the nearest pixel, one of them on the wrong place: the lattice's vectors
    are fitted to all copies (one neighbour's offset, a pixel off, put the seventh step 3 px off) and
    the misplaced copy is left out."""
    from odnn_sep.image.border_copies import lattice_points

    rng = np.random.default_rng(0)
    u, v = np.array([24.2, 65.6]), np.array([181.0, -67.0])
    true = [np.array([355.0, 24.0]) + i * u + j * v for i in range(7) for j in (0,)]
    found = [tuple(np.round(c + rng.uniform(-0.5, 0.5, 2))) for c in true[:3] + true[4:]] + [(48.0, 63.0)]
    pts = lattice_points(found, (512, 512), (200, 80))
    missing = true[3]
    assert min(np.hypot(x - missing[0], y - missing[1]) for x, y in pts) < 2.0
