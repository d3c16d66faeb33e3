"""Probe of ``odnn-sep unwatermark --text`` on marks the other watermark recipes never draw: is the
reported outcome honest, and how good is the output?

See ``_watermark_probe.py`` for the generator (fonts from Pillow, OpenCV's Hershey strokes and, where
installed, a Rust toolchain's documentation faces; 1 character to a sentence, tiled and multi-line
marks, grey, small and upscaled photos, marks cut by the border, opacity 0.1-0.95, JPEG q 70) and for the
oracle (a mark is still there when the output keeps >= 4 grey levels RMS in the mark's band beyond the
format's noise floor, with >= 0.25 of the mark's own structure). Classes per run of the command: removed
(exit 0) with the mark gone, **removed while the mark is still there (dishonest)**, still visible (exit 3)
rightly, still visible while the output is clean (over-cautious), not found (exit 1), and on clean photos a
false alarm (exit 0 or 3); a crash is any other exit code or a traceback. PSNR "in the band": over the
true mark's pixels grown by 2 px, against the clean photo (JPEG cases: against the photo before JPEG).

    python recipes/bench_watermark_probe.py --seeds 11 12 --marked 12 --clean 3 --json probe.json
    python recipes/bench_watermark_probe.py --table "before=probe_before.json" "after=probe.json" --write
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

CLASSES = ("removed-ok", "dishonest", "visible-ok", "over-cautious", "not found", "false alarm", "clean-ok", "crash")


def _runs(rows):
    from _watermark_probe import classify

    for r in rows:
        for lr in r["lines_run"]:
            yield r, lr, classify(lr, r["layout"] != "clean")


def counts(rows) -> dict:
    """Outcome classes over every run of the command in ``rows``."""
    out = dict.fromkeys(CLASSES, 0)
    for _, _, c in _runs(rows):
        out[c] += 1
    return out


def stats(rows) -> dict:
    """Median and worst band / image PSNR of the runs with an output on marked cases, ours and Telea."""
    ours = [(lr["out"]["psnr_band"], lr["out"]["psnr"], lr["telea"]["psnr_band"], lr["inp"]["psnr_band"])
            for r, lr, c in _runs(rows) if "telea" in lr]
    if not ours:
        return {}
    a = np.array(ours)
    return dict(n=len(a), band_med=np.median(a[:, 0]), band_min=a[:, 0].min(), img_med=np.median(a[:, 1]),
                img_min=a[:, 1].min(), telea_med=np.median(a[:, 2]), in_med=np.median(a[:, 3]),
                ge40=int(np.sum(a[:, 1] >= 40)), beat_telea=int(np.sum(a[:, 0] >= a[:, 2])))


def table(labelled: list[tuple[str, list]]) -> str:
    """Markdown: one row of counts and PSNR per labelled population."""
    from _bench_md import md_table

    rows = []
    for lab, rs in labelled:
        c, s = counts(rs), stats(rs)
        rows.append([lab, sum(c.values()), c["removed-ok"], f"**{c['dishonest']}**", c["visible-ok"],
                     c["over-cautious"], c["not found"], f"{c['false alarm']}/{c['false alarm'] + c['clean-ok']}",
                     c["crash"], f"{s.get('in_med', float('nan')):.1f}", f"{s.get('band_med', float('nan')):.1f}",
                     f"{s.get('band_min', float('nan')):.1f}", f"{s.get('telea_med', float('nan')):.1f}",
                     f"{s.get('img_med', float('nan')):.1f} ({s.get('img_min', float('nan')):.1f})",
                     f"{s.get('ge40', 0)}/{s.get('n', 0)}"])
    return md_table(["code, seeds", "runs", "removed (clean)", "removed while still there (dishonest)",
                     "still visible (right)", "still visible (output clean)", "not found", "false alarms",
                     "crashes", "input band PSNR median", "output band PSNR median", "output band PSNR worst",
                     "Telea band PSNR median", "output PSNR median (worst)", "output >= 40 dB"], rows)


def per_case(rows) -> str:
    """Markdown: every run, one row."""
    from _bench_md import md_table

    out = []
    def g(lr, k, key):
        return f"{lr[k][key]:.1f}" if k in lr and key in lr[k] else ""

    for r, lr, c in _runs(rows):
        out.append([f"{r['seed']}/{r['case']}", r["photo"], "x".join(map(str, r["shape"][:2]))
                    + (" grey" if r.get("grey") else ""), r["layout"], r.get("font", ""), repr(lr["text"][:28]),
                    r.get("alpha", ""), r.get("color", ""), r["post"] + (" border" if r.get("near_border") else ""),
                    lr["rc"], c, g(lr, "inp", "psnr_band"), g(lr, "out", "psnr_band"), g(lr, "telea", "psnr_band"),
                    g(lr, "out", "left"), f"{lr['out']['share']:.2f}" if "share" in lr.get("out", {}) else ""])
    return md_table(["case", "photo", "size", "layout", "font", "text", "alpha", "colour", "post", "exit",
                     "class", "input band dB", "output band dB", "Telea band dB", "left (levels)", "share"], out)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--seeds", type=int, nargs="*", default=[11, 12])
    ap.add_argument("--marked", type=int, default=12, help="marked cases per seed")
    ap.add_argument("--clean", type=int, default=3, help="clean-photo cases per seed")
    ap.add_argument("--json", type=Path, help="write the rows here")
    ap.add_argument("--table", nargs="*", help="only tabulate these JSON files, each LABEL=PATH or PATH")
    ap.add_argument("--notes", type=Path, help="text appended to the section (what the numbers show)")
    ap.add_argument("--write", action="store_true", help="write the BENCHMARKS.md section (with --table)")
    ap.add_argument("--keep", type=Path, help="keep the inputs, outputs and reports in this folder")
    args = ap.parse_args()
    if args.table:
        pops = []
        for spec in args.table:
            lab, _, path = str(spec).rpartition("=")
            pops.append((lab or Path(path).stem, json.loads(Path(path).read_text())))
        body = (__doc__.split("\n\n", 1)[1].split("    python")[0].rstrip() + "\n\n" + table(pops)
                + f"\n\nEvery run of the last population ({pops[-1][0]}):\n\n" + per_case(pops[-1][1]) + "\n")
        if args.notes:
            body += "\n" + args.notes.read_text().rstrip() + "\n"
        print(body)
        if args.write:
            from _bench_md import write_section

            cmd = ("python recipes/bench_watermark_probe.py --seeds 11 12 13 --json dev.json; ... --seeds 2026 2027 "
                   "--json eval.json (each with the code before, PYTHONPATH on a checkout of it, and after); then "
                   "python recipes/bench_watermark_probe.py --table LABEL=dev.json LABEL=eval.json ... --notes "
                   "notes.md --write")
            write_section("watermark_probe", "Image: text watermark probe (fonts, layouts and photos the other "
                          "recipes never draw), honest outcome", cmd, body)
        return
    from _watermark_probe import run_population

    rows = []
    with tempfile.TemporaryDirectory() as td:
        work = Path(td) if args.keep is None else args.keep
        work.mkdir(parents=True, exist_ok=True)
        for s in args.seeds:
            rows += run_population(s, args.marked, args.clean, work)
    if args.json:
        args.json.write_text(json.dumps(rows, default=lambda o: o.tolist() if hasattr(o, "tolist") else str(o)))
    print(table([("this run", rows)]))
    print(per_case(rows))


if __name__ == "__main__":
    main()
