import json

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import FormatError, InputError
from odnn_sep.image import make_watermark_demo, read_image, unwatermark, write_image
from odnn_sep.image.synth import add_text_watermark, photo_like


def psnr(a, b):
    from skimage.metrics import peak_signal_noise_ratio

    return peak_signal_noise_ratio(a, b, data_range=255)


@pytest.fixture(scope="module")
def demo():
    return make_watermark_demo(random_state=3)


@pytest.fixture(scope="module")
def demo_result(demo):
    y, clean, truth = demo
    return unwatermark(y, text=truth["text"], font="DejaVuSans-Bold")


def test_text_mode_recovers_photo_alpha_colour(demo, demo_result):
    y, clean, truth = demo
    r = demo_result
    assert abs(r.alpha - truth["alpha"]) / truth["alpha"] < 0.02
    assert np.allclose(r.color * 255, truth["color"], atol=3)
    assert r.image.shape == y.shape and r.image.dtype == y.dtype
    assert psnr(clean, r.image) > 45 > psnr(clean, y) + 10
    rep = r.report
    assert rep["font"].endswith("DejaVuSans-Bold.ttf") and abs(rep["font_size_px"] - truth["size"]) < 0.5
    assert abs(rep["angle_deg"] - truth["angle"]) < 0.5
    assert rep["match_score"] >= rep["match_score_threshold"]
    for k in ("alpha", "color", "bbox", "lost_pixels", "runtime_s"):
        assert k in rep


def test_caller_array_not_mutated(demo):
    y, _, truth = demo
    before = y.copy()
    unwatermark(y, mask=truth["mask"] > 0.05)
    assert np.array_equal(y, before)


def test_mask_mode_beats_inpainting_with_the_same_rough_mask(demo):
    import cv2

    y, clean, truth = demo
    rough = cv2.dilate((truth["mask"] > 0.05).astype(np.uint8), np.ones((7, 7), np.uint8))
    r = unwatermark(y, mask=rough)
    telea = cv2.cvtColor(cv2.inpaint(cv2.cvtColor(y, cv2.COLOR_RGB2BGR), rough * 255, 3, cv2.INPAINT_TELEA),
                         cv2.COLOR_BGR2RGB)
    assert psnr(clean, r.image) > psnr(clean, telea) + 3
    assert abs(r.alpha - truth["alpha"]) < 0.1


def test_grey_16bit_and_rgba_keep_format():
    clean = photo_like((120, 200), random_state=4)
    g16 = (clean.mean(axis=2) * 257).astype(np.uint16)
    y, M = add_text_watermark(g16, "TEST", size=40, angle=0.0, center=(100, 60), alpha=0.5, color=(255, 255, 255))
    r = unwatermark(y, mask=M > 0.05)
    assert r.image.dtype == np.uint16 and r.image.shape == g16.shape
    rgba = np.dstack([clean, np.linspace(0, 255, 200 * 120).reshape(120, 200).astype(np.uint8)])
    y4, M4 = add_text_watermark(rgba, "TEST", size=40, center=(100, 60), alpha=0.5, color=(0, 0, 0))
    r4 = unwatermark(y4, mask=M4 > 0.05)
    assert r4.image.shape == rgba.shape and np.array_equal(r4.image[..., 3], rgba[..., 3])
    assert psnr(clean, r4.image[..., :3]) > psnr(clean, y4[..., :3])


def test_errors():
    y = photo_like((100, 150), random_state=1)
    with pytest.raises(InputError, match=r"give the watermark's text \(text=/--text\) or a mask"):
        unwatermark(y)
    with pytest.raises(InputError, match=r"image is empty \(shape \(0, 0, 3\)\)"):
        unwatermark(np.zeros((0, 0, 3), np.uint8), text="x")
    with pytest.raises(InputError, match=r"mask size 10x10 differs from the image size 150x100"):
        unwatermark(y, mask=np.ones((10, 10)))
    # the best score and what it was compared with
    with pytest.raises(InputError, match=r"text 'NOT HERE' not found in the image \(best match score [0-9.]+, "
                                         r"needs >= 0.19\); check --text/--font or give --mask"):
        unwatermark(y, text="NOT HERE", font="DejaVuSans-Bold")


def test_cli_end_to_end(tmp_path, demo):
    y, clean, truth = demo
    inp = tmp_path / "in.png"
    write_image(inp, y)
    rc = main(["unwatermark", str(inp), "--text", truth["text"], "--font", "DejaVuSans-Bold", "-o",
               str(tmp_path / "out.png"), "--report", str(tmp_path / "r.json"), "--plot", str(tmp_path / "p.png"),
               "--quiet"])
    assert rc == 0
    out = read_image(tmp_path / "out.png")
    assert psnr(clean, out) > 45
    rep = json.loads((tmp_path / "r.json").read_text())
    assert abs(rep["alpha"] - truth["alpha"]) < 0.02 and (tmp_path / "p.png").stat().st_size > 0


