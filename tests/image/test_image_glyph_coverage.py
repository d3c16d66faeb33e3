"""A text in a script the fonts do not cover is refused before the search, naming the characters.

Before, it was drawn as empty boxes, searched for seconds and reported "not found (best match
score 0.047)", as if the mark were too faint to find.
"""
import numpy as np

from odnn_sep.image.synth import photo_like


def test_cli_text_without_glyphs_is_refused_in_one_line(tmp_path, capsys):
    from PIL import Image

    from odnn_sep.cli import main
    src = tmp_path / "in.png"
    Image.fromarray(np.asarray(photo_like((120, 160)), np.uint8)).save(src)
    out = tmp_path / "out.png"
    assert main(["unwatermark", str(src), "-o", str(out), "--text", "水印 2024"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "U+6C34" in err[0] and "--font" in err[0]
    assert main(["unwatermark", str(src), "-o", str(out), "--text", "水印", "--font", "DejaVuSans"]) == 1
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("Error: font DejaVuSans has no glyph")
    assert not out.exists()
