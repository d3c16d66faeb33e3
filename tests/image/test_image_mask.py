"""``--mask``: polarity, soft masks as priors, opaque marks inpainted, bad masks refused."""
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.image import unwatermark
from odnn_sep.image.synth import add_text_watermark, make_watermark_demo, photo_like

cv2 = pytest.importorskip("cv2", reason="OpenCV is the inpainting reference")
REAL = Path(__file__).resolve().parents[2] / ".." / "shared" / "data" / "watermark_examples_braindotai"


def psnr(a, b):
    d = a.astype(float) - b.astype(float)
    return 10 * np.log10(255.0**2 / max(np.mean(d * d), 1e-12))


def telea(y, hole):
    return cv2.inpaint(y, hole.astype(np.uint8) * 255, 3, cv2.INPAINT_TELEA)


@pytest.fixture(scope="module")
def demo():
    return make_watermark_demo(random_state=3)


def test_black_on_white_mask_is_read_inverted_and_said(demo, caplog):
    y, clean, truth = demo
    rough = cv2.dilate((truth["mask"] > 0.05).astype(np.uint8), np.ones((7, 7), np.uint8))
    straight = unwatermark(y, mask=rough * 255)
    with caplog.at_level("WARNING"):
        flipped = unwatermark(y, mask=(1 - rough) * 255)
    assert "inverted" in caplog.text and flipped.report["mask_inverted"]
    assert "inverted" in flipped.report["mask_note"]
    assert not straight.report["mask_inverted"]
    told = unwatermark(y, mask=(1 - rough) * 255, mask_invert=True)
    assert np.array_equal(told.image, flipped.image)
    assert np.abs(flipped.image.astype(int) - straight.image.astype(int)).max() <= 1
    assert psnr(clean, flipped.image) > psnr(clean, telea(y, rough)) + 3
    # told to keep the polarity, the large mask is used as it is: no silent inversion (the photo
    # around the mark holds no blend of one colour and opacity: not found)
    with pytest.raises(InputError, match="no watermark found inside the mask"):
        unwatermark(y, mask=(1 - rough) * 255, mask_invert=False)


@pytest.mark.parametrize("bad, match", [
    (np.zeros((320, 480), np.uint8), "empty"),
    (np.full((320, 480), 255, np.uint8), "uniform"),
    (np.full((320, 480), 7, np.uint8), "uniform"),
    (np.ones((100, 480), np.uint8), "size"),
])
def test_bad_masks_one_line_error(demo, bad, match):
    with pytest.raises(InputError, match=match) as e:
        unwatermark(demo[0], mask=bad)
    assert "\n" not in str(e.value)


def test_opaque_logo_is_inpainted_and_said():
    clean = photo_like((200, 300), random_state=5)
    y = clean.copy()
    y[70:130, 60:120] = (30, 140, 230)  # an opaque two-colour logo
    y[90:110, 140:250] = (10, 10, 10)
    mask = np.zeros((200, 300), np.uint8)
    mask[66:134, 56:124] = 255
    mask[86:114, 136:254] = 255
    r = unwatermark(y, mask=mask)
    assert r.report["opaque"] and "inpainted" in r.report["mask_note"]
    ref = telea(y, mask > 0)
    assert psnr(clean, r.image) > psnr(clean, ref) - 0.5
    assert psnr(clean, r.image) > psnr(clean, y) + 5


def test_soft_mask_is_a_region_where_the_data_say_the_coverage():
    clean = photo_like((160, 320), random_state=7)
    y, M = add_text_watermark(clean, "SOFT", size=56, center=(160, 80), alpha=0.45, color=(255, 255, 255))
    soft = cv2.GaussianBlur((M > 0.05).astype(np.float32), (0, 0), 4)
    soft = np.round(255 * soft / soft.max()).astype(np.uint8)
    r = unwatermark(y, mask=soft)
    assert r.report["mask_soft"] and not r.report["opaque"]
    assert abs(r.alpha - 0.45) < 0.05
    assert psnr(clean, r.image) > psnr(clean, y) + 8


@pytest.mark.skipif(not (REAL / "logo_mask2.png").exists(), reason="shared data not present")
def test_real_logo_mask_matches_plain_inpainting(tmp_path):
    from odnn_sep.cli import main

    out = tmp_path / "o.png"
    assert main([*map(str, ["unwatermark", REAL / "logo_watermarked2.jpg", "--mask", REAL / "logo_mask2.png",
                            "-o", out, "--quiet"])]) == 0
    from odnn_sep.image.io import read_image

    y, res = read_image(REAL / "logo_watermarked2.jpg"), read_image(out)
    mk = read_image(REAL / "logo_mask2.png")[:, :, :3].max(axis=2) < 128
    ref = telea(y, mk)
    # the logo is opaque: what is gone is inpainted like cv2.inpaint does, nothing smeared outside
    assert np.array_equal(res[~mk], y[~mk])
    assert np.mean(np.abs(res[mk].astype(float) - ref[mk])) < 3.0
    assert np.mean(np.abs(res[mk].astype(float) - y[mk])) > 30.0


def test_cli_mask_flags_and_no_output_on_error(tmp_path, demo):
    from odnn_sep.cli import main
    from odnn_sep.image.io import write_image

    y, _, truth = demo
    src, mk, out = tmp_path / "y.png", tmp_path / "m.png", tmp_path / "o.png"
    write_image(src, y)
    write_image(mk, ((truth["mask"] <= 0.05) * 255).astype(np.uint8))
    assert main(["unwatermark", str(src), "--mask", str(mk), "--mask-invert", "-o", str(out), "--quiet"]) == 0
    assert out.exists()
    write_image(mk, np.zeros((10, 10), np.uint8))
    out2 = tmp_path / "o2.png"
    assert main(["unwatermark", str(src), "--mask", str(mk), "-o", str(out2), "--quiet"]) == 1
    assert not out2.exists()
