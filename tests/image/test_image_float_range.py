"""A float image outside [0, 1] (0-255 floats, an overexposed scale) is refused, not clipped silently."""
import numpy as np
import pytest

from odnn_sep.errors import InputError
from odnn_sep.image import unwatermark
from odnn_sep.image.io import split
from odnn_sep.image.synth import add_text_watermark, photo_like


@pytest.fixture(scope="module")
def marked():
    y, _ = add_text_watermark(photo_like((120, 200), random_state=4), "SAMPLE", size=30, center=(100, 60))
    return y


def test_float_0_255_refused(marked):
    # before: clipped to white, searched, and reported "not found (best match score 0.000)"
    with pytest.raises(InputError, match=r"float image must hold values in \[0, 1\]; got .* to 255; for 0-255 "
                                         r"values use 8-bit pixels \(uint8\) or divide by 255"):
        unwatermark(marked.astype(np.float64), text="SAMPLE", font="DejaVuSans-Bold")


def test_float_over_one_refused(marked):
    # before: the mark was fitted on the clipped values (a wrong opacity) and the output clipped to 1
    with pytest.raises(InputError, match=r"got 0\.\d+ to 1\.2$"):
        unwatermark(marked / 255.0 * 1.2, text="SAMPLE", font="DejaVuSans-Bold")


def test_float_rounding_slack_accepted():
    a = np.full((8, 8, 3), 1.0 + 1e-9)
    a[0, 0] = -1e-9
    assert split(a).levels == 65535
    with pytest.raises(InputError, match="negative|got -0.5"):
        split(np.full((8, 8), -0.5))


def test_float_tiff_of_0_255_values_refused_by_the_command(marked, tmp_path, capsys):
    cv2 = pytest.importorskip("cv2")
    from odnn_sep.cli import main

    src = tmp_path / "f.tif"  # a 32-bit float TIFF holding 0-255 values, as some tools save them
    cv2.imwrite(str(src), cv2.cvtColor(marked.astype(np.float32), cv2.COLOR_RGB2BGR))
    assert main(["unwatermark", str(src), "--text", "SAMPLE", "--font", "DejaVuSans-Bold",
                 "-o", str(tmp_path / "o.png")]) == 1
    assert "a float image must hold values in [0, 1]" in capsys.readouterr().err
    assert not (tmp_path / "o.png").exists()


def test_float_resampling_overshoot_read_with_a_warning(caplog):
    # a cubic resize of a [0, 1] image overshoots at sharp edges by a few 8-bit levels
    a = np.full((8, 8, 3), 0.5)
    a[0, 0], a[1, 1] = 1.015, -0.01
    with caplog.at_level("WARNING", logger="odnn_sep.image.io"):
        assert split(a).levels == 65535
    assert "strays outside [0, 1]" in caplog.text
    with pytest.raises(InputError, match="got -0.01 to 1.03$"):
        split(np.where(a > 1, 1.03, a))