def test_cli_errors(tmp_path, capsys):
    y = photo_like((60, 80), random_state=2)
    inp = tmp_path / "in.png"
    write_image(inp, y)
    assert main(["unwatermark", str(inp), "-o", str(tmp_path / "o.png")]) == 1
    assert "give the watermark's text (--text) or a mask of its area (--mask)" in capsys.readouterr().err
    bad = tmp_path / "bad.png"
    bad.write_bytes(b"not an image at all")
    assert main(["unwatermark", str(bad), "--text", "x", "-o", str(tmp_path / "o.png")]) == 1
    assert "could not read input image" in capsys.readouterr().err
    empty = tmp_path / "empty.png"
    empty.write_bytes(b"")
    assert main(["unwatermark", str(empty), "--text", "x", "-o", str(tmp_path / "o.png")]) == 1
    assert "is empty (0 bytes)" in capsys.readouterr().err
    m = tmp_path / "m.png"
    write_image(m, np.zeros((10, 10), np.uint8))
    assert main(["unwatermark", str(inp), "--mask", str(m), "-o", str(tmp_path / "o.png")]) == 1
    assert "mask size 10x10 differs from the image size 80x60" in capsys.readouterr().err
    assert main(["unwatermark", str(inp), "--text", "x", "-o", str(inp)]) == 1
    assert "is the input file" in capsys.readouterr().err


def test_read_unreadable_raises_format_error(tmp_path):
    bad = tmp_path / "bad.jpg"
    bad.write_bytes(b"\x00\x01garbage")
    with pytest.raises(FormatError, match="could not read input image"):
        read_image(bad)


@pytest.mark.slow
def test_tiled_marks_all_found():
    clean = photo_like((300, 400), random_state=7)
    y, M = add_text_watermark(clean, "PROOF", size=30, angle=20, center=(200, 150), alpha=0.4,
                              color=(255, 255, 255), tile=(130, 90))
    r = unwatermark(y, text="PROOF", font="DejaVuSans-Bold")
    assert len(r.report["marks"]) >= 6
    assert abs(r.alpha - 0.4) < 0.01
    assert psnr(clean, r.image) > 45


def test_rotated_45_degrees_found():
    clean = photo_like((300, 300), random_state=11)
    y, M = add_text_watermark(clean, "DRAFT", size=44, angle=-45, center=(150, 150), alpha=0.5,
                              color=(0, 0, 0))
    r = unwatermark(y, text="DRAFT", font="DejaVuSans-Bold", max_marks=1)
    assert abs(r.report["angle_deg"] + 45) < 0.5
    assert psnr(clean, r.image) > 45


def test_unknown_font_message():
    from odnn_sep.image.render import resolve_font

    with pytest.raises(InputError, match=r"font 'NoSuchFont' not found as a file nor by name in .*; pass a "
                                         r"\.ttf/\.otf path or a name such as 'DejaVuSans-Bold'"):
        resolve_font("NoSuchFont")


@pytest.mark.parametrize("ext", [".png", ".tif"])
def test_cli_16bit_rgba_file_keeps_format(tmp_path, ext):
    clean = photo_like((90, 160), random_state=5).astype(np.uint16) * 257
    rgba = np.dstack([clean, np.full((90, 160), 40000, np.uint16)])
    y, M = add_text_watermark(rgba, "MARK", size=36, center=(80, 45), alpha=0.5, color=(255, 255, 255))
    inp, mask, out = tmp_path / f"in{ext}", tmp_path / "m.png", tmp_path / f"out{ext}"
    write_image(inp, y)
    write_image(mask, ((M > 0.05) * 255).astype(np.uint8))
    assert main(["unwatermark", str(inp), "--mask", str(mask), "-o", str(out), "--quiet"]) == 0
    back = read_image(out)
    assert back.dtype == np.uint16 and back.shape == rgba.shape
    assert np.array_equal(back[..., 3], rgba[..., 3])
    err_in = np.abs(y[..., :3].astype(float) - clean).mean()
    assert np.abs(back[..., :3].astype(float) - clean).mean() < err_in / 3


def test_large_image_found_on_reduced_copy_and_refined_at_full_resolution():
    # longer side above WORK_MAX_PX: searched on a reduced copy, the mark refined on its full-res crop
    from odnn_sep.image.api import WORK_MAX_PX

    clean = photo_like((900, 1300), random_state=5)
    assert max(clean.shape[:2]) > WORK_MAX_PX
    y, M = add_text_watermark(clean, "PROOF copy", size=70, angle=-15.0, center=(700.0, 420.0), alpha=0.45,
                              color=(250, 250, 250))
    r = unwatermark(y, text="PROOF copy", font="DejaVuSans-Bold", max_marks=1)
    assert abs(r.alpha - 0.45) / 0.45 < 0.02
    assert abs(r.report["font_size_px"] - 70) < 0.5 and abs(r.report["angle_deg"] + 15.0) < 0.5
    assert np.hypot(r.report["center"][0] - 700.0, r.report["center"][1] - 420.0) < 1.5
    assert psnr(clean, r.image) > 45


def test_threshold_above_the_score_means_not_found(demo):
    # the threshold decides: a real mark whose score is below a user's stricter --min-score is reported
    # as not found, with its score
    y, clean, truth = demo
    r = unwatermark(y, text=truth["text"], font="DejaVuSans-Bold", max_marks=1)
    strict = r.report["match_score"] + 0.01
    with pytest.raises(InputError, match=f"best match score {r.report['match_score']:.3f}, needs >= {strict:g}"):
        unwatermark(y, text=truth["text"], font="DejaVuSans-Bold", min_score=strict, max_marks=1)
