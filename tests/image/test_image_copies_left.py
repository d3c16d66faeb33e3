"""A tiled mark whose other copies are cut by the border must not be reported removed (they are now
found and removed: ``border_copies``; a copy still left is what ``copies_left`` looks for).

Found by ``recipes/bench_watermark_probe.py`` (development seed 12, case 3: 'Preview only' tiled over
the moon photo; the one whole copy was removed, the copies cut by the border stayed, exit 0).
"""
import numpy as np
import pytest


def _marked(copies):
    from PIL import Image, ImageDraw, ImageFont

    from odnn_sep.image.render import resolve_font

    f = ImageFont.truetype(str(resolve_font("DejaVuSans-Bold")), 34)
    H, W = 170, 270
    L = Image.new("L", (W, H), 0)
    d = ImageDraw.Draw(L)
    for xy in copies:
        d.text(xy, "SAMPLE", font=f, fill=255)
    M = np.asarray(L, dtype=np.float64) / 255
    yy, xx = np.mgrid[0:H, 0:W]
    photo = np.stack([0.35 + 0.2 * xx / W, 0.4 + 0.1 * yy / H, 0.5 - 0.1 * xx / W], -1)
    photo = photo + 0.01 * np.random.default_rng(0).standard_normal(photo.shape)
    y = (1 - 0.45 * M[..., None]) * photo + 0.45 * M[..., None]
    return np.round(np.clip(y, 0, 1) * 255).astype(np.uint8)


def test_copy_cut_by_the_border_is_removed_too():
    """The copy cut by the right border is now registered and removed (``border_copies``); the check
    of what is left (``copies_left``, tested on its own below) then finds nothing."""
    from odnn_sep.image import unwatermark

    y = _marked([(50, 95), (195, 15)])      # one whole copy, one cut by the right border
    clean = _marked([])
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    rm = r.report["residual_mark"]
    assert rm["visible"] is False and rm["copies_left"] is None
    assert len(r.report["marks"]) == 2 and r.report["marks"][1]["center"][0] > 250
    err = r.image[:, 190:].astype(float) - clean[:, 190:]
    assert 10 * np.log10(255 ** 2 / np.mean(err ** 2)) > 50     # the input there: 23 dB


def test_single_copy_removed_has_no_copies_left():
    from odnn_sep.image import unwatermark

    r = unwatermark(_marked([(50, 95)]), text="SAMPLE", font="DejaVuSans-Bold")
    rm = r.report["residual_mark"]
    assert rm["copies_left"] is None and rm["visible"] is False


@pytest.mark.parametrize("seed", [0, 1])
def test_copies_left_on_clean_photo_outside_the_box(seed):
    """A perfect removal of the only copy, on noise and a smooth ramp: nothing left elsewhere."""
    from odnn_sep.image.residual_copies import copies_left

    rng = np.random.default_rng(seed)
    H, W = 140, 220
    photo = 0.4 + 0.3 * np.mgrid[0:H, 0:W][1][..., None] / W + 0.03 * rng.standard_normal((H, W, 1))
    M = np.zeros((H, W))
    M[40:70, 50:55] = 1
    M[40:45, 45:110] = 1
    box = (41, 36, 114, 74)
    assert copies_left(photo, photo[36:74, 41:114], M, box) is None


def test_copy_left_between_removed_copies_is_found():
    """Tiled marks of which only some copies were found: a copy left inside the removed copies' box
    (development seed 13, cases 2 and 7 of the probe) is looked for with one copy as the template."""
    from odnn_sep.image.residual_copies import copies_left

    rng = np.random.default_rng(3)
    H, W = 150, 330
    photo = 0.45 + 0.02 * rng.standard_normal((H, W, 1))
    c = np.zeros((30, 70))
    c[5:25, 10:15] = 1
    c[5:10, 5:65] = 1
    c[20:25, 20:60] = 1
    removed, left = np.zeros((H, W)), np.zeros((H, W))
    removed[20:50, 20:90] = c
    removed[100:130, 240:310] = c
    left[60:90, 130:200] = c                                   # inside the removed copies' box
    y = (1 - 0.4 * (removed + left)[..., None]) * photo + 0.4 * (removed + left)[..., None]
    box = (16, 16, 314, 134)
    out_box = y[16:134, 16:314].copy()
    done = removed[16:134, 16:314] > 0
    out_box[done] = photo[16:134, 16:314][done]                 # the two found copies removed
    found = copies_left(y, out_box, removed, box, copy_box=(16, 16, 94, 54))
    assert found is not None and abs(found["at"][0] - 135) <= 2 and abs(found["at"][1] - 65) <= 2
    y2 = (1 - 0.4 * removed[..., None]) * photo + 0.4 * removed[..., None]   # no third copy
    out2 = y2[16:134, 16:314].copy()
    out2[done] = photo[16:134, 16:314][done]
    assert copies_left(y2, out2, removed, box, copy_box=(16, 16, 94, 54)) is None
