"""Text marks tiled over a photo (a stock photo's grid), copies cut by the border included.

For each photo of the unseen-font generator (``_watermark_unseen.photos``), one tiled mark in a DejaVu
face: random word, face, size, angle within 40 degrees, opacity 0.3-0.7, white, black or a random
colour, the copies 1.2-2 text widths and 2.5-5 text heights apart on a grid turned with the text,
one copy centred at a random point. The command's API runs with the font given and without it.
Counted: outcome (removed / still visible / not found), copies placed, PSNR against the clean photo
(input and output; the output of a "still visible" run as ``--keep-partial`` writes it).

    python recipes/probe_image_tiles.py --seed 1      # development
    python recipes/probe_image_tiles.py --seed 2      # evaluation, run once
    PYTHONPATH=<checkout> python recipes/probe_image_tiles.py --seed 2   # the version before
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

DEJAVU = ("DejaVuSans", "DejaVuSans-Bold", "DejaVuSerif", "DejaVuSerif-Bold", "DejaVuSansMono")


def tiled(img, rng):
    """(marked image, truth) of one tiled mark on ``img``."""
    from _watermark_unseen import WORDS

    from odnn_sep.image.synth import add_text_watermark, text_coverage

    H, W = img.shape[:2]
    text, font = str(rng.choice(WORDS)), str(rng.choice(DEJAVU))
    size = int(rng.integers(max(14, min(H, W) // 22), max(16, min(H, W) // 10)))
    angle = float(rng.uniform(-40, 40))
    upright = text_coverage(text, font, size, 0)
    th, tw = upright.shape
    du, dv = float(rng.uniform(1.2, 2.0)) * tw, float(rng.uniform(2.5, 5.0)) * th
    t = np.deg2rad(angle)
    u = np.array([np.cos(t), -np.sin(t)]) * du        # along the text (counter-clockwise, y down)
    v = np.array([np.sin(t), np.cos(t)]) * dv         # across it
    c0 = np.array([rng.uniform(0, W), rng.uniform(0, H)])
    r = rng.random()
    color = (255,) * 3 if r < 0.4 else (0,) * 3 if r < 0.7 else tuple(int(x) for x in rng.integers(0, 256, 3))
    alpha = float(rng.uniform(0.3, 0.7))
    y = img
    n = 0
    reach = int(np.hypot(H, W) / min(du, dv)) + 2
    for i in range(-reach, reach + 1):
        for j in range(-reach, reach + 1):
            cx, cy = c0 + i * u + j * v
            if -tw < cx < W + tw and -tw < cy < H + tw:
                y, M = add_text_watermark(y, text, font=font, size=size, angle=angle, center=(float(cx), float(cy)),
                                          alpha=alpha, color=color)
                n += int(M.max() > 0.5)
    return y, {"text": text, "font": font, "size": size, "angle": round(angle, 1), "copies": n}


def psnr(a, b) -> float:
    d = np.asarray(a, float) - np.asarray(b, float)
    return float(10 * np.log10(255.0 ** 2 / max(float(np.mean(d * d)), 1e-12)))


def main(argv=None) -> int:
    from _watermark_unseen import photos

    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args(argv)
    rng = np.random.default_rng(a.seed)
    tally: dict = {}
    print("photo | text | copies drawn | font given | outcome | copies placed | PSNR in -> out | seconds")
    for name, img in photos():
        img = img if img.ndim == 3 else np.repeat(img[:, :, None], 3, axis=2)
        y, truth = tiled(img, rng)
        for given in (True, False):
            t0 = time.perf_counter()
            try:
                res = unwatermark(y, text=truth["text"], font=truth["font"] if given else None)
                outcome = "still visible" if res.report["residual_mark"]["visible"] else "removed"
                placed, out = len(res.report["marks"]), psnr(res.image, img)
            except InputError:
                outcome, placed, out = "not found", 0, psnr(y, img)
            key = ("font given" if given else "no font", outcome)
            tally.setdefault(key, []).append(out)
            print(f"{name} | {truth['text']} | {truth['copies']} | {given} | {outcome} | {placed} | "
                  f"{psnr(y, img):.1f} -> {out:.1f} | {time.perf_counter() - t0:.1f}", flush=True)
    for (mode, outcome), v in sorted(tally.items()):
        print(f"{mode}, {outcome}: {len(v)}; output PSNR median {np.median(v):.1f} dB, worst {min(v):.1f} dB")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
