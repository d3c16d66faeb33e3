"""CPU cost of `odnn-sep mismatch` on ODE records, where it goes, and whether two checkouts agree exactly.

    python recipes/probe_mismatch_speed.py                              # this checkout
    python recipes/probe_mismatch_speed.py --src /path/to/other/checkout # another one (before a change)
    python recipes/probe_mismatch_speed.py --attribute --cases duffing   # CPU per purpose of the integrations

Cases: `duffing` (an oscillator with a cubic stiffness, 2 000 samples), `pendulum` (a pendulum swinging
at 0.3 rad, 2 000 samples, fitted as a small-angle one), `phone60` (the 60-degree phone pendulum of
/work/shared/data, 20 s from 5 s, as in `bench_mismatch.py`'s real recordings), `duffing20k` (the
oscillator at 20 000 samples, fitted on a subsample). Each case runs in its own process; its CPU
seconds (the machine is shared: wall time is noise) and a digest of its whole report are printed, so
two checkouts that give the same digest gave the same report, number for number. `--attribute`
wraps the ODE integrator and sums the CPU time of the integrations by what asked for them (the
effect refits of the forward selection, their Jacobians, the held-out refits, the profiles of
parameters that may not be identifiable, ...).
"""
from __future__ import annotations

import argparse
import collections
import hashlib
import json
import os
import subprocess
import sys
import time
import warnings
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
DATA = Path(os.environ.get("ODNN_SEP_DATA", "/work/shared/data"))
CASES = ("duffing", "pendulum", "phone60", "duffing20k")
# what asked for an integration: the innermost of these functions on the stack
PURPOSES = ("confirmed_groups", "_drop_check", "recheck_rivals", "_additive_alternative_score",
            "cross_validate", "one_step", "refit_robust", "calibrate", "explain")


def record(name):
    """(preset, t, y, params) of a case."""
    from odnn_sep.mismatch import make_model

    def synth(preset, params, span, n, noise, effect, seed):
        t = np.linspace(span[0], span[1], n)
        m = make_model(preset, params).with_effect(*effect)
        return preset, t, m.predict(t) + noise * np.random.default_rng(seed).normal(size=n), {}
    osc = {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}
    if name == "duffing":
        return synth("oscillator", osc, (0, 20), 2000, 0.01, ("cubic_stiffness", {"beta": 0.02}), 100)
    if name == "duffing20k":
        return synth("oscillator", osc, (0, 20), 20000, 0.01, ("cubic_stiffness", {"beta": 0.02}), 101)
    if name == "pendulum":
        return synth("pendulum", {"w2": 9.81, "c": 0.05, "theta0": 0.3, "omega0": 0.0}, (0, 15), 2000, 0.002,
                     ("large_angle", {"s_angle": 1.0}), 100)
    if name == "phone60":
        from odnn_sep.mismatch.io import load_data
        t, y, _ = load_data(DATA / "phone_pendulum_phyphox/l2LongTheta60.csv", column="1", start=5, duration=20)
        return "pendulum", t, y, {"L": 0.258}
    raise SystemExit(f"unknown case {name!r}; known: {', '.join(CASES)}")


def _exact(o):
    """The report with every float written exactly (hex), for the digest."""
    if isinstance(o, dict):
        return {str(k): _exact(v) for k, v in o.items()}
    if isinstance(o, (list, tuple)):
        return [_exact(v) for v in o]
    if isinstance(o, np.ndarray):
        return _exact(o.tolist())
    if isinstance(o, (float, np.floating)):
        return float(o).hex()
    if isinstance(o, np.integer):
        return int(o)
    return o


