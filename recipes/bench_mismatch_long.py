"""Cost and consistency of `odnn-sep mismatch` on long records (time vs length, verdicts, coverage).

Each case runs in its own process under a time limit, so a checkout on which a long record runs
away is measured too (`--src` points the cases at another checkout, e.g. the code before a change):

    python recipes/bench_mismatch_long.py --timing                      # time vs length
    python recipes/bench_mismatch_long.py --timing --src /path/to/old   # the same, another checkout
    python recipes/bench_mismatch_long.py --consistency --seeds 100-104 # natural length vs 20 000 points
    python recipes/bench_mismatch_long.py --coverage --seeds 110-129    # nulls at 20 000 points only

`--timing` analyses each system (null record) at its natural length and at 2 000, 5 000, 20 000 and
100 000 samples over the same span (CPU seconds, ODE right-hand-side calls, samples fitted, verdict).
`--consistency` analyses each system with and without its effect at its natural length and at
20 000 samples, and reports whether the verdicts agree and how often the 95 % intervals of the base
parameters cover the truth. `--coverage` analyses null records of 20 000 samples only (more seeds
for the same money) and reports the coverage and false physics per system.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from _mismatch_long_cases import SYSTEMS  # noqa: E402

LENGTHS = (2000, 5000, 20000, 100000)


def run(system, n, seed, effect, src, timeout):
    """One case in a child process; its JSON dict, or a dict saying it ran out of time / failed."""
    env = dict(os.environ)
    if src:
        env["PYTHONPATH"] = src
    cmd = [sys.executable, str(HERE / "_mismatch_long_cases.py"), system, str(n), str(seed)] + \
        (["effect"] if effect else [])
    try:
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout, env=env, cwd="/")
    except subprocess.TimeoutExpired:
        return dict(system=system, n=n, seed=seed, effect=effect, status=f"over {timeout} s")
    if out.returncode != 0:
        last = (out.stderr.strip().splitlines() or ["?"])[-1][:120]
        return dict(system=system, n=n, seed=seed, effect=effect, status=f"error: {last}")
    return {**json.loads(out.stdout.strip().splitlines()[-1]), "status": "ok"}


def _verdict(r):
    return "+".join(r["named"]) or "nothing"


def timing(args):
    print("| system | samples | CPU s | wall s | ODE rhs calls | samples fitted | verdict |")
    print("|---|---:|---:|---:|---:|---:|---|")
    for system in args.systems:
        natural = SYSTEMS[system][3]
        for n in (natural,) + LENGTHS:
            r = run(system, n, args.seed, False, args.src, args.timeout)
            if r["status"] != "ok":
                print(f"| {system} | {n} | {r['status']} | | | | |", flush=True)
                continue
            print(f"| {system} | {n} | {r['cpu_s']:.1f} | {r['wall_s']:.1f} | {r['rhs_calls']} | {r['fitted']} | "
                  f"{_verdict(r)} |", flush=True)
            if args.rows:
                with open(args.rows, "a") as fh:
                    fh.write(json.dumps(r) + "\n")


def consistency(args):
    agree, total, cover = 0, 0, {"natural": [], "long": []}
    print("| system | seed | effect | natural: verdict | 20 000: verdict | natural: intervals | 20 000: intervals |")
    print("|---|---:|---|---|---|---|---|")
    for system in args.systems:
        for seed in args.seed_list:
            for effect in (False, True):
                a = run(system, SYSTEMS[system][3], seed, effect, args.src, args.timeout)
                b = run(system, 20000, seed, effect, args.src, args.timeout)
                if a["status"] != "ok" or b["status"] != "ok":
                    print(f"| {system} | {seed} | {effect} | {a['status']} | {b['status']} | | |", flush=True)
                    continue
                total += 1
                agree += _verdict(a) == _verdict(b)
                for key, r in (("natural", a), ("long", b)):
                    if not effect:
                        cover[key] += [c for c in r["covers"].values() if c is not None]

                def iv(r):
                    return "; ".join(f"{k} [{v[0]:.5g}, {v[1]:.5g}]" if v else f"{k} -"
                                     for k, v in r["intervals"].items())
                print(f"| {system} | {seed} | {'yes' if effect else 'no'} | {_verdict(a)} | {_verdict(b)} | {iv(a)} | "
                      f"{iv(b)} |", flush=True)
                if args.rows:
                    with open(args.rows, "a") as fh:
                        fh.write(json.dumps({"natural": a, "long": b}) + "\n")
    print(f"\nverdicts agree: {agree}/{total}")
    for key, c in cover.items():
        if c:
            print(f"95 % intervals of the base parameters covering the truth on nulls ({key}): "
                  f"{sum(c)}/{len(c)} = {100 * sum(c) / len(c):.0f} %")


def coverage(args):
    print("| system | seeds | 95 % intervals covering the truth | false physics | median CPU s | worst CPU s |")
    print("|---|---:|---:|---:|---:|---:|")
    for system in args.systems:
        rows = [run(system, 20000, seed, False, args.src, args.timeout) for seed in args.seed_list]
        ok = [r for r in rows if r["status"] == "ok"]
        c = [v for r in ok for v in r["covers"].values() if v is not None]
        cpu = sorted(r["cpu_s"] for r in ok)
        false = sum(bool(r["named"]) for r in ok)
        cov = f"{sum(c)}/{len(c)} = {100 * sum(c) / max(len(c), 1):.0f} %"
        med = f"{cpu[len(cpu) // 2]:.1f}" if cpu else "-"
        worst = f"{cpu[-1]:.1f}" if cpu else "-"
        print(f"| {system} | {len(ok)}/{len(rows)} | {cov} | {false} | {med} | {worst} |", flush=True)
        if args.rows:
            with open(args.rows, "a") as fh:
                for r in rows:
                    fh.write(json.dumps(r) + "\n")


def _seeds(text):
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def main(argv=None):
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--timing", action="store_true", help="time vs length")
    p.add_argument("--consistency", action="store_true", help="natural length vs 20 000 samples")
    p.add_argument("--coverage", action="store_true", help="nulls of 20 000 samples: coverage and false physics")
    p.add_argument("--systems", default=",".join(SYSTEMS), help="comma-separated, of: " + ", ".join(SYSTEMS))
    p.add_argument("--seed", type=int, default=100, help="seed of the timing records")
    p.add_argument("--seeds", default="100-102", help="seeds of the consistency run (evaluation seeds: 100+)")
    p.add_argument("--src", default=None, help="checkout to import odnn_sep from (PYTHONPATH of every case)")
    p.add_argument("--timeout", type=int, default=300, help="seconds each case may take")
    p.add_argument("--rows", default=None, help="append every case as a JSON line here")
    args = p.parse_args(argv)
    args.systems = [s for s in args.systems.split(",") if s]
    unknown = [s for s in args.systems if s not in SYSTEMS]
    if unknown:
        p.error(f"unknown system(s) {unknown}; known: {', '.join(SYSTEMS)}")
    args.seed_list = _seeds(args.seeds)
    if not (args.timing or args.consistency or args.coverage):
        p.error("give --timing, --consistency and/or --coverage")
    if args.timing:
        timing(args)
    if args.consistency:
        consistency(args)
    if args.coverage:
        coverage(args)


if __name__ == "__main__":
    main()
