"""Watermark: is a mark reported removed really gone? The residual-mark verdict with and without the rims
along the mark's contours (``odnn_sep.image.residual_rims``), against an oracle that knows the clean photo.

Marks from the unseen-font generator (``_watermark_unseen.draw``: fonts the tool never tries, or with
``--family dejavu`` the DejaVu faces it does try; letter spacing, faux bold, blur or resampling, PNG and
JPEG q 90). For each mark found, the output of ``unwatermark`` (no ``--font``) is judged:

* oracle (the probe's, ``_watermark_probe.score`` on the mark's box): the mark is still there when the
  output keeps >= 4 grey levels RMS in the true mark's band beyond the JPEG noise floor, with >= 0.25 of the
  mark's own structure;
* the tool's verdict without the rims (``residual.measure(rims=False)``, the version before) and with them;
* the clean photo scored as the output of a perfect removal (it must never be called visible).

With ``--family logo`` the marks are the logos of ``recipes/bench_logo.py`` (one per photo and format,
given with or without their alpha channel, single or tiled) removed with ``--reference``; "before" is the
logo check's edge correlation alone (``logo_residual``: z > 4 against chance).

Usage::

    python recipes/bench_watermark_rims.py --seeds 1 7 --trials 2                  # development
    python recipes/bench_watermark_rims.py --seeds 1 7 --trials 1 --family dejavu  # development
    python recipes/bench_watermark_rims.py --seeds 2026 2027 --trials 1            # evaluation
    python recipes/bench_watermark_rims.py --seeds 7 11 --family logo              # development (logos)
    python recipes/bench_watermark_rims.py --seeds 2026 2027 --family logo         # evaluation (logos)
"""
from __future__ import annotations

