"""``--reference``: a logo found over position, scale and rotation, its blend fitted and undone."""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.image import unwatermark
from odnn_sep.image.logo import Placement, prepare_logo, render
from odnn_sep.image.synth import photo_like

cv2 = pytest.importorskip("cv2", reason="OpenCV draws the logos and is the inpainting reference")


def psnr(a, b):
    d = a.astype(float) - b.astype(float)
    return 10 * np.log10(255.0**2 / max(np.mean(d * d), 1e-12))


def logo_rgba(coloured: bool) -> np.ndarray:
    """A ring and a bar code-like block, RGBA uint8 (transparent ground)."""
    a = np.zeros((70, 170, 4), np.uint8)
    c1 = (230, 60, 40) if coloured else (255, 255, 255)
    c2 = (40, 90, 220) if coloured else (255, 255, 255)
    cv2.circle(a, (35, 35), 28, c1 + (255,), 9, lineType=cv2.LINE_AA)
    for i, x in enumerate(range(80, 165, 12)):
        cv2.rectangle(a, (x, 12 + 3 * (i % 3)), (x + 5 + (i % 2) * 3, 58), c2 + (255,), -1)
    return a


def blend(clean, logo, placements, alpha):
    """The logo blended with Pillow-independent code: OpenCV's warp of premultiplied RGBA."""
    H, W = clean.shape[:2]
    y = clean.astype(float) / 255
    A = np.zeros((H, W))
    f = logo.astype(float) / 255
    for cx, cy, s, ang in placements:
        R = cv2.getRotationMatrix2D(((logo.shape[1] - 1) / 2, (logo.shape[0] - 1) / 2), ang, s)
        R[:, 2] += (cx - (logo.shape[1] - 1) / 2, cy - (logo.shape[0] - 1) / 2)
        pm = cv2.warpAffine(np.dstack([f[:, :, :3] * f[:, :, 3:], f[:, :, 3]]), R, (W, H), flags=cv2.INTER_CUBIC)
        m = np.clip(pm[:, :, 3], 0, 1)
        col = np.clip(pm[:, :, :3] / np.maximum(m, 1e-6)[:, :, None], 0, 1)
        y = (1 - alpha * m[:, :, None]) * y + alpha * m[:, :, None] * col
        A = np.maximum(A, m)
    return np.round(y * 255).astype(np.uint8), A


def telea(y, A):
    hole = cv2.dilate((A > 0.02).astype(np.uint8), np.ones((3, 3), np.uint8))
    return cv2.inpaint(y, hole * 255, 3, cv2.INPAINT_TELEA)


@pytest.mark.parametrize("coloured", [False, True])
def test_logo_found_opacity_fitted_and_removed(coloured):
    clean = photo_like((260, 400), random_state=11)
    logo = logo_rgba(coloured)
    y, A = blend(clean, logo, [(230.0, 140.0, 1.3, 17.0)], 0.4)
    r = unwatermark(y, reference=logo)
    rep = r.report
    assert rep["mode"] == "reference" and len(rep["marks"]) == 1
    m = rep["marks"][0]
    assert abs(m["center"][0] - 230) < 1.5 and abs(m["center"][1] - 140) < 1.5
    assert abs(m["scale"] - 1.3) < 0.03 and abs(m["angle_deg"] - 17) < 1.5
    assert abs(r.alpha - 0.4) < 0.03
    assert rep["logo_colours"] == ("own" if coloured else "fitted")
    assert psnr(clean, r.image) > psnr(clean, telea(y, A)) + 3
    res = rep["residual_mark"]
    assert res["input_score"] > 0.3 and res["score"] < 0.5 * res["input_score"]
    if not coloured:  # a coloured logo leaves a faint trace (~41 dB here), which the report may flag
        assert not res["visible"]


