"""Logo mode (``--reference``): how much of a removed logo's blend is left in outputs called removed.

Logos, photos and blends of ``bench_logo.py`` (one copy, PNG), the logo given with its alpha channel or
flattened. For every logo found, the output against the clean photo: the mean signed error over the
logo's solid interior (the logo's own pixels, alpha over 0.9 of its top, eroded by 2 px), in 8-bit
levels (the largest channel): an opacity fitted a few per cent off leaves the whole logo lighter or
darker, a flat patch a viewer sees at once on a dark ground. Beside it, the measures the outcome can
read without the clean photo (``residual.step_left`` along the logo's edges; ``residual.contrast_levels``
of a blend left in the output) and the tool's own call (``residual_mark.visible``).

    python recipes/probe_image_logo_left.py --seed 101 --trials 14       # development
    python recipes/probe_image_logo_left.py --seed 202 --trials 14       # evaluation, run once
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parents[1]))


def interior_bias(out, clean, A) -> float:
    """Largest |mean(out - clean)| over the channels, on the logo's solid interior (levels)."""
    import cv2

    solid = cv2.erode((A >= 0.9 * A.max()).astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    if solid.sum() < 20:
        return float("nan")
    d = out.astype(float)[solid] - clean.astype(float)[solid]
    return float(np.abs(d.mean(axis=0)).max())


def main(argv=None) -> int:
    from bench_logo import blend, flatten, make_logo, photos

    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark
    from odnn_sep.image.residual import contrast_levels, step_left

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=101)
    ap.add_argument("--trials", type=int, default=14)
    ap.add_argument("--dump", default=None, help="folder: each found trial's crops as .npz (to study measures)")
    a = ap.parse_args(argv)
    rng = np.random.default_rng(a.seed)
    ph = photos(False)
    removed_bias = []   # interior error of the outputs called removed (logos with a solid interior)
    print("photo | colours | alpha given | true alpha | fitted | found | called | interior bias | step share | "
          "step levels | contrast | seconds")
    for k in range(a.trials):
        name, clean = ph[k % len(ph)]
        coloured = bool(rng.random() < 0.5)
        logo = make_logo(rng, coloured)
        given = bool(rng.random() < 0.5)
        y, A, L, truth = blend(clean, logo, rng, False)
        t0 = time.perf_counter()
        try:
            res = unwatermark(y, reference=logo if given else flatten(logo))
        except InputError:
            print(f"{name} | {coloured} | {given} | {truth['alpha']:.3f} | - | no | - | - | - | - | - | "
                  f"{time.perf_counter() - t0:.1f}", flush=True)
            continue
        rep = res.report
        x0, y0, x1, y1 = rep["bbox"]
        yc, oc, Mc = y[y0:y1, x0:x1] / 255.0, res.image[y0:y1, x0:x1] / 255.0, res.mask[y0:y1, x0:x1].astype(float)
        if a.dump:
            Path(a.dump).mkdir(parents=True, exist_ok=True)
            np.savez_compressed(Path(a.dump) / f"{a.seed}_{k}.npz", y=yc, out=oc, M=Mc, clean=clean[y0:y1, x0:x1] / 255.0,
                                A=A[y0:y1, x0:x1], coloured=coloured, visible=rep["residual_mark"]["visible"])
        share, lv = step_left(oc, yc, Mc)
        con = contrast_levels(oc, Mc)
        bias = interior_bias(res.image, clean, A)
        if not rep["residual_mark"]["visible"] and np.isfinite(bias):
            removed_bias.append(bias)
        print(f"{name} | {coloured} | {given} | {truth['alpha']:.3f} | {rep['alpha']:.3f} | yes | "
              f"{'visible' if rep['residual_mark']['visible'] else 'removed'} | {bias:.1f} | "
              f"{share:.3f} | {lv:.1f} | {con:.1f} | {time.perf_counter() - t0:.1f}", flush=True)
    b = np.asarray(removed_bias)
    if b.size:
        print(f"called removed, with a solid interior: {b.size}; interior error >= 5 levels: {int((b >= 5).sum())} "
              f"(median {np.median(b):.1f}, worst {b.max():.1f} levels)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
