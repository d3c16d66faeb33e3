"""The real multi-line example as one text (``unwatermark_lines``, as the command runs it): CPU time
per line, each line's verdict, font, size and angle, and the output's PSNR against the original.

    python recipes/probe_image_lines_speed.py
"""
from __future__ import annotations

import hashlib
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def main() -> int:
    from _watermark_unseen import REAL_LINES

    import odnn_sep.image.api as api
    from odnn_sep.image.io import read_image
    from odnn_sep.image.textlines import unwatermark_lines

    d = Path(__file__).resolve().parents[1].parent / "shared" / "data" / "watermark_examples_braindotai"
    if not (d / "watermarked-image.png").is_file():
        print("no real example; nothing to do")
        return 0
    y = np.ascontiguousarray(read_image(d / "watermarked-image.png")[:, :, :3])
    inner, times, where = api.unwatermark, [], []

    def timed(*a, **k):  # CPU seconds of each line's search
        c0 = time.process_time()
        try:
            r = inner(*a, **k)
            where.append(f"size {r.report.get('font_size_px')}, angle {r.report.get('angle_deg')}")
            return r
        except Exception:
            where.append("-")
            raise
        finally:
            times.append(time.process_time() - c0)

    api.unwatermark = timed
    c0 = time.process_time()
    r = unwatermark_lines(y, REAL_LINES)
    total = time.process_time() - c0
    for ln, t, w in zip(r.report["lines"], times, where):
        print(f"{ln['text']!r}: {ln['outcome']}, font {Path(str(ln.get('font'))).name}, "
              f"{w}, residual {ln.get('residual_mark', {}).get('score')}, alpha {ln.get('alpha')}, {t:.1f} s CPU")
    print(f"total {total:.1f} s CPU; output sha1 {hashlib.sha1(np.ascontiguousarray(r.image).tobytes()).hexdigest()[:12]}; "
          f"PSNR {psnr_to_original(d, y, r.image):.2f} dB")
    return 0


def psnr_to_original(d, y, out) -> float:
    """PSNR of ``out`` against the original registered onto the watermarked image (ECC, affine)."""
    import cv2

    from odnn_sep.image.io import read_image

    o = np.ascontiguousarray(read_image(d / "original-image.png")[:, :, :3])
    H, W = y.shape[:2]
    go = cv2.cvtColor(o, cv2.COLOR_RGB2GRAY).astype(np.float32)
    gy = cv2.cvtColor(y, cv2.COLOR_RGB2GRAY).astype(np.float32)
    _, warp = cv2.findTransformECC(gy, go, np.eye(2, 3, dtype=np.float32), cv2.MOTION_AFFINE,
                                   (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 200, 1e-7), None, 5)
    clean = cv2.warpAffine(o, warp, (W, H), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                           borderMode=cv2.BORDER_REPLICATE).astype(float)
    mse = np.mean((clean - np.asarray(out, float)) ** 2)
    return float(10 * np.log10(255.0 ** 2 / mse))


if __name__ == "__main__":
    sys.exit(main())
