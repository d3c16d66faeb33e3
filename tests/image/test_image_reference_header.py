"""A --reference logo with more pixels than the photo is refused from its header, before it is decoded."""
import struct
import zlib

from odnn_sep.cli import main
from odnn_sep.image import io
from odnn_sep.image.io import write_image
from odnn_sep.image.synth import photo_like


def _blank_png(path, w, h):
    """A grey PNG of w x h zeros, written row by row (a few hundred kilobytes for tens of megapixels)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)

    z = zlib.compressobj(9)
    row = bytes(w + 1)
    idat = b"".join(z.compress(row) for _ in range(h)) + z.flush()
    path.write_bytes(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
                     + chunk(b"IDAT", idat) + chunk(b"IEND", b""))


def test_huge_reference_refused_before_decoding(tmp_path, monkeypatch, capsys):
    inp, logo = tmp_path / "in.png", tmp_path / "logo.png"
    write_image(inp, photo_like((60, 80), random_state=2))
    _blank_png(logo, 6000, 5000)  # 30 megapixels in a small file
    decoded = []
    real = io.read_image

    def spy(path, *, what="input image"):
        decoded.append(what)
        return real(path, what=what)

    monkeypatch.setattr(io, "read_image", spy)
    assert main(["unwatermark", str(inp), "--reference", str(logo), "-o", str(tmp_path / "o.png")]) == 1
    err = capsys.readouterr().err
    assert "--reference image" in err and "is 6000x5000, more pixels than the photo (80x60)" in err
    assert "--reference image" not in decoded
    assert not (tmp_path / "o.png").exists()
