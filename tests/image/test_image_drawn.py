"""Letters of --text the mark does not have: the removal drew them in the opposite colour (exit 0 before)."""
import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.image import unwatermark
from odnn_sep.image.io import write_image
from odnn_sep.image.synth import add_text_watermark, photo_like


@pytest.fixture(scope="module")
def marked():
    clean = photo_like((240, 360), random_state=3)
    y, _ = add_text_watermark(clean, "SAMPLE", size=40, center=(180, 120), alpha=0.5)
    return y, clean


def test_true_text_draws_nothing(marked):
    r = unwatermark(marked[0], text="SAMPLE", font="DejaVuSans-Bold")
    assert r.report["residual_mark"]["drawn"] is None
    assert not r.report["residual_mark"]["visible"]


def test_added_letter_is_drawn_and_refused(marked, tmp_path, capsys):
    y, clean = marked
    r = unwatermark(y, text="SAMPLE X", font="DejaVuSans-Bold")
    drawn = r.report["residual_mark"]["drawn"]
    # the X sits right of the mark's last letter (x 268) and came out dark where the photo had no mark
    assert drawn and all(p["at"][0] > 268 and p["output_corr"] < -0.5 for p in drawn)
    assert r.report["residual_mark"]["visible"]
    x0 = int(min(p["at"][0] for p in drawn)) - 12
    err = np.abs(r.image[100:140, x0:x0 + 30].astype(int) - clean[100:140, x0:x0 + 30]).max()
    assert err > 40  # what the check is for: the photo there was damaged
    inp, out = tmp_path / "in.png", tmp_path / "out.png"
    write_image(inp, y)
    assert main(["unwatermark", str(inp), "--text", "SAMPLE X", "--font", "DejaVuSans-Bold", "-o", str(out)]) == 3
    msg = capsys.readouterr().err
    assert "the removal drew letters the image does not show" in msg
    assert "give --text with only the characters the mark shows" in msg
    assert not out.exists()
