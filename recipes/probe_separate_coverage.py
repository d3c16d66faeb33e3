"""How often the printed intervals hold the truth where the noise estimate is the weak point.

- ``--phi``: θ of the datasets with a nonlinear φ (biology, oscillator), default sizes, 30 dB: the
  share of 95 % intervals holding the truth, the median and worst |θ̂ − θ| / stderr (0.67 and about 3
  expected) and the median interval width (% of θ);
- ``--cone``: convex/monotone records of 20-400 points: the share of identified sets holding θ, for
  fits that warn that 5 or fewer residual degrees of freedom are left (their noise level then comes
  from the differences between neighbouring points) and for those that do not, and the median width
  of the sets (% of θ).

    python recipes/probe_separate_coverage.py --phi --seeds 1000:1200
    python recipes/probe_separate_coverage.py --cone --seeds 300:330

Run it with another version on ``PYTHONPATH`` to compare (a version without the warning counts every
fit as not warned).
"""
from __future__ import annotations

import argparse
import sys
import warnings

import numpy as np


def phi_rows(seeds):
    from odnn_sep.core import Separator
    from odnn_sep.signals import make_dataset

    rows = []
    for name in ("biology", "oscillator"):
        hits, z, width = {}, {}, {}
        for s in seeds:
            ds = make_dataset(name, random_state=s)
            r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
            for j, k in enumerate(r.names):
                t = ds.theta_true[k]
                hits.setdefault(k, []).append(r.interval[j, 0] <= t <= r.interval[j, 1])
                z.setdefault(k, []).append(abs(r.theta[j] - t) / r.stderr[j])
                width.setdefault(k, []).append((r.interval[j, 1] - r.interval[j, 0]) / abs(t) * 100)
        for k in hits:
            rows.append(f"| {name} | {k} | {sum(hits[k])}/{len(hits[k])} | {np.median(z[k]):.2f} | "
                        f"{np.max(z[k]):.1f} | {np.median(width[k]):.3g} |")
    return "| dataset | θ | interval holds θ | \\|z\\| median | worst | width % |\n|---|---|---|---|---|---|", rows


def cone_rows(seeds):
    from odnn_sep.core import Separator
    from odnn_sep.signals import make_dataset

    rows = []
    for name in ("implicit_convex", "implicit_monotone"):
        for n in (20, 30, 40, 60, 100, 200, 400):
            warned, quiet, widths = [], [], []
            for s in seeds:
                ds = make_dataset(name, n=n, random_state=s)
                with warnings.catch_warnings(record=True) as caught:
                    warnings.simplefilter("always")
                    r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
                held = bool(r.interval[0, 0] <= ds.theta_true["theta"] <= r.interval[0, 1])
                widths.append(float(np.diff(r.interval[0])[0]) / abs(ds.theta_true["theta"]) * 100)
                few = ("too narrow", "kinks or steps", "rounding level")    # the few-degrees-of-freedom warning
                (warned if any(k in str(w.message) for w in caught for k in few) else quiet).append(held)
            show = lambda v: f"{sum(v)}/{len(v)}" if v else "—"  # noqa: E731
            rows.append(f"| {name.split('_')[1]} | {n} | {len(warned)}/{len(seeds)} | {show(warned)} | {show(quiet)} | "
                        f"{sum(warned) + sum(quiet)}/{len(seeds)} | {np.median(widths):.1f} |")
    return ("| class | n | warned | set holds θ: warned | not warned | all | median width % |\n"
            "|---|---|---|---|---|---|---|"), rows


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    what = p.add_mutually_exclusive_group(required=True)
    what.add_argument("--phi", action="store_true")
    what.add_argument("--cone", action="store_true")
    p.add_argument("--seeds", default="1000:1200", help="START:STOP (evaluation seeds)")
    args = p.parse_args(argv)
    try:
        a, b = (int(v) for v in args.seeds.split(":"))
    except ValueError:
        p.error(f"--seeds must be START:STOP; got {args.seeds!r}")
    if not 0 <= a < b:
        p.error(f"--seeds {args.seeds!r} holds no seed")
    warnings.simplefilter("ignore")
    head, rows = (phi_rows if args.phi else cone_rows)(range(a, b))
    print(head)
    print("\n".join(rows))
    return 0


if __name__ == "__main__":
    sys.exit(main())
