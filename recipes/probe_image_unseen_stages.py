"""Which stage of the text search loses a mark in a font the tool never tries (issue 13).

Draws the marks of ``bench_watermark.py --unseen-only --unseen-trials 1 --seed S`` (the same random
draws, ``_watermark_unseen.draw``), runs ``unwatermark`` without ``--font`` as the benchmark does, and
records every look of the search: where the true mark ranks on the coarse grid, after the coarse
selection, after the finer grids, after the blend-fit screening, whether a placement at the true place
was registered and its detection score, and the best score of each look (and of the glyph-by-glyph
look). Two oracle scores bound what the detection statistic can do: the true coverage at the true
place, and the default fonts registered from the true place. ``--clean`` runs the benchmark's
false-alarm searches instead (clean photos, random text) and prints their best scores per look.

Usage::

    python recipes/probe_image_unseen_stages.py --seed 7 [--only-missed] [--clean]
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


class Recorder:
    """Wraps the search's stages and keeps what each look saw."""

    def __init__(self):
        self.looks = []
        self.truth = None  # (cx, cy, radius) of the true mark, or None on clean photos
        self.scales = False  # also score every registered placement on copies reduced 2x and 3x
        self.moved = False  # also move the glyphs of every placement at the true place (``layoutlook.moved``)
        self.text = None

    def near(self, cx, cy) -> bool:
        if self.truth is None:
            return False
        tx, ty, rad = self.truth
        return float(np.hypot(cx - tx, cy - ty)) <= rad

    def install(self):
        import odnn_sep.image.layoutlook as layoutlook
        import odnn_sep.image.locate as locate
        import odnn_sep.image.textmode as textmode

        rec = self
        orig_best, orig_coarse, orig_select, orig_search = (textmode.best_match, locate._coarse, locate._select,
                                                            locate.search)
        orig_screen, orig_score, orig_layout = textmode.screen_hypotheses, textmode.placement_score, \
            layoutlook.layout_look

        def best_match(*a, **kw):
            look = {k: (Path(v).name if isinstance(v, (str, Path)) else v) for k, v in kw.items() if k != "tried"}
            rec.looks.append({"look": look or "first", "fonts": [Path(f).name for f in a[2]], "scores": []})
            out = orig_best(*a, **kw)
            rec.looks[-1]["final"] = out[2]
            return out

        def coarse(*a, **kw):
            cands = orig_coarse(*a, **kw)
            s = sorted(cands, key=lambda c: -c[0])
            ranks = [i for i, c in enumerate(s) if rec.near(c[3], c[4])]
            rec.looks[-1]["coarse"] = (ranks[0] if ranks else None, len(s), s[ranks[0]][0] if ranks else None,
                                       s[0][0] if s else None)
            return cands

        def select(cands, *a, **kw):
            top = orig_select(cands, *a, **kw)
            ranks = [i for i, c in enumerate(top) if rec.near(c[3], c[4])]
            rec.looks[-1]["select"] = (ranks[0] if ranks else None, len(top))
            return top

        def search(*a, **kw):
            out = orig_search(*a, **kw)
            ranks = [i for i, m in enumerate(out) if rec.near(*m.center)]
            rec.looks[-1]["finer"] = (ranks[0] if ranks else None, len(out))
            return out

        def screen(*a, **kw):
            out = orig_screen(*a, **kw)
            s = sorted(out, key=lambda t: -t[0])
            ranks = [i for i, t in enumerate(s) if rec.near(*t[1].center)]
            rec.looks[-1]["screen"] = (ranks[0] if ranks else None, len(s), s[ranks[0]][0] if ranks else None,
                                       s[0][0] if s else None)
            return out

        def score(y, p, **kw):
            v = orig_score(y, p, **kw)
            if rec.looks:
                coarse = coarse_scores(y, p) if rec.scales else (float("nan"), float("nan"))
                rec.looks[-1]["scores"].append((float(v), rec.near(*p.center), Path(p.font).name, round(p.size, 1),
                                                *coarse))
                if rec.moved and rec.near(*p.center):
                    from odnn_sep.image.layoutlook import moved

                    rec.looks[-1].setdefault("moved", []).append(moved(y, rec.text, p, 0)[1])
            return v

        def layout(*a, **kw):
            q, v = orig_layout(*a, **kw)
            rec.looks.append({"look": "layout", "final": v, "near": q is not None and rec.near(*q.center),
                              "scores": []})
            return q, v

        textmode.best_match, locate._coarse, locate._select, locate.search = best_match, coarse, select, search
        textmode.screen_hypotheses, textmode.placement_score, layoutlook.layout_look = screen, score, layout


