"""Copies of a tiled mark that neither the search nor the tile's lattice places must not leave the
outcome "removed": the output is searched for them at full resolution, and every copy the detection
statistic finds there is counted, with its position, in ``residual_mark.copies_left``.

Found by ``recipes/probe_image_tiles.py`` (development seed 1, astronaut: "DRAFT copy", DejaVu Serif
44 px, black; 1 of 5 copies placed, exit 0) and ``recipes/probe_image_inputs.py`` (one whole copy and
one cut at a corner, exit 0 with the corner copy left).
"""
from pathlib import Path

import numpy as np
import pytest

PHOTO = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "photos_clean_skimage" / "astronaut.png"


def test_copy_cut_at_a_corner_is_reported_left():
    """The corner copy's edge-correlation peak lies 16 px off it: refined within a quarter of the copy."""
    from odnn_sep.image import unwatermark
    from odnn_sep.image.synth import add_text_watermark, photo_like

    img = photo_like((300, 450), random_state=4)
    t, _ = add_text_watermark(img, "SAMPLE", size=28, angle=30, center=(225, 150), alpha=0.5)
    t, _ = add_text_watermark(t, "SAMPLE", size=28, angle=30, center=(425, 29), alpha=0.5)
    rm = unwatermark(t, text="SAMPLE", font="DejaVuSans-Bold").report["residual_mark"]
    assert rm["visible"] is True
    left = rm["copies_left"]
    assert left["count"] == 1 and left["positions"] == [left["at"]]
    # the found copy's coverage starts 121 px above and 200 px left of the corner copy's
    assert abs(left["at"][0] - 369) <= 2 and abs(left["at"][1] + 11) <= 2


@pytest.mark.skipif(not PHOTO.is_file(), reason=f"photo not available at {PHOTO}")
def test_tiled_copies_on_a_busy_photo_are_counted():
    """Four copies on the astronaut's suit and the border, which the edge correlation of a copy reduced
    to 1 px strokes ranked below the photo's edges: each is found (the lattice of the first one found)."""
    from odnn_sep.image import unwatermark
    from odnn_sep.image.io import read_image
    from odnn_sep.image.synth import add_text_watermark

    img = np.ascontiguousarray(read_image(PHOTO)[:, :, :3])
    y = img
    centres = [(357.4 - 70.35 * k, 164.3 + 129.7 * k) for k in (-1, 0, 1, 2, 3)]
    for c in centres:
        y, _ = add_text_watermark(y, "DRAFT copy", font="DejaVuSerif", size=44, angle=-28.5, center=c,
                                  alpha=0.5, color=(0, 0, 0))
    r = unwatermark(y, text="DRAFT copy", font="DejaVuSerif")
    rm = r.report["residual_mark"]
    assert len(r.report["marks"]) == 1 and rm["visible"] is True
    left = rm["copies_left"]
    assert left["count"] == 4 and len(left["positions"]) == 4
    # every copy left is one of the four not removed: 70 px left and 130 px down per step of the tile
    # from the one cut by the top border (the removed copy is the next step)
    pos = sorted(left["positions"], key=lambda p: p[1])
    for (x, y_), k in zip(pos, (0, 2, 3, 4)):
        assert abs(x - pos[0][0] + 70.35 * k) <= 2 and abs(y_ - pos[0][1] - 129.7 * k) <= 2
