"""A text that cannot fit in the image at the smallest size searched: the error says so (sizes of the
text and of the image), instead of "not found (best match score 0.000)"."""
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import MarkNotFoundError
from odnn_sep.image import unwatermark
from odnn_sep.image.io import write_image
from odnn_sep.image.synth import add_text_watermark, photo_like


@pytest.mark.parametrize("font", [None, "DejaVuSans-Bold"])
def test_text_wider_than_the_image_says_so(font):
    with pytest.raises(MarkNotFoundError, match=r"px wide, more than the image \(60 x 40 px") as exc:
        unwatermark(photo_like((40, 60), random_state=1), text="COPYRIGHT ACME CORPORATION", font=font)
    assert "score 0.000" not in str(exc.value)


def test_cli_one_line_error_and_no_output(tmp_path, capsys):
    src = tmp_path / "small.png"
    write_image(src, photo_like((40, 60), random_state=1))
    out = tmp_path / "o.png"
    assert main(["unwatermark", str(src), "--text", "COPYRIGHT", "-o", str(out)]) == 1
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and "smallest size searched" in err and "(60 x 40 px" in err
    assert not out.exists()


def test_a_text_that_fits_is_still_found():
    y, _ = add_text_watermark(photo_like((60, 120), random_state=2), "SAMPLE", size=16, center=(60, 30),
                              alpha=0.5)
    r = unwatermark(y, text="SAMPLE", font="DejaVuSans-Bold")
    assert abs(r.alpha - 0.5) < 0.05
