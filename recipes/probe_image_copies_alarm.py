"""False "copies left" on photos with one text mark: how often the search for copies of the mark in
the output (``residual_copies.copies_left``) reports a copy where there is none.

For each photo of the unseen-font generator (``_watermark_unseen.photos``), ``--trials`` single marks
drawn as ``bench_watermark.py`` draws them (DejaVu family, random text, size, angle, position, opacity
and colour). The command's API runs on the PNG with the font given and without it, and on a JPEG
(q 90) with the font given. Counted: outcome (removed / still visible / not found), and the runs whose
report holds ``copies_left``: every one is a false alarm, as the photo holds one copy only.

    python recipes/probe_image_copies_alarm.py --seed 1      # development
    python recipes/probe_image_copies_alarm.py --seed 2      # evaluation, run once
    PYTHONPATH=<checkout> python recipes/probe_image_copies_alarm.py --seed 2   # the version before
"""
from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))


def main(argv=None) -> int:
    from _watermark_unseen import photos
    from bench_watermark import draw_trial, jpeg

    from odnn_sep.errors import InputError
    from odnn_sep.image import unwatermark

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--trials", type=int, default=2, help="marks per photo (default 2)")
    a = ap.parse_args(argv)
    rng = np.random.default_rng(a.seed)
    tally: dict = {}
    alarms = []
    print("photo | text | run | outcome | copies_left | seconds")
    for name, img in photos():
        img = img if img.ndim == 3 else np.repeat(img[:, :, None], 3, axis=2)
        for _ in range(a.trials):
            y, _M, t = draw_trial(img, rng)
            for run, data, font in (("png, font given", y, t["font"]), ("png, no font", y, None),
                                    ("jpeg q90, font given", jpeg(y), t["font"])):
                t0 = time.perf_counter()
                try:
                    rm = unwatermark(data, text=t["text"], font=font).report["residual_mark"]
                    outcome = "still visible" if rm["visible"] else "removed"
                    left = rm.get("copies_left")
                except InputError:
                    outcome, left = "not found", None
                tally[outcome] = tally.get(outcome, 0) + 1
                if left is not None:
                    alarms.append((name, t["text"], run, left))
                n = "-" if left is None else f"{left.get('count', 1)} at {left['at']} (score {left['score']})"
                print(f"{name} | {t['text']} | {run} | {outcome} | {n} | {time.perf_counter() - t0:.1f}", flush=True)
    runs = sum(tally.values())
    print(f"runs {runs}: " + ", ".join(f"{k} {v}" for k, v in sorted(tally.items())))
    print(f"false copies left: {len(alarms)} of {runs} runs")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
