"""A text mark of several lines: each line found and removed in turn, the outcome honest per line.

Before, a line break in the text was refused, and a run with one line's text reported the mark
removed (exit 0) with the other line left in the photo.
"""
import numpy as np

from odnn_sep.image import unwatermark
from odnn_sep.image.render import render_text
from odnn_sep.image.synth import photo_like


def _two_line_mark():
    photo = photo_like((260, 380), random_state=3).astype(float)
    M = np.zeros(photo.shape[:2])
    for text, (r, c) in (("Studio 2024", (70, 60)), ("John Doe", (118, 90))):
        g = render_text(text, "DejaVuSans-Bold", 30)
        M[r:r + g.shape[0], c:c + g.shape[1]] = np.maximum(M[r:r + g.shape[0], c:c + g.shape[1]], g)
    aM = 0.5 * M[..., None]
    y = np.clip(np.round((1 - aM) * photo + aM * 255), 0, 255).astype(np.uint8)
    return y, photo


def _psnr(a, b):
    return 10 * np.log10(255 ** 2 / np.mean((np.asarray(a, float) - b) ** 2))


def test_both_lines_removed():
    y, photo = _two_line_mark()
    r = unwatermark(y, text="Studio 2024\nJohn Doe", font="DejaVuSans-Bold")
    assert [ln["outcome"] for ln in r.report["lines"]] == ["removed", "removed"]
    assert not r.report["residual_mark"]["visible"]
    assert _psnr(r.image, photo) > 45 > _psnr(y, photo)


def test_a_line_not_found_leaves_the_mark_visible():
    y, _ = _two_line_mark()
    r = unwatermark(y, text="Studio 2024\nQWXZ", font="DejaVuSans-Bold")
    assert r.report["residual_mark"]["visible"]
    assert r.report["lines"][0]["outcome"] == "removed"
    assert r.report["lines"][1]["outcome"] in ("not found", "still visible")


def test_cli_multiline_text_and_other_control_characters(tmp_path, capsys):
    from PIL import Image

    from odnn_sep.cli import main
    y, _ = _two_line_mark()
    src = tmp_path / "in.png"
    Image.fromarray(y).save(src)
    out = tmp_path / "out.png"
    assert main(["unwatermark", str(src), "-o", str(out), "--text", "Studio 2024\nJohn Doe",
                 "--font", "DejaVuSans-Bold"]) == 0
    assert out.is_file() and "2 lines" in capsys.readouterr().out
    assert main(["unwatermark", str(src), "-o", str(tmp_path / "o2.png"), "--text", "Studio\t2024"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "control character" in err[0] and not (tmp_path / "o2.png").exists()


def test_one_line_given_warns_about_the_line_beside():
    y, _ = _two_line_mark()
    r = unwatermark(y, text="Studio 2024", font="DejaVuSans-Bold")
    assert r.report["residual_mark"]["text_beside"]["side"] == "below"
    both = unwatermark(y, text="Studio 2024\nJohn Doe", font="DejaVuSans-Bold")
    assert "text_beside" not in both.report["residual_mark"] or both.report["residual_mark"]["text_beside"] is None
