"""Image I/O keeps what photos carry: EXIF orientation applied, EXIF/ICC/PNG text written back."""
import numpy as np
import pytest

from odnn_sep.errors import FormatError
from odnn_sep.image.io import read_image, read_image_meta, split, write_image

Image = pytest.importorskip("PIL.Image", reason="Pillow writes the test files")
ImageCms = pytest.importorskip("PIL.ImageCms", reason="Pillow's ImageCms makes an ICC profile")
ImageOps = pytest.importorskip("PIL.ImageOps", reason="Pillow's exif_transpose is the reference")


def _photo(h=24, w=36):
    rng = np.random.default_rng(0)
    yy, xx = np.mgrid[0:h, 0:w]
    a = np.stack([xx * 6, yy * 9, (xx + yy) * 4], -1) + rng.integers(0, 20, (h, w, 3))
    return np.clip(a, 0, 255).astype(np.uint8)


def _icc():
    return ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()


@pytest.mark.parametrize("orientation", range(1, 9))
def test_exif_orientation_applied_like_pillow(tmp_path, orientation):
    src = tmp_path / "p.jpg"
    a = _photo()
    ex = Image.Exif()
    ex[0x0112] = orientation
    Image.fromarray(a).save(src, quality=100, exif=ex.tobytes())
    got = read_image(src)
    with Image.open(src) as im:
        ref = np.asarray(ImageOps.exif_transpose(im))
    assert got.shape == ref.shape
    assert np.abs(got.astype(int) - ref.astype(int)).max() <= 1  # decoders may differ by one level


@pytest.mark.parametrize("ext", [".jpg", ".png"])
def test_exif_and_icc_kept_orientation_reset(tmp_path, ext):
    src = tmp_path / f"p{ext}"
    ex = Image.Exif()
    ex[0x0112] = 6
    ex[0x010F] = "TestMaker"  # Make
    icc = _icc()
    kw = {"quality": 95} if ext == ".jpg" else {}
    Image.fromarray(_photo()).save(src, exif=ex.tobytes(), icc_profile=icc, **kw)
    img, meta = read_image_meta(src)
    assert img.shape[:2] == (36, 24)  # rotated upright
    out = tmp_path / f"o{ext}"
    write_image(out, img, src, meta=meta)
    with Image.open(out) as im:
        assert im.info.get("icc_profile") == icc
        e = im.getexif()
        assert e.get(0x0112) == 1 and e.get(0x010F) == "TestMaker"
        assert im.size == (24, 36)
    assert read_image(out).shape[:2] == (36, 24)  # reading the output again does not rotate it twice


def test_png_text_chunks_and_16bit_kept(tmp_path):
    from PIL import PngImagePlugin

    src = tmp_path / "t.png"
    info = PngImagePlugin.PngInfo()
    info.add_text("Author", "Ada")
    info.add_itxt("Description", "caf\u00e9 photo")
    icc = _icc()
    Image.fromarray(_photo()).save(src, pnginfo=info, icc_profile=icc)
    img, meta = read_image_meta(src)
    a16 = img.astype(np.uint16) * 257
    out = tmp_path / "o.png"
    write_image(out, a16, src, meta=meta)
    with Image.open(out) as im:
        assert im.text["Author"] == "Ada" and im.text["Description"] == "caf\u00e9 photo"
        assert im.info.get("icc_profile") == icc
    back = read_image(out)
    assert back.dtype == np.uint16 and np.array_equal(back, a16)


def test_grey_alpha_stays_grey_alpha(tmp_path):
    rng = np.random.default_rng(1)
    la = rng.integers(0, 256, (20, 30, 2)).astype(np.uint8)
    src = tmp_path / "la.png"
    Image.fromarray(la, "LA").save(src)
    img = read_image(src)
    assert img.shape == (20, 30, 2) and np.array_equal(img, la)
    planes = split(img)
    assert planes.grey and planes.view.shape == (20, 30, 1) and np.array_equal(planes.alpha, la[:, :, 1])
    out = tmp_path / "o.png"
    write_image(out, img, src)
    with Image.open(out) as im:
        assert im.mode == "LA"
    assert np.array_equal(read_image(out), la)


def test_palette_read_as_rgb_with_warning(tmp_path, caplog):
    src = tmp_path / "p.png"
    Image.fromarray(_photo()).convert("P").save(src)
    with caplog.at_level("WARNING"):
        img = read_image(src)
    assert img.shape == (24, 36, 3)
    assert "palette" in caplog.text


def test_animated_gif_refused(tmp_path):
    src = tmp_path / "a.gif"
    frames = [Image.fromarray(np.full((10, 12, 3), 40 * i, np.uint8)) for i in range(3)]
    frames[0].save(src, save_all=True, append_images=frames[1:])
    with pytest.raises(FormatError, match="animated"):
        read_image(src)


def test_cli_keeps_orientation_exif_and_icc(tmp_path):
    """A phone JPEG (orientation 6, ICC) through ``unwatermark --mask``: upright output, EXIF and ICC kept."""
    from odnn_sep.cli import main
    from odnn_sep.image.synth import add_text_watermark, photo_like

    clean = photo_like((120, 200), random_state=3)  # upright: 200 wide
    y, M = add_text_watermark(clean, "EXIF", size=40, center=(100, 60), alpha=0.5, color=(255, 255, 255))
    stored = np.ascontiguousarray(np.rot90(y, 1))  # the sensor's orientation; EXIF 6 turns it upright
    ex = Image.Exif()
    ex[0x0112] = 6
    src, mask, out = tmp_path / "phone.jpg", tmp_path / "m.png", tmp_path / "o.jpg"
    icc = _icc()
    Image.fromarray(stored).save(src, quality=98, exif=ex.tobytes(), icc_profile=icc)
    write_image(mask, ((M > 0.05) * 255).astype(np.uint8))  # drawn on the upright image
    assert main(["unwatermark", str(src), "--mask", str(mask), "-o", str(out), "--quiet"]) == 0
    with Image.open(out) as im:
        assert im.size == (200, 120) and im.getexif().get(0x0112) == 1
        assert im.info.get("icc_profile") == icc


def test_16bit_to_jpeg_is_warned(tmp_path, caplog):
    import logging

    from odnn_sep.image.io import read_image, write_image

    img = (np.arange(32 * 48 * 3, dtype=np.uint16).reshape(32, 48, 3) * 20)
    with caplog.at_level(logging.WARNING):
        write_image(tmp_path / "o.jpg", img)
    assert "16-bit image is written at 8 bits" in caplog.text
    assert read_image(tmp_path / "o.jpg").dtype == np.uint8
