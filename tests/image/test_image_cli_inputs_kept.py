"""The --reference logo and a --font file are inputs: no report or figure is written over them."""
import shutil

import pytest

from odnn_sep.cli import main
from odnn_sep.image.io import write_image
from odnn_sep.image.render import resolve_font
from odnn_sep.image.synth import add_text_watermark, photo_like


@pytest.fixture
def photo(tmp_path):
    p = tmp_path / "in.png"
    write_image(p, photo_like((60, 80), random_state=2))
    return p


@pytest.mark.parametrize("flag", ["--report", "--plot"])
def test_report_or_plot_over_the_reference_refused(tmp_path, photo, capsys, flag):
    logo = tmp_path / "logo.png"
    write_image(logo, photo_like((48, 64), random_state=3))
    before = logo.read_bytes()
    assert main(["unwatermark", str(photo), "--reference", str(logo), "-o", str(tmp_path / "o.png"),
                 flag, str(logo)]) == 1
    assert f"{flag} path '{logo}' is the --reference file" in capsys.readouterr().err
    assert logo.read_bytes() == before
    assert not (tmp_path / "o.png").exists()


def test_report_over_the_font_file_refused(tmp_path, capsys):
    # a mark the search finds: the version before wrote its report over the font file
    photo = tmp_path / "marked.png"
    write_image(photo, add_text_watermark(photo_like((120, 200), random_state=2), "SAMPLE", size=30,
                                          center=(100, 60), alpha=0.5)[0])
    font = tmp_path / "mark.ttf"
    shutil.copyfile(resolve_font("DejaVuSans-Bold"), font)
    before = font.read_bytes()
    assert main(["unwatermark", str(photo), "--text", "SAMPLE", "--font", str(font), "-o", str(tmp_path / "o.png"),
                 "--report", str(font)]) == 1
    assert f"--report path '{font}' is the --font file" in capsys.readouterr().err
    assert font.read_bytes() == before
    assert not (tmp_path / "o.png").exists()
