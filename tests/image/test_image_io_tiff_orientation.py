"""A TIFF tagged with an orientation is turned upright once (OpenCV's TIFF decoder turns it itself)."""
import numpy as np
import pytest

from odnn_sep.image.io import read_image
from odnn_sep.image.io_meta import apply_orientation

Image = pytest.importorskip("PIL.Image", reason="Pillow writes the test files")


def _stored(h=24, w=36):
    # every pixel different, so a flip or a turn cannot pass for another
    return (np.arange(h * w * 3).reshape(h, w, 3) % 251).astype(np.uint8)


@pytest.mark.parametrize("big", [False, True])
@pytest.mark.parametrize("orientation", range(1, 9))
def test_tiff_orientation_applied_once(tmp_path, orientation, big):
    stored = _stored()
    im = Image.fromarray(stored)
    ex = im.getexif()
    ex[0x0112] = orientation
    src = tmp_path / "p.tif"
    im.save(src, exif=ex.tobytes(), **({"big_tiff": True} if big else {}))
    got = read_image(src)
    upright = apply_orientation(stored, orientation)
    assert got.shape == upright.shape
    assert np.array_equal(got, upright)


def test_tiff_16bit_grey_orientation(tmp_path):
    stored = (np.arange(24 * 36).reshape(24, 36) * 61).astype(np.uint16)
    im = Image.fromarray(stored)
    ex = im.getexif()
    ex[0x0112] = 6
    src = tmp_path / "g.tif"
    im.save(src, exif=ex.tobytes())
    got = read_image(src)
    assert got.dtype == np.uint16
    assert np.array_equal(got, np.rot90(stored, -1))