def coarse_scores(y, p):
    """Detection scores of a registered placement on its crop and rendering reduced 2x and 3x (area)."""
    import cv2

    from odnn_sep.image.detect import detection_score

    x0, y0, x1, y1 = p.box
    crop, m = np.asarray(y[y0:y1, x0:x1], dtype=np.float32), p.coverage.astype(np.float32)
    out = []
    for k in (2, 3):
        h, w = m.shape
        if min(h, w) // k < 12:
            out.append(float("nan"))
            continue
        cs = cv2.resize(crop, (w // k, h // k), interpolation=cv2.INTER_AREA)
        ms = cv2.resize(m, (w // k, h // k), interpolation=cv2.INTER_AREA)
        out.append(detection_score(cs.reshape(h // k, w // k, -1).astype(np.float64), ms.astype(np.float64)))
    return tuple(out)


def true_place(M):
    nz = np.nonzero(M > 0.05)
    x0, x1, y0, y1 = nz[1].min(), nz[1].max(), nz[0].min(), nz[0].max()
    return (x0 + x1) / 2, (y0 + y1) / 2, max(6.0, 0.2 * max(x1 - x0, y1 - y0)), (x0, y0, x1 + 1, y1 + 1)


def oracles(y, text, M, truth):
    """(true coverage's detection score, best default font registered from the true place)."""
    from odnn_sep.errors import NotIdentifiableError
    from odnn_sep.image.detect import detection_score
    from odnn_sep.image.register import refine
    from odnn_sep.image.render import default_fonts
    from odnn_sep.image.screening import placement_score

    cx, cy, _, (x0, y0, x1, y1) = true_place(M)
    H, W = M.shape
    pad = 6
    b = (max(0, x0 - pad), max(0, y0 - pad), min(W, x1 + pad), min(H, y1 + pad))
    yf = y.astype(np.float64) / 255
    if yf.ndim == 2:
        yf = yf[:, :, None]
    true_sc = detection_score(yf[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]])
    best = (0.0, None)
    for f in default_fonts()[:4]:
        try:
            p = refine(yf, text, f, float(truth["size"]), float(truth["angle"]), (cx, cy), iterations=40)
        except NotIdentifiableError:
            continue
        v = placement_score(yf, p)
        if v > best[0]:
            best = (v, Path(f).name)
    return true_sc, best


def fmt_look(lk) -> str:
    top = max((s[0] for s in lk["scores"]), default=0.0)
    near = max((s[0] for s in lk["scores"] if s[1]), default=None)
    if lk["look"] == "layout":
        return f"layout: best {lk['final']:.3f}{' (true place)' if lk['near'] else ''}"
    name = lk["look"] if isinstance(lk["look"], str) else ",".join(f"{k}={v}" for k, v in lk["look"].items())
    parts = [name]
    for key in ("coarse", "select", "finer", "screen"):
        v = lk.get(key)
        if v is None:
            parts.append(f"{key} -")
        elif key in ("coarse", "screen"):
            r, n, vs, v0 = v
            parts.append(f"{key} {'miss' if r is None else r}/{n}" + (f" ({vs:.3f} vs top {v0:.3f})" if r is not None else ""))
        else:
            parts.append(f"{key} {'miss' if v[0] is None else v[0]}/{v[1]}")
    parts.append(f"registered {len(lk['scores'])}, true place {'-' if near is None else f'{near:.3f}'}, "
                 f"best {top:.3f}")
    if lk["scores"] and not np.isnan(lk["scores"][0][4]):
        n2 = max((s[4] for s in lk["scores"] if s[1]), default=None)
        n3 = max((s[5] for s in lk["scores"] if s[1]), default=None)
        parts.append(f"x2 true {'-' if n2 is None else f'{n2:.3f}'} best {np.nanmax([s[4] for s in lk['scores']]):.3f}; "
                     f"x3 true {'-' if n3 is None else f'{n3:.3f}'} best {np.nanmax([s[5] for s in lk['scores']]):.3f}")
    if lk.get("moved"):
        parts.append(f"glyphs moved at the true place: best {max(lk['moved']):.3f}")
    return " | ".join(parts)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=7)
    ap.add_argument("--only-missed", action="store_true", help="details only for marks not found")
    ap.add_argument("--clean", action="store_true", help="the benchmark's false-alarm searches instead")
    ap.add_argument("--formats", default="png,jpeg")
    ap.add_argument("--scales", action="store_true", help="also score every placement reduced 2x and 3x")
    ap.add_argument("--moved", action="store_true", help="also move the glyphs of the true place's placements")
    ap.add_argument("--photos", default="", help="comma-separated photo names to run (default all)")
    args = ap.parse_args(argv)
    from _watermark_unseen import POST, WORDS, available_fonts, draw, photos, post, run_ours
    from bench_watermark import jpeg

    rec = Recorder()
    rec.scales = args.scales
    rec.moved = args.moved
    rec.install()
    if args.clean:
        rng = np.random.default_rng(args.seed + 7)
        for name, img in photos():
            y = post(img, POST[int(rng.integers(len(POST)))])
            text = str(rng.choice(WORDS))
            rec.looks = []
            _, outcome, _ = run_ours(y, text, max_marks=1)
            print(f"CLEAN {name:20s} {text!r:18s} {outcome}")
            for lk in rec.looks:
                print("    " + fmt_look(lk))
        return 0
    fonts = available_fonts()
    rng = np.random.default_rng(args.seed)
    for name, img in photos():
        y_png, clean, M, truth = draw(img, rng, fonts)
        if args.photos and name not in args.photos.split(","):
            continue
        rec.text = truth["text"]
        for fmt in args.formats.split(","):
            y = y_png if fmt == "png" else jpeg(y_png)
            cx, cy, rad, _ = true_place(M)
            rec.truth = (cx, cy, rad)
            rec.looks = []
            _, outcome, _ = run_ours(y, truth["text"])
            print(f"{name:18s} {fmt:4s} {truth['font']:22s} {truth['text']!r:16s} {truth['size']:3d}px "
                  f"sp {truth['spacing']:4.1f} st {truth['stroke']} {truth['post']:8s} a={truth['alpha']:.2f} "
                  f"ang {truth['angle']:5.1f}: {outcome}", flush=True)
            if args.only_missed and outcome != "not found":
                continue
            tsc, (fsc, fname) = oracles(y, truth["text"], M, truth)
            print(f"    oracle: true coverage {tsc:.3f}; default font registered from the true place {fsc:.3f} "
                  f"({fname})")
            for lk in rec.looks:
                print("    " + fmt_look(lk), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
