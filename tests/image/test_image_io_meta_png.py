"""PNG metadata read without decoding the pixels, and with them when chunks follow the pixel data."""
import struct
import zlib

import numpy as np
from PIL import Image, PngImagePlugin

from odnn_sep.image.io import read_image_meta, write_image
from odnn_sep.image.io_meta import png_has_late_metadata, read_meta


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _with_late_chunk(src, dst, kind, data):
    """A copy of the PNG ``src`` with one chunk inserted just before IEND (after the pixel data)."""
    b = open(src, "rb").read()
    i = b.rindex(b"IEND") - 4
    open(dst, "wb").write(b[:i] + _chunk(kind, data) + b[i:])


def test_header_text_read_without_late_chunks(tmp_path):
    info = PngImagePlugin.PngInfo()
    info.add_text("Title", "sunset")
    f = tmp_path / "t.png"
    Image.fromarray(np.full((16, 24, 3), 90, np.uint8)).save(f, pnginfo=info)
    assert not png_has_late_metadata(f)
    assert read_meta(f).text == {"Title": "sunset"}


def test_text_after_pixel_data_is_read(tmp_path):
    f, g = tmp_path / "a.png", tmp_path / "b.png"
    write_image(f, np.full((16, 24, 3), 90, np.uint8))
    _with_late_chunk(f, g, b"tEXt", b"Author\x00someone")
    assert png_has_late_metadata(g)
    img, meta = read_image_meta(g)
    assert meta.text == {"Author": "someone"} and img.shape == (16, 24, 3)


def test_exif_orientation_after_pixel_data_is_applied(tmp_path):
    f, g = tmp_path / "a.png", tmp_path / "b.png"
    a = np.zeros((16, 24, 3), np.uint8)
    a[0, 0] = 255
    write_image(f, a)
    ex = Image.Exif()
    ex[0x0112] = 6  # rotate 90 degrees clockwise to display
    _with_late_chunk(f, g, b"eXIf", ex.tobytes()[6:] if ex.tobytes().startswith(b"Exif") else ex.tobytes())
    img, meta = read_image_meta(g)
    assert meta.orientation == 6 and img.shape == (24, 16, 3)


def test_exif_in_header_is_read(tmp_path):
    f = tmp_path / "e.png"
    ex = Image.Exif()
    ex[0x0112] = 3
    Image.fromarray(np.zeros((16, 24, 3), np.uint8)).save(f, exif=ex)
    meta = read_meta(f)
    assert meta.orientation == 3