def test_logo_without_alpha_on_white_and_tiled_copies():
    clean = photo_like((300, 420), random_state=12)
    logo = logo_rgba(False)
    spots = [(110.0, 80.0), (310.0, 80.0), (110.0, 220.0), (310.0, 220.0)]
    y, A = blend(clean, logo, [(x, yy, 0.9, -8.0) for x, yy in spots], 0.35)
    flat = np.full(logo.shape[:2] + (3,), 255, np.uint8)
    a = logo[:, :, 3:4] / 255.0
    flat = np.round(flat * (1 - a) + 0 * a).astype(np.uint8)  # the logo in black on white, no alpha
    r = unwatermark(y, reference=flat)
    assert len(r.report["marks"]) == 4 and not r.report["logo_alpha_channel"]
    assert np.allclose(r.color, 1.0, atol=0.06)  # the mark's colour is fitted: white, though the file is black
    assert psnr(clean, r.image) > psnr(clean, telea(y, A)) + 3


def test_absent_logo_is_not_found():
    clean = photo_like((240, 360), random_state=13)
    with pytest.raises(InputError, match="not found"):
        unwatermark(clean, reference=logo_rgba(True))


@pytest.mark.parametrize("ref, match", [
    (np.zeros((0, 10, 4), np.uint8), "empty"),
    (np.zeros((400, 50, 4), np.uint8), "larger than the photo"),
    (np.zeros((30, 50, 4), np.uint8), "fully transparent"),
    (np.full((30, 50, 3), 200, np.uint8), "shows no logo"),
])
def test_bad_reference_one_line_error(ref, match):
    with pytest.raises(InputError, match=match) as e:
        unwatermark(photo_like((120, 160), random_state=1), reference=ref)
    assert "\n" not in str(e.value)


def test_render_places_the_logo_centre():
    lg = prepare_logo(logo_rgba(False), (300, 300), 3)
    M, _, (x0, y0, x1, y1) = render(lg, Placement(150.0, 120.0, 1.0, 0.0), (300, 300))
    ys, xs = np.nonzero(M > 0.5)
    assert abs((xs.min() + xs.max()) / 2 + x0 - 150) <= 1 and abs((ys.min() + ys.max()) / 2 + y0 - 120) <= 1


def test_cli_exit_code_3_and_keep_partial(tmp_path, monkeypatch):
    import odnn_sep.image.logo_residual as residual
    from odnn_sep.cli import main
    from odnn_sep.image.io import write_image

    clean = photo_like((200, 300), random_state=14)
    logo = logo_rgba(False)
    y, _ = blend(clean, logo, [(150.0, 100.0, 1.0, 5.0)], 0.45)
    src, ref, out = tmp_path / "y.png", tmp_path / "logo.png", tmp_path / "o.png"
    write_image(src, y)
    write_image(ref, logo)
    assert main(["unwatermark", str(src), "--reference", str(ref), "-o", str(out), "--quiet"]) == 0
    assert out.exists()
    # a mark judged still visible: exit 3, no output unless --keep-partial
    monkeypatch.setattr(residual, "VISIBLE_SD", -1e9)
    monkeypatch.setattr(residual, "VISIBLE_MIN", -1e9)
    out2 = tmp_path / "o2.png"
    assert main(["unwatermark", str(src), "--reference", str(ref), "-o", str(out2), "--quiet"]) == 3
    assert not out2.exists()
    assert main(["unwatermark", str(src), "--reference", str(ref), "-o", str(out2), "--quiet",
                 "--keep-partial"]) == 3
    assert out2.exists()
    big = tmp_path / "big.png"
    write_image(big, np.zeros((400, 400, 4), np.uint8))
    out3 = tmp_path / "o3.png"
    assert main(["unwatermark", str(src), "--reference", str(big), "-o", str(out3)]) == 1
    assert not out3.exists()


def test_unreadable_reference_is_named_as_the_reference(tmp_path, capsys):
    from PIL import Image

    from odnn_sep.cli import main

    Image.fromarray(np.zeros((40, 60, 3), np.uint8)).save(tmp_path / "p.png")
    (tmp_path / "logo.png").write_text("not an image")
    assert main(["unwatermark", str(tmp_path / "p.png"), "-o", str(tmp_path / "o.png"), "--reference",
                 str(tmp_path / "logo.png")]) != 0
    assert "--reference image" in capsys.readouterr().err
    assert not (tmp_path / "o.png").exists()
