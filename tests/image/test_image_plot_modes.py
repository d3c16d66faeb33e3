"""--plot draws every mode and image kind: mask mode (no font size), grey+alpha, a tall strip."""
from types import SimpleNamespace

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.image.io import write_image
from odnn_sep.image.plot import plot_unwatermark
from odnn_sep.image.synth import add_text_watermark, photo_like

Image = pytest.importorskip("PIL.Image", reason="Pillow reads the figure's size")


@pytest.fixture(scope="module")
def marked():
    y, M = add_text_watermark(photo_like((120, 200), random_state=4), "SAMPLE", size=30, center=(100, 60))
    return y, M


def test_mask_mode_plot_written(marked, tmp_path):
    # before: KeyError 'font_size_px' (the title read text mode's fields), exit 1, nothing kept
    y, M = marked
    inp, mask, out, fig = (tmp_path / n for n in ("in.png", "m.png", "o.png", "p.png"))
    write_image(inp, y)
    box = np.zeros(M.shape, np.uint8)
    rr, cc = np.nonzero(M > 0.05)
    box[rr.min() - 3:rr.max() + 4, cc.min() - 3:cc.max() + 4] = 255
    write_image(mask, box)
    assert main(["unwatermark", str(inp), "--mask", str(mask), "-o", str(out), "--plot", str(fig)]) == 0
    assert out.exists() and fig.stat().st_size > 5_000


def test_grey_alpha_plot_written(marked, tmp_path):
    # before: matplotlib's "Invalid shape (120, 200, 2) for image data", exit 1, nothing kept
    import cv2

    y, _ = marked
    grey = cv2.cvtColor(y, cv2.COLOR_RGB2GRAY)
    inp, out, fig = tmp_path / "la.png", tmp_path / "o.png", tmp_path / "p.png"
    write_image(inp, np.dstack([grey, np.full_like(grey, 200)]))
    assert main(["unwatermark", str(inp), "--text", "SAMPLE", "--font", "DejaVuSans-Bold", "-o", str(out),
                 "--plot", str(fig)]) == 0
    assert out.exists() and fig.stat().st_size > 5_000


def test_tall_strip_figure_bounded(tmp_path):
    # before: a 20 x 4000 px strip asked for a figure 2000 inches tall
    img = np.full((4000, 20, 3), 0.5)
    res = SimpleNamespace(image=img, alpha=0.4, mask=np.zeros((4000, 20)), report={})
    plot_unwatermark(img, res, tmp_path / "p.png")
    w, h = Image.open(tmp_path / "p.png").size
    assert h <= 3600 and w <= 1200
