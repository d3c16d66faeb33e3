"""The advice printed when a mark is still visible fits the mode: --font and --mask do not go with --reference."""
from types import SimpleNamespace

import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.image import api
from odnn_sep.image.io import write_image
from odnn_sep.image.synth import photo_like


def _still_visible(mode):
    def fake(img, **kwargs):
        residual = {"score": 0.21, "visible": True, "edge_ncc": 0.2, "z": 7.9}
        return SimpleNamespace(image=np.array(img), alpha=0.5,
                               report={"mode": mode, "residual_mark": residual, "lost_pixels": 0})
    return fake


@pytest.mark.parametrize("mode, args, said, not_said", [
    ("reference", ["--reference", "logo.png"], "--mask over the mark instead of --reference", "--font"),
    ("text", ["--text", "SAMPLE"], "try --font with the mark's font file", "instead of --reference"),
    ("mask", ["--mask", "logo.png"], "a mask that follows the mark's strokes", "--font"),
])
def test_advice_fits_the_mode(tmp_path, monkeypatch, capsys, mode, args, said, not_said):
    inp, logo = tmp_path / "in.png", tmp_path / "logo.png"
    write_image(inp, photo_like((60, 80), random_state=2))
    write_image(logo, photo_like((48, 64), random_state=3))
    monkeypatch.setattr(api, "unwatermark", _still_visible(mode))
    args = [str(logo) if a == "logo.png" else a for a in args]
    assert main(["unwatermark", str(inp), "-o", str(tmp_path / "o.png"), *args]) == 3
    err = capsys.readouterr().err
    assert "mark still visible after removal" in err and said in err and not_said not in err
    assert not (tmp_path / "o.png").exists()
