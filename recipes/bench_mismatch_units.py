"""The same records with time in s, ms, us, ns and hours (or values times 1e-6, 1e-9): verdicts compared.

For each time-series system of ``bench_mismatch.py`` (its effect at the strength in ``STRENGTH``, and its null twin) one
noisy record is analysed with its time column in each unit. The table gives the verdict per unit and
the largest difference from the record in seconds, after converting back to seconds, of a parameter
and of an interval end, in standard errors of the record in seconds. With ``--values`` the time stays
in seconds and the values are multiplied by 1e-6 and 1e-9 instead (a motion of micrometres or
nanometres given in metres); the mechanical systems only (``VALUE_SYSTEMS``).

    python recipes/bench_mismatch_units.py --quick        # cooling and free fall, nothing written
    python recipes/bench_mismatch_units.py                # every time-series system, writes BENCHMARKS.md
    python recipes/bench_mismatch_units.py --values       # values in other units, writes BENCHMARKS.md
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402

UNITS = {"s": 1.0, "ms": 1e3, "us": 1e6, "ns": 1e9, "h": 1 / 3600}
STRENGTH = {"cooling/radiation": 0.01, "cooling/two_body_heat": 1.0, "freefall/quadratic_drag": 0.02,
            "oscillator/air_drag": 0.05, "oscillator/duffing": 0.2, "pendulum/large_angle": 0.5}
QUICK = ("cooling/radiation", "freefall/quadratic_drag")
SECTION = "mismatch_units"
VALUE_UNITS = {"as given": 1.0, "x 1e-6": 1e-6, "x 1e-9": 1e-9}
VALUE_SYSTEMS = ("freefall/quadratic_drag", "oscillator/air_drag", "oscillator/duffing")
VALUE_SECTION = "mismatch_values"


def _converted(res, factor):
    """Final parameters, intervals and standard errors, each multiplied by ``factor[name]``."""
    f = res.final_fit
    p = {k: float(v) * factor[k] for k, v in f.params.items() if not isinstance(v, str)}
    iv = {k: np.array(v) * factor[k] for k, v in f.intervals().items()}
    se = {k: float(v) * factor[k] for k, v in f.stderr.items()}
    return p, iv, se


def in_given_values(res, family, vscale):
    """Final parameters, intervals and standard errors converted back to the values as given (the
    powers of ``odnn_sep.mismatch.valuescale``; None where this version has no such module)."""
    try:
        from odnn_sep.mismatch.valuescale import value_power
    except ImportError:
        return None
    return _converted(res, {k: vscale ** -value_power(family, k) for k in res.final_fit.params})


def in_seconds(res, family, scale):
    """Final parameters, intervals and standard errors converted to seconds."""
    from odnn_sep.mismatch.timescale import time_power
    return _converted(res, {k: scale ** -time_power(family, k) for k in res.final_fit.params})


def run_case(name, null, seed=3, values=False):
    """One record per unit: [(unit, status, effects, param gap, interval gap, seconds)]."""
    import bench_mismatch as bm

    from odnn_sep.mismatch import explain
    spec = bm.SYSTEMS[name]
    x = bm.coords(spec)
    m = bm.null_model(spec, STRENGTH[name]) if null else bm.truth_model(spec, STRENGTH[name])[0]
    y = m.predict(x) + spec["noise"] * np.random.default_rng(seed).normal(size=len(x))
    fixed = {k: v for k, v in spec["params"].items() if k in ("m", "L")}
    rows, ref = [], None
    for unit, scale in (VALUE_UNITS if values else UNITS).items():
        t0 = time.time()
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            if values:
                res = explain(spec["preset"], x, y * scale, params=fixed)
                conv = in_given_values(res, spec["preset"], scale)
            else:
                res = explain(spec["preset"], x * scale, y, params=fixed)
                conv = in_seconds(res, spec["preset"], scale)
        gap_p = gap_i = 0.0
        if conv is None:
            gap_p = gap_i = float("nan")
        else:
            p, iv, se = conv
        if ref is None:
            ref = conv
        elif conv is None or ref is None:
            pass
        elif set(p) != set(ref[0]) or set(iv) != set(ref[1]):
            gap_p = gap_i = float("nan")
        else:
            gap_p = max(abs(p[k] - ref[0][k]) / ref[2][k] for k in ref[2])
            gap_i = max(float(np.max(np.abs(iv[k] - ref[1][k]))) / ref[2][k] for k in ref[1])
        rows.append((unit, res.as_dict()["verdict"]["status"], "+".join(res.effects) or "-", gap_p, gap_i,
                     time.time() - t0))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="cooling and free fall only; nothing written")
    ap.add_argument("--systems", help="comma-separated subset of systems")
    ap.add_argument("--values", action="store_true", help="values times 1e-6 and 1e-9 instead of other time units")
    ap.add_argument("--no-write", action="store_true")
    args = ap.parse_args(argv)
    from _bench_md import md_table
    default = VALUE_SYSTEMS if args.values else list(STRENGTH)
    names = QUICK if args.quick else (args.systems.split(",") if args.systems else default)
    first = "as given" if args.values else "s"
    table, same = [], True
    for name in names:
        for null in (False, True):
            rows = run_case(name, null, values=args.values)
            verdicts = {(r[1], r[2]) for r in rows}
            same &= len(verdicts) == 1
            for unit, status, eff, gp, gi, sec in rows:
                table.append([name, "null" if null else "effect", unit, status, eff,
                              "-" if unit == first else f"{gp:.1e}", "-" if unit == first else f"{gi:.1e}",
                              f"{sec:.1f}"])
                print(" | ".join(table[-1]), file=sys.stderr, flush=True)
    body = md_table(["system", "record", "values" if args.values else "time unit", "status", "named",
                     "max param gap (SE)", "max interval-end gap (SE)", "seconds"], table)
    summary = f"same verdict in every unit: {'yes' if same else 'NO'}" + (
        "; gaps after converting back to the values as given" if args.values else "")
    print(body)
    print(summary)
    if not (args.quick or args.no_write):
        from _bench_md import write_section
        cmd = "python recipes/bench_mismatch_units.py" + (" --values" if args.values else "") \
            + (f" --systems {args.systems}" if args.systems else "")
        title = "Mismatch finder: the value unit of the record" if args.values else \
            "Mismatch finder: the time unit of the record"
        write_section(VALUE_SECTION if args.values else SECTION, title, cmd,
                      f"{__doc__.split(chr(10) + chr(10))[1]}\n\n{body}\n\n{summary}.\n")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
