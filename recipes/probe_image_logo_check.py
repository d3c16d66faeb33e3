"""Logo mode's residual-mark check on logos blended at scale 1, no rotation, opacity 0.6.

Each logo of ``bench_logo.make_logo`` (and the ring-and-bars logo of the tests) is blended into
``synth.photo_like((240, 360), random_state=3)`` at a random centre, with OpenCV's cubic warp of the
premultiplied logo (``tests/image/test_image_reference.blend``) or pasted at whole pixels, and removed
with ``--reference``. Printed per logo: the registered scale and angle, the check's measures
(``z`` of the edge correlation, ``rim_left``), PSNR of input and output against the clean photo, and
the check run on the clean photo as if it were the output (a perfect removal: "visible" there is a
false alarm of the check itself).

    python recipes/probe_image_logo_check.py --first -2 --last 19     # about 6 minutes on 2 busy cores
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests" / "image"))
sys.path.insert(0, str(Path(__file__).resolve().parent))


def psnr(a, b):
    d = a.astype(float) - b.astype(float)
    return 10 * np.log10(255.0**2 / max(float(np.mean(d * d)), 1e-12))


def main() -> int:
    from bench_logo import make_logo
    from test_image_reference import blend, logo_rgba

    import odnn_sep.image.logo_residual as lr
    from odnn_sep.image import unwatermark
    from odnn_sep.image.synth import photo_like

    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--first", type=int, default=-2, help="first logo (-2, -1: the tests' logo, mono / coloured)")
    ap.add_argument("--last", type=int, default=19)
    a = ap.parse_args()
    seen = {}
    check = lr.residual_mark

    def keep(y, out, M, L, **kw):         # the crops the check sees, to score the clean photo the same way
        seen["args"] = (np.array(y), np.array(M), np.array(L))
        return check(y, out, M, L, **kw)

    lr.residual_mark = keep
    clean = photo_like((240, 360), random_state=3)
    tally = {"outputs called visible": 0, "perfect removals called visible": 0, "logos": 0}
    for kind in ("warp", "paste"):
        for seed in range(a.first, a.last + 1):
            rng = np.random.default_rng(abs(seed) + (100 if kind == "warp" else 0))
            logo = make_logo(rng, bool(seed % 2)) if seed >= 0 else logo_rgba(seed == -1)
            h, w = logo.shape[:2]
            if w > 340:
                continue
            if kind == "warp":
                cx, cy = rng.uniform(w / 2 + 2, 360 - w / 2 - 2), rng.uniform(h / 2 + 2, 240 - h / 2 - 2)
                y, _ = blend(clean, logo, [(cx, cy, 1.0, 0.0)], 0.6)
            else:
                y0, x0 = int(rng.integers(0, 240 - h)), int(rng.integers(0, 360 - w))
                al = logo[:, :, 3:4] / 255 * 0.6
                yf = clean.astype(float)
                yf[y0:y0 + h, x0:x0 + w] = (1 - al) * yf[y0:y0 + h, x0:x0 + w] + al * logo[:, :, :3]
                y = np.round(yf).astype(np.uint8)
            r = unwatermark(y, reference=logo)
            rm, m, b = r.report["residual_mark"], r.report["marks"][0], r.report["bbox"]
            yc, M, L = seen["args"]
            perfect = check(yc, clean[b[1]:b[3], b[0]:b[2]] / 255.0, M, L)
            tally["logos"] += 1
            tally["outputs called visible"] += rm["visible"]
            tally["perfect removals called visible"] += perfect["visible"]
            print(f"{kind:5s} {seed:3d} scale {m['scale']:.4f} angle {m['angle_deg']:5.2f} visible {rm['visible']!s:5s} "
                  f"z {rm['z']:5.2f} rim_left {rm['rim_left']:.3f} PSNR in {psnr(clean, y):.1f} out "
                  f"{psnr(clean, r.image):.1f} | clean as output: visible {perfect['visible']!s:5s} z {perfect['z']:5.2f}",
                  flush=True)
    for k, v in tally.items():
        print(f"{k}: {v}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