def _attribute():
    """Wrap the ODE integrator; return the table it fills: (purpose, kind) -> [integrations, CPU s, rhs calls]."""
    import odnn_sep.mismatch  # noqa: F401  (loads every module that imported the integrator)
    import odnn_sep.mismatch.presets_base as pb
    table = collections.defaultdict(lambda: [0, 0.0, 0])
    original = pb.integrate_ode

    def wrapped(name, rhs, state0, t, p):
        f, names, effect = sys._getframe(1), [], ""
        while f is not None:
            names.append(f.f_code.co_name)
            if f.f_code.co_name == "refit_robust" and not effect:
                effect = f" ({f.f_locals.get('name')})"
            f = f.f_back
        purpose = next((x for x in PURPOSES if x in names), "other")
        purpose += effect if purpose == "refit_robust" else ""
        kind = "Jacobian" if ("jac" in names[:12] or "difference_jacobian" in names) else "evaluation"
        calls = [0]

        def counted(tt, st):
            calls[0] += 1
            return rhs(tt, st)
        c0 = time.process_time()
        try:
            return original(name, counted, state0, t, p)
        finally:
            row = table[(purpose, kind)]
            row[0] += 1
            row[1] += time.process_time() - c0
            row[2] += calls[0]
    for mod in list(sys.modules.values()):
        if getattr(mod, "__name__", "").startswith("odnn_sep.mismatch") and \
                getattr(mod, "integrate_ode", None) is original:
            mod.integrate_ode = wrapped
    return table


def run_case(name, attribute=False):
    """Analyse one case here; a dict of its cost, verdict and report digest."""
    from odnn_sep.mismatch import explain
    table = _attribute() if attribute else None
    preset, t, y, params = record(name)
    c0, w0 = time.process_time(), time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain(preset, t, y, params=params)
    out = dict(case=name, cpu_s=round(time.process_time() - c0, 2), wall_s=round(time.time() - w0, 1),
               effects=list(res.effects), disturbances=[d["effect"] for d in res.disturbances],
               digest=hashlib.sha256(json.dumps(_exact(res.as_dict()), sort_keys=True, default=str)
                                     .encode()).hexdigest()[:16])
    if table is not None:
        out["attribution"] = [[p, k, *v] for (p, k), v in sorted(table.items(), key=lambda kv: -kv[1][1])]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", default="duffing,pendulum,phone60", help="comma-separated, of: " + ", ".join(CASES))
    ap.add_argument("--src", default=None, help="checkout to import odnn_sep from (PYTHONPATH of every case)")
    ap.add_argument("--attribute", action="store_true", help="CPU per purpose of the ODE integrations")
    ap.add_argument("--one", default=None, help=argparse.SUPPRESS)   # a child process: one case
    args = ap.parse_args(argv)
    if args.one:
        print(json.dumps(run_case(args.one, args.attribute)))
        return
    env = dict(os.environ)
    if args.src:
        env["PYTHONPATH"] = args.src
    print("| case | CPU s | wall s | named | disturbances | report digest |")
    print("|---|---:|---:|---|---|---|")
    rows = []
    for name in [c for c in args.cases.split(",") if c]:
        cmd = [sys.executable, str(Path(__file__).resolve()), "--one", name] + (["--attribute"] if args.attribute else [])
        done = subprocess.run(cmd, capture_output=True, text=True, env=env, cwd="/")
        if done.returncode != 0:
            print(f"| {name} | error: {(done.stderr.strip().splitlines() or ['?'])[-1][:100]} |||||", flush=True)
            continue
        r = json.loads(done.stdout.strip().splitlines()[-1])
        rows.append(r)
        print(f"| {name} | {r['cpu_s']:.1f} | {r['wall_s']:.1f} | {', '.join(r['effects']) or 'nothing'} | "
              f"{', '.join(r['disturbances']) or '-'} | {r['digest']} |", flush=True)
    for r in rows:
        if "attribution" in r:
            print(f"\n{r['case']}: CPU of the ODE integrations by purpose")
            print("| purpose | kind | integrations | CPU s | right-hand-side calls |")
            print("|---|---|---:|---:|---:|")
            for purpose, kind, n, cpu, calls in r["attribution"]:
                print(f"| {purpose} | {kind} | {n} | {cpu:.1f} | {calls} |")


if __name__ == "__main__":
    main()
