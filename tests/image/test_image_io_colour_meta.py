"""What a photo file carries besides EXIF and ICC: its resolution and a PNG's own colour chunks are
written back, and a colour profile goes only onto pixels of its colour space (a CMYK JPEG is read as
RGB: its CMYK profile on the RGB output told viewers to read the pixels as ink)."""
from __future__ import annotations

import struct
import zlib

import numpy as np
import pytest

PIL = pytest.importorskip("PIL")


def _srgb() -> bytes:
    from PIL import ImageCms

    return ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()


def _photo():
    rng = np.random.default_rng(0)
    return rng.integers(0, 256, (40, 56, 3), dtype=np.uint8)


def _round_trip(src, out):
    from odnn_sep.image.io import read_image_meta, write_image

    img, meta = read_image_meta(src)
    write_image(out, img, meta=meta)
    from PIL import Image

    with Image.open(out) as im:
        return dict(im.info)


def test_cmyk_profile_is_not_written_onto_rgb_pixels(tmp_path, caplog):
    from PIL import Image

    cmyk_profile = bytearray(_srgb())
    cmyk_profile[16:20] = b"CMYK"      # the header's colour space field
    Image.fromarray(_photo()).convert("CMYK").save(tmp_path / "in.jpg", quality=95, icc_profile=bytes(cmyk_profile))
    for name in ("out.png", "out.jpg"):
        with caplog.at_level("WARNING"):
            info = _round_trip(tmp_path / "in.jpg", tmp_path / name)
        assert (info.get("icc_profile") or b"")[16:20] != b"CMYK", name
        assert "CMYK" in caplog.text


def test_rgb_profile_is_kept(tmp_path):
    from PIL import Image

    Image.fromarray(_photo()).save(tmp_path / "in.jpg", quality=95, icc_profile=_srgb())
    assert _round_trip(tmp_path / "in.jpg", tmp_path / "out.png")["icc_profile"] == _srgb()


@pytest.mark.parametrize("src,out", [("in.jpg", "out.jpg"), ("in.png", "out.png"), ("in.jpg", "out.png"),
                                     ("in.png", "out.jpg")])
def test_resolution_is_kept(tmp_path, src, out):
    from PIL import Image

    Image.fromarray(_photo()).save(tmp_path / src, dpi=(300, 300))
    dpi = _round_trip(tmp_path / src, tmp_path / out).get("dpi")
    assert dpi is not None and abs(dpi[0] - 300) < 0.5 and abs(dpi[1] - 300) < 0.5


def test_png_gamma_and_srgb_chunks_are_kept(tmp_path):
    import io

    from PIL import Image

    buf = io.BytesIO()
    Image.fromarray(_photo()).save(buf, format="PNG")
    b = buf.getvalue()

    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    end = 8 + 12 + struct.unpack(">I", b[8:12])[0]
    (tmp_path / "linear.png").write_bytes(b[:end] + chunk(b"gAMA", struct.pack(">I", 100000)) + b[end:])
    (tmp_path / "srgb.png").write_bytes(b[:end] + chunk(b"sRGB", b"\x01") + b[end:])
    assert _round_trip(tmp_path / "linear.png", tmp_path / "o1.png").get("gamma") == 1.0
    assert _round_trip(tmp_path / "srgb.png", tmp_path / "o2.png").get("srgb") == 1


def test_no_resolution_invented_for_a_jpeg_without_one(tmp_path):
    from PIL import Image

    from odnn_sep.image.io_meta import read_meta

    ex = Image.Exif()
    ex[0x010F] = "Camera"
    Image.fromarray(_photo()).save(tmp_path / "in.jpg", exif=ex)   # JFIF aspect 1:1, no resolution
    assert read_meta(tmp_path / "in.jpg").dpi is None
