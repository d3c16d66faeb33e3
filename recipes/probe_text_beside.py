"""How often the line-beside warning fires: on two-line marks given one line, and on single-line marks.

Marks in the DejaVu family (the font given), over the eight photos of the unseen-font benchmark
(``_watermark_unseen.photos``): random text, face, size, angle, opacity (0.3-0.8 for two lines,
0.25-0.8 for one), white / black / random colour. Two-line marks have a line spacing of 1.1-1.6
sizes and the tool is given one of the two lines; it should warn (``residual_mark.text_beside``).
Single-line marks: it should not.

    python recipes/probe_text_beside.py --seed 0            # development seed
    python recipes/probe_text_beside.py --seed 5 --single-seeds 5 6
    python recipes/probe_text_beside.py --seed 5 --scale 3   # photos and marks 3x larger
"""
from __future__ import annotations

import argparse
import logging
import sys
import warnings
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

PAIRS = [("Studio 2024", "John Doe"), ("SAMPLE", "do not copy"), ("Preview", "stock image"),
         ("PROOF", "not for sale"), ("photo by", "J Doe")]
WORDS = ["SAMPLE", "Studio 2024", "PROOF", "photo by J Doe", "DRAFT copy", "Preview", "odnn", "CONFIDENTIAL"]
FONTS = ["DejaVuSans-Bold", "DejaVuSans", "DejaVuSerif"]


def _blend(img, M, alpha, color):
    photo = img.astype(float)
    aM = alpha * (M[..., None] if photo.ndim == 3 else M)
    col = color if photo.ndim == 3 else color.mean()
    return np.clip(np.round((1 - aM) * photo + aM * col), 0, 255).astype(np.uint8)


def _marked(img, cov, rng, alpha_lo):
    """The photo with coverage ``cov`` blended at a random place, opacity (``alpha_lo``-0.8) and colour."""
    H, W = img.shape[:2]
    alpha, color = float(rng.uniform(alpha_lo, 0.8)), _colour(rng)
    x0, y0 = int(rng.integers(2, W - cov.shape[1] - 2)), int(rng.integers(2, H - cov.shape[0] - 2))
    M = np.zeros((H, W))
    M[y0:y0 + cov.shape[0], x0:x0 + cov.shape[1]] = cov
    return _blend(img, M, alpha, color)


def _colour(rng):
    r = rng.random()
    return np.array((255, 255, 255) if r < 0.4 else (0, 0, 0) if r < 0.7 else rng.integers(0, 256, 3), float)


def _two_lines(l1, l2, font, size, gap, angle):
    import cv2
    from _watermark_unseen import render

    from odnn_sep.image.render import resolve_font
    c1, c2 = (render(t, resolve_font(font), None, size, 0.0, 0, 0.0) for t in (l1, l2))
    w = max(c1.shape[1], c2.shape[1])
    block = np.zeros((int(gap + c2.shape[0]) + 8, w + 4))
    block[2:2 + c1.shape[0], 2:2 + c1.shape[1]] = c1
    r2 = int(2 + gap)
    block[r2:r2 + c2.shape[0], 2:2 + c2.shape[1]] = np.maximum(block[r2:r2 + c2.shape[0], 2:2 + c2.shape[1]], c2)
    rot = cv2.getRotationMatrix2D((block.shape[1] / 2, block.shape[0] / 2), angle, 1.0)
    cos, sin = abs(rot[0, 0]), abs(rot[0, 1])
    nw, nh = int(block.shape[0] * sin + block.shape[1] * cos) + 2, int(block.shape[0] * cos + block.shape[1] * sin) + 2
    rot[0, 2] += nw / 2 - block.shape[1] / 2
    rot[1, 2] += nh / 2 - block.shape[0] / 2
    return cv2.warpAffine(block.astype(np.float32), rot, (nw, nh), flags=cv2.INTER_CUBIC).clip(0, 1)


def _photos(scale):
    """The benchmark's photos, enlarged ``scale`` times (bicubic) so that the marks drawn on them are too."""
    import cv2
    from _watermark_unseen import photos

    return [(n, img if scale == 1 else cv2.resize(img, None, fx=scale, fy=scale, interpolation=cv2.INTER_CUBIC))
            for n, img in photos()]


def _run(y, text, font):
    from odnn_sep.image import unwatermark
    try:
        r = unwatermark(y, text=text, font=font)
    except Exception:  # noqa: BLE001 - a mark not found is not a run of the check
        return False
    return r.report["residual_mark"].get("text_beside")


def two_line_runs(seed, scale=1):
    rng = np.random.default_rng(seed)
    warned = n = 0
    for _name, img in _photos(scale):
        H, W = img.shape[:2]
        for _ in range(2):
            l1, l2 = PAIRS[int(rng.integers(len(PAIRS)))]
            font = FONTS[int(rng.integers(3))]
            size = int(rng.integers(max(16, min(H, W) // 18), max(18, min(H, W) // 9)))
            angle, gap = float(rng.uniform(-30, 30)), float(rng.uniform(1.1, 1.6)) * size
            cov = _two_lines(l1, l2, font, size, gap, angle)
            if cov.shape[0] >= H - 8 or cov.shape[1] >= W - 8:
                continue
            y = _marked(img, cov, rng, 0.3)
            which = l1 if rng.random() < 0.5 else l2
            tb = _run(y, which, font)
            n += tb is not False
            warned += tb not in (None, False)
    return warned, n


def single_line_runs(seed, scale=1):
    from _watermark_unseen import render

    from odnn_sep.image.render import resolve_font
    rng = np.random.default_rng(seed)
    warned = n = 0
    for _name, img in _photos(scale):
        H, W = img.shape[:2]
        for _ in range(3):
            text, font = str(rng.choice(WORDS)), FONTS[int(rng.integers(3))]
            size = int(rng.integers(max(16, min(H, W) // 18), max(18, min(H, W) // 7)))
            cov = render(text, resolve_font(font), None, size, 0.0, 0, float(rng.uniform(-45, 45)))
            if cov.shape[0] >= H - 8 or cov.shape[1] >= W - 8:
                continue
            tb = _run(_marked(img, cov, rng, 0.25), text, font)
            n += tb is not False
            warned += tb not in (None, False)
    return warned, n


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=0, help="seed of the two-line marks")
    ap.add_argument("--single-seeds", type=int, nargs="*", default=None, help="seeds of the single-line marks")
    ap.add_argument("--scale", type=int, default=1, help="enlarge the photos (and so the marks) this many times")
    args = ap.parse_args(argv)
    warnings.simplefilter("ignore")
    logging.disable(logging.WARNING)
    w, n = two_line_runs(args.seed, args.scale)
    print(f"two-line marks, one line given (seed {args.seed}, scale {args.scale}): warned on {w} of {n} marks found")
    for s in args.single_seeds if args.single_seeds is not None else [args.seed]:
        w, n = single_line_runs(s, args.scale)
        print(f"single-line marks (seed {s}, scale {args.scale}): warned on {w} of {n} marks found")
    return 0


if __name__ == "__main__":
    sys.exit(main())
