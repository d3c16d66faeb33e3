"""Watermark: letters the removal draws when ``--text`` has characters the mark does not have.

For each photo of the unseen-font generator (``_watermark_unseen.photos``), one mark in a font the tool
never tries (``_watermark_unseen.draw``) and one in a DejaVu face the tool tries (random face, size,
angle within 40 degrees, opacity 0.3-0.8, white, black or random colour), PNG (and JPEG q 90 with
``--jpeg``). Each mark is removed without ``--font``, given its own text and given its text with a
character added ("X" at the end; a longer addition, " 2024", was never found on development seed 1:
the search refuses a text that much longer than the mark). Counted: marks found, outputs with parts called drawn (``residual_mark.drawn``; with the
true text every one of them is a false alarm), and with the longer text, outputs with parts called drawn
against those written as removed (exit 0) anyway.

    python recipes/probe_image_drawn.py --seed 1          # development (about 4 minutes on 2 busy cores)
    python recipes/probe_image_drawn.py --seed 5 --photos 4   # a second draw, run once
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

DEJAVU = ("DejaVuSans", "DejaVuSans-Bold", "DejaVuSerif", "DejaVuSerif-Bold", "DejaVuSansMono")


def _dejavu(img, rng):
    from _watermark_unseen import WORDS

    from odnn_sep.image.synth import add_text_watermark, text_coverage

    H, W = img.shape[:2]
    for _ in range(50):
        text, font = str(rng.choice(WORDS)), str(rng.choice(DEJAVU))
        size, angle = int(rng.integers(max(16, min(H, W) // 18), max(18, min(H, W) // 7))), float(rng.uniform(-40, 40))
        h, w = text_coverage(text, font, size, angle).shape
        if h < H - 8 and w < W - 8:
            break
    r = rng.random()
    color = (255, 255, 255) if r < 0.4 else (0, 0, 0) if r < 0.7 else tuple(int(v) for v in rng.integers(0, 256, 3))
    center = (float(rng.uniform(w / 2 + 2, W - w / 2 - 2)), float(rng.uniform(h / 2 + 2, H - h / 2 - 2)))
    y, _ = add_text_watermark(img, text, font=font, size=size, angle=angle, center=center,
                              alpha=float(rng.uniform(0.3, 0.8)), color=color)
    return y, {"text": text, "font": font, "size": size}


def _run(y, text):
    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark

    try:
        rep = unwatermark(y, text=text).report
    except InputError:
        return "not found", 0
    res = rep.get("residual_mark") or {}
    return ("visible" if res.get("visible") else "removed"), len(res.get("drawn") or [])


def main() -> int:
    from _watermark_unseen import available_fonts, draw, photos
    from bench_watermark import jpeg

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--jpeg", action="store_true", help="each mark as JPEG (q 90) too")
    ap.add_argument("--photos", type=int, default=None, help="only the first N photos")
    a = ap.parse_args()
    rng = np.random.default_rng(a.seed)
    fonts = available_fonts()
    tally = {"marks": 0, "found": 0, "true text: drawn (false alarm)": 0, "longer text: found": 0,
             "longer text: drawn": 0, "longer text: exit 0 anyway": 0}
    for name, img in photos()[:a.photos]:
        marks = [("unseen",) + draw(img, rng, fonts)[::3], ("dejavu",) + _dejavu(img, rng)]
        for family, y_png, truth in marks:
            for fmt in ("png", "jpeg") if a.jpeg else ("png",):
                y = y_png if fmt == "png" else jpeg(y_png)
                tally["marks"] += 1
                outcome, drawn = _run(y, truth["text"])
                tally["found"] += outcome != "not found"
                tally["true text: drawn (false alarm)"] += drawn > 0
                line = f"{name:22s} {family:6s} {fmt:4s} {truth['font']:28s} {truth['text']!r:18s} {outcome:9s} drawn {drawn}"
                for extra in ("X",):
                    o2, d2 = _run(y, truth["text"] + extra)
                    tally["longer text: found"] += o2 != "not found"
                    tally["longer text: drawn"] += d2 > 0
                    tally["longer text: exit 0 anyway"] += o2 == "removed"
                    line += f" | +{extra.strip()!r}: {o2} drawn {d2}"
                print(line, flush=True)
    for k, v in tally.items():
        print(f"{k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
