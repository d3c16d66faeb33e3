"""``--text "Studio 2024\\nJohn Doe"`` typed in a shell passes a backslash and an ``n``, not a line
break: the command looked for one line with a backslash in it and said "not found (best match score
0.000)", exit 1. The pair is now read as the line break meant, with a warning."""
import numpy as np

from odnn_sep.image.render import render_text
from odnn_sep.image.synth import photo_like


def _two_line_mark():
    photo = photo_like((260, 380), random_state=3).astype(float)
    M = np.zeros(photo.shape[:2])
    for text, (r, c) in (("Studio 2024", (70, 60)), ("John Doe", (118, 90))):
        g = render_text(text, "DejaVuSans-Bold", 30)
        M[r:r + g.shape[0], c:c + g.shape[1]] = np.maximum(M[r:r + g.shape[0], c:c + g.shape[1]], g)
    aM = 0.5 * M[..., None]
    return np.clip(np.round((1 - aM) * photo + aM * 255), 0, 255).astype(np.uint8)


def test_typed_backslash_n_is_a_line_break(tmp_path, capsys):
    from PIL import Image

    from odnn_sep.cli import main

    src, out = tmp_path / "in.png", tmp_path / "out.png"
    Image.fromarray(_two_line_mark()).save(src)
    assert main(["unwatermark", str(src), "-o", str(out), "--text", "Studio 2024\\nJohn Doe",
                 "--font", "DejaVuSans-Bold"]) == 0
    cap = capsys.readouterr()
    assert out.is_file() and "2 lines" in cap.out
    assert "typed as two characters" in cap.err
