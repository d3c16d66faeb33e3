"""New-user inputs of ``odnn-sep unwatermark`` that no generator draws: what a photo file carries and
how marks are laid out (a fourth round; the earlier rounds are ``probe_user_inputs.py`` and
``probe_image_drawn.py``).

Each case runs the command line as a user would (``odnn-sep unwatermark ... --font DejaVuSans-Bold``)
and prints one row: the exit code, what the output file holds, and the PSNR against the clean photo
where there is one. Run it on another checkout with ``PYTHONPATH=<checkout>`` for the version before.

    python recipes/probe_image_inputs.py            # about 2 minutes on 2 busy cores
"""
from __future__ import annotations

import os
import struct
import subprocess
import sys
import tempfile
import zlib
from pathlib import Path

import numpy as np


def _cli(*args) -> tuple[int, str]:
    env = dict(os.environ)
    p = subprocess.run([sys.executable, "-m", "odnn_sep.cli", "unwatermark", *map(str, args)], capture_output=True,
                       text=True, env=env)
    return p.returncode, (p.stdout + p.stderr).strip().splitlines()[-1][:110] if (p.stdout + p.stderr).strip() else ""


def _psnr(a, b) -> float:
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(10 * np.log10(255.0 ** 2 / max(float(np.mean(d * d)), 1e-12)))


def _info(path):
    from PIL import Image

    if not Path(path).exists():
        return None, {}
    with Image.open(path) as im:
        return np.asarray(im.convert("RGB")), dict(im.info)


def _srgb() -> bytes:
    from PIL import ImageCms

    return ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()


def main() -> int:
    from PIL import Image

    from odnn_sep.image.io import read_image
    from odnn_sep.image.synth import add_text_watermark, photo_like

    d = Path(tempfile.mkdtemp(prefix="probe_image_inputs_"))
    clean = photo_like((320, 480), random_state=3)
    y, _ = add_text_watermark(clean, "SAMPLE", size=40, angle=10, center=(240, 160), alpha=0.5)
    mark = Image.fromarray(y)
    font = ("--text", "SAMPLE", "--font", "DejaVuSans-Bold")
    rows = []

    cmyk = bytearray(_srgb())
    cmyk[16:20] = b"CMYK"                       # a CMYK profile's header, as a print shop's JPEG carries
    mark.convert("CMYK").save(d / "cmyk.jpg", quality=95, icc_profile=bytes(cmyk))
    for out in ("cmyk_out.png", "cmyk_out.jpg"):
        rc, _ = _cli(d / "cmyk.jpg", "-o", d / out, *font)
        icc = (_info(d / out)[1].get("icc_profile") or b"")[16:20].decode() or "none"
        rows.append((f"CMYK JPEG with a CMYK profile -> {out[-3:].upper()}", f"exit {rc}, profile on the RGB output: {icc}"))

    mark.save(d / "dpi.jpg", quality=95, dpi=(300, 300))
    mark.save(d / "dpi.png", dpi=(300, 300))
    for src, out in (("dpi.jpg", "dpi_out.jpg"), ("dpi.png", "dpi_out.png")):
        rc, _ = _cli(d / src, "-o", d / out, *font)
        dpi = _info(d / out)[1].get("dpi")
        rows.append((f"{src[-3:].upper()} at 300 dpi", f"exit {rc}, output dpi {tuple(round(v) for v in dpi) if dpi else None}"))

    buf = (d / "plain.png")
    mark.save(buf)
    b = buf.read_bytes()
    end = 8 + 12 + struct.unpack(">I", b[8:12])[0]
    chunk = b"gAMA" + struct.pack(">I", 100000)
    (d / "linear.png").write_bytes(b[:end] + struct.pack(">I", 4) + chunk + struct.pack(">I", zlib.crc32(chunk)) + b[end:])
    rc, _ = _cli(d / "linear.png", "-o", d / "linear_out.png", *font)
    rows.append(("PNG with gAMA 1.0 (linear)", f"exit {rc}, output gamma {_info(d / 'linear_out.png')[1].get('gamma')}"))

    two = clean.copy()
    for text, c in (("Studio 2024", (240, 130)), ("John Doe", (240, 185))):
        two, _ = add_text_watermark(two, text, size=32, center=c, alpha=0.5)
    Image.fromarray(two).save(d / "two.png")
    rc, _ = _cli(d / "two.png", "-o", d / "two_out.png", "--text", "Studio 2024\\nJohn Doe", "--font", "DejaVuSans-Bold")
    out, _ = _info(d / "two_out.png")
    rows.append(("--text \"Studio 2024\\nJohn Doe\" (typed in bash, no $'')",
                 f"exit {rc}, PSNR {_psnr(out, clean) if out is not None else _psnr(two, clean):.1f} dB"
                 f"{'' if out is not None else ' (no output: the input)'}"))

    photos = [("photo_like", clean)]
    cat = Path(__file__).resolve().parents[2] / "shared" / "data" / "photos_clean_skimage" / "chelsea.png"
    if cat.is_file():
        photos.append(("chelsea", np.ascontiguousarray(read_image(cat)[:, :, :3])))
    for name, img in photos:
        H, W = img.shape[:2]
        t, _ = add_text_watermark(img, "SAMPLE", size=28, angle=30, center=(W / 2, H / 2), alpha=0.5, tile=(200, 120))
        Image.fromarray(t).save(d / f"tile_{name}.png")
        rc, _ = _cli(d / f"tile_{name}.png", "-o", d / f"tile_{name}_out.png", "--keep-partial", *font)
        out, _ = _info(d / f"tile_{name}_out.png")
        rows.append((f"diagonal tile, {name} ({W}x{H}, 200x120 px apart, 30 deg)",
                     f"exit {rc}, PSNR {_psnr(t, img):.1f} -> {_psnr(out, img):.1f} dB (--keep-partial)"))

    img = photo_like((300, 450), random_state=4)
    t, _ = add_text_watermark(img, "SAMPLE", size=28, angle=30, center=(225, 150), alpha=0.5)
    t, _ = add_text_watermark(t, "SAMPLE", size=28, angle=30, center=(425, 29), alpha=0.5)
    Image.fromarray(t).save(d / "corner.png")
    rc, _ = _cli(d / "corner.png", "-o", d / "corner_out.png", "--keep-partial", *font)
    out, _ = _info(d / "corner_out.png")
    rows.append(("one whole copy and one cut at a corner", f"exit {rc}, corner PSNR {_psnr(t[:80, 360:], img[:80, 360:]):.1f} -> "
                 f"{_psnr(out[:80, 360:], img[:80, 360:]):.1f} dB"))

    print("| input | outcome |\n|---|---|")
    for a, b_ in rows:
        print(f"| {a} | {b_} |")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