import argparse
import importlib.util
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def _oracle(out, y, clean, M, fmt) -> dict:
    """The probe's oracle on crops (float [0, 1]); JPEG: the floor is the clean photo's own JPEG error."""
    import cv2
    from _watermark_probe import _across

    band = cv2.dilate((M > 0.05).astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    o, i, c = out * 255, y * 255, clean * 255
    floor = 0.0
    if fmt == "jpeg":
        from bench_watermark import jpeg

        c8 = np.clip(np.round(c), 0, 255).astype(np.uint8)
        cj = jpeg(c8[:, :, 0] if c8.shape[2] == 1 else c8).astype(np.float64)
        cj = cj[:, :, None] if cj.ndim == 2 else cj
        floor = float(np.sqrt(np.mean((cj - c)[band] ** 2)))
    d_out, d_in = (o - c)[band], (i - c)[band]
    left = float(np.sqrt(max(0.0, np.mean(d_out ** 2) - floor ** 2)))
    n_in = float(np.sum(d_in ** 2))
    proj = abs(float(np.sum(d_out * d_in)) / n_in) if n_in > 0 else 0.0
    e_in = _across(i - c, M)
    edge = max(0.0, _across(o - c, M) / e_in) if e_in > 0 else 0.0
    share = max(proj, edge)
    return {"left": left, "share": share, "there": bool(left >= 4.0 and share >= 0.25)}


def _judged(out, inp, clean, M_true, rendering, fmt, before, reported) -> dict:
    """A found mark's row: the oracle, the verdicts before and after, and the clean photo's rims."""
    from odnn_sep.image.residual_rims import rims_left

    c_share, c_levels, c_vis = rims_left(clean, inp, [rendering])
    return {"found": True, **_oracle(out, inp, clean, M_true, fmt), "before": bool(before),
            "after": bool(reported["visible"]), "rim_left": reported.get("rim_left"),
            "rim_levels": reported.get("rim_levels"), "clean_rim_left": round(c_share, 3),
            "clean_rim_levels": round(c_levels, 2), "clean_visible": c_vis}


def _print_row(r: dict, what: str) -> None:
    print(f"{r['seed']} {r['photo']:20s} {what} oracle {'there' if r['there'] else 'gone ':5s} (left {r['left']:5.1f}, "
          f"share {r['share']:.2f}) | before {'visible' if r['before'] else 'removed'} after "
          f"{'visible' if r['after'] else 'removed'} rims {r['rim_left']} ({r['rim_levels']} levels) | clean photo "
          f"rims {r['clean_rim_left']} ({r['clean_rim_levels']} levels)", flush=True)


def run(seed: int, family: str, trials: int) -> list[dict]:
    """Every found mark of ``seed``: oracle, verdicts without and with the rims, clean photo's rims."""
    import _watermark_unseen as U
    from bench_watermark import jpeg

    import odnn_sep.image.api as api
    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark
    from odnn_sep.image.residual import measure

    if family == "unseen":
        fonts = U.available_fonts()
    else:
        mpl = Path(importlib.util.find_spec("matplotlib").origin).parent / "mpl-data" / "fonts" / "ttf"
        fonts = [(mpl / f, None) for f in ("DejaVuSans.ttf", "DejaVuSans-Bold.ttf", "DejaVuSerif.ttf",
                                          "DejaVuSans-Oblique.ttf")]
    seen: dict = {}
    real_residual = api._residual

    def spy(out, inp, M, prior, b, rs):       # the crops the verdict is made on
        seen.update(out=np.asarray(out, float), inp=np.asarray(inp, float), b=b,
                    covs=[M[b[1]:b[3], b[0]:b[2]]] + ([prior[b[1]:b[3], b[0]:b[2]]] if prior is not None else []))
        return real_residual(out, inp, M, prior, b, rs)

    api._residual = spy
    rows = []
    rng = np.random.default_rng(seed)
    try:
        for name, img in U.photos():
            for k in range(trials):
                y_png, clean, Mt, truth = U.draw(img, rng, fonts)
                for fmt in ("png", "jpeg"):
                    y = y_png if fmt == "png" else jpeg(y_png)
                    try:
                        rep = unwatermark(y, text=truth["text"]).report["residual_mark"]
                    except InputError:
                        rows.append({"seed": seed, "photo": name, "trial": k, "format": fmt, "found": False})
                        continue
                    b = seen["b"]
                    cl = clean[b[1]:b[3], b[0]:b[2]].astype(np.float64) / 255
                    cl = cl[:, :, None] if cl.ndim == 2 else cl
                    out, inp, covs = seen["out"], seen["inp"], seen["covs"]
                    before = measure(out, inp, *covs, random_state=0)["visible"]
                    rows.append({"seed": seed, "photo": name, "trial": k, "format": fmt, "font": truth["font"],
                                 "alpha": round(truth["alpha"], 2), "post": truth["post"],
                                 **_judged(out, inp, cl, Mt[b[1]:b[3], b[0]:b[2]], covs[-1], fmt, before, rep)})
                    _print_row(rows[-1], f"#{k} {fmt:4s} {truth['font'][:22]:22s}")
    finally:
        api._residual = real_residual
    return rows


def run_logo(seed: int) -> list[dict]:
    """Every found logo of ``seed`` (``bench_logo``'s logos and blend, one per photo and format)."""
    import bench_logo as B
    import cv2

    import odnn_sep.image.logo_residual as LR
    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark

    seen: dict = {}
    real_residual = LR.residual_mark

    def spy(y, out, M, L, **kw):               # the crops the verdict is made on
        seen.update(inp=np.asarray(y, float), out=np.asarray(out, float), M=np.asarray(M, float))
        return real_residual(y, out, M, L, **kw)

    LR.residual_mark = spy
    rows = []
    rng = np.random.default_rng(seed)
    try:
        for name, clean in B.photos(False):
            for fmt in ("png", "jpeg"):
                logo = B.make_logo(rng, bool(rng.random() < 0.5))
                given_alpha, tiled = bool(rng.random() < 0.5), bool(rng.random() < 0.3)
                y, A, _, truth = B.blend(clean, logo, rng, tiled)
                if fmt == "jpeg":
                    y = cv2.imdecode(cv2.imencode(".jpg", y, [cv2.IMWRITE_JPEG_QUALITY, 90])[1], cv2.IMREAD_UNCHANGED)
                try:
                    rep = unwatermark(y, reference=logo if given_alpha else B.flatten(logo)).report
                except InputError:
                    rows.append({"seed": seed, "photo": name, "format": fmt, "found": False})
                    continue
                x0, y0, x1, y1 = rep["bbox"]
                rm = rep["residual_mark"]
                cl = clean[y0:y1, x0:x1].astype(np.float64) / 255
                out, inp, M = seen["out"], seen["inp"], seen["M"]
                before = bool(rm["z"] > LR.VISIBLE_SD and rm["score"] - rm["chance"] > LR.VISIBLE_MIN)
                rows.append({"seed": seed, "photo": name, "format": fmt, "font": "logo", "tiled": tiled,
                             **_judged(out, inp, cl, A[y0:y1, x0:x1] / truth["alpha"], M, fmt, before, rm)})
                _print_row(rows[-1], f"{fmt:4s} {'tiled ' if tiled else 'single'}")
    finally:
        LR.residual_mark = real_residual
    return rows


def summary(rows: list[dict]) -> str:
    found = [r for r in rows if r["found"]]
    there = [r for r in found if r["there"]]
    gone = [r for r in found if not r["there"]]
    return "\n".join([
        f"marks drawn {len(rows)}, found {len(found)}; oracle: still there {len(there)}, gone {len(gone)}",
        f"still there but reported removed (dishonest): before {sum(not r['before'] for r in there)}, "
        f"after {sum(not r['after'] for r in there)}",
        f"gone but reported visible (by the oracle): before {sum(r['before'] for r in gone)}, "
        f"after {sum(r['after'] for r in gone)}",
        f"clean photo scored as the output, called visible by the rims: {sum(r['clean_visible'] for r in found)}"
        f"/{len(found)} (largest share {max((r['clean_rim_left'] for r in found), default=float('nan')):.2f})"])


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, nargs="+", default=[1, 7])
    ap.add_argument("--trials", type=int, default=2, help="marks per photo (default 2)")
    ap.add_argument("--family", choices=("unseen", "dejavu", "logo"), default="unseen")
    args = ap.parse_args(argv)
    rows = [r for s in args.seeds for r in (run_logo(s) if args.family == "logo" else run(s, args.family, args.trials))]
    print(summary(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
