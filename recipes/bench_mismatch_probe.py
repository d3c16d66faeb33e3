"""Probe of the mismatch finder on records unlike the main benchmark's, run through the CLI.

Its own generator, independent of the presets: closed forms and SciPy integration of the physics
(Newton cooling with Stefan-Boltzmann radiation or a second body, free fall with air drag, an
oscillator with cubic stiffness, a pendulum with the full sine), with parameter ranges, sampling and
units the main benchmark does not use: cooling constants 0.001-0.05 /s, ambient -10 to 40 degC,
records in K or degF, 30-5000 points, irregular sampling, positions in mm, angles in degrees. Every
case has a null twin (the same noise and disturbance, no effect). Disturbance kinds:

- ``pickup_near``: a pickup near (8-30 % off) the system's frequency; for cooling and free fall,
  0.7-3 cycles over the record (the decay's own time scale);
- ``pickup_harmonic``: near (5-20 % off) twice or three times the system's frequency; 5-30 cycles for
  cooling and free fall;
- ``two_pickups``: one of each at once;
- ``pickup_drift``: a pickup plus a slow linear drift (2-6 noise levels over the record);
- ``step``: a step offset (2-6 noise levels) somewhere in the middle 40 % of the record;
- ``student_t``: heavy-tailed noise (Student t, 2-3 degrees of freedom);
- ``ar1``: AR(1) noise with phi 0.85-0.95;
- ``adc``: a low-resolution ADC (8-10 bits over the record's range);
- ``clip``: the sensor saturates: 3-10 % of the record clipped at a rail.

Each record is written to a CSV in a temporary folder and analysed as a user would:
``odnn-sep mismatch FILE --model PRESET [--units U] --quiet --report R.json``. A case counts as
"strong" when its effect, left out of a recalibrated base model, leaves a residual RMS ratio >= 1.5
(noise-free effect record, base model refitted in process). Null twins count false physics (any
effect named in ``verdict.effects``); effect cases count the true effect named (alone, or among
others); every run counts crashes (a traceback, or a non-zero exit) and unclear errors (an error
message longer than one line).

    python recipes/bench_mismatch_probe.py --dev --seeds 1              # development seeds (0+)
    python recipes/bench_mismatch_probe.py --seeds 1                    # evaluation seeds (100+), writes
                                                                        # its BENCHMARKS.md section
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

SECTION = "mismatch_probe"
KINDS = ("pickup_near", "pickup_harmonic", "two_pickups", "pickup_drift", "step", "student_t", "ar1",
         "adc", "clip")
PRESETS = ("cooling", "freefall", "oscillator", "pendulum")
EFFECTS = {"cooling": ("radiation", "two_body_heat"), "freefall": ("quadratic_drag",),
           "oscillator": ("cubic_stiffness",), "pendulum": ("large_angle",)}
STRONG = 1.5


# --------------------------------------------------------------------------------------------------
# the physics (independent of the presets)
def _times(rng, n, T, irregular):
    if irregular:
        t = np.sort(rng.uniform(0.0, T, n))
        t[0], t[-1] = 0.0, T
        t = np.unique(t)
        return t
    return np.linspace(0.0, T, n)


def _ode(rhs, y0, t):
    sol = solve_ivp(rhs, (t[0], t[-1]), y0, t_eval=t, rtol=1e-10, atol=1e-12, method="DOP853")
    return sol.y


def system(preset, rng, ode_small):
    """Draw one system: (t, clean null record, clean effect record, effect name, unit, CLI extra args,
    system frequency in Hz or None, noise level)."""
    irregular = rng.random() < 0.3
    if preset == "cooling":
        h = float(np.exp(rng.uniform(np.log(0.001), np.log(0.05))))
        T = rng.uniform(1.0, 5.0) / h
        n = int(np.exp(rng.uniform(np.log(30), np.log(5000))))
        t = _times(rng, n, T, irregular)
        ta = rng.uniform(-10, 40)
        t0 = ta + rng.uniform(15, 90)
        null = ta + (t0 - ta) * np.exp(-h * t)
        effect = EFFECTS["cooling"][rng.integers(2)]
        if effect == "radiation":
            tak = ta + 273.15
            r = rng.uniform(0.4, 1.5) * h   # Stefan-Boltzmann, its linearised rate a fraction of h

            def rhs(_, y):
                return [-h * (y[0] - ta) - r * ((y[0] + 273.15) ** 4 - tak ** 4) / (4 * tak ** 3)]
            eff = _ode(rhs, [t0], t)[0]
        else:
            lam = rng.uniform(3, 10) * h
            B = rng.uniform(0.05, 0.2) * (t0 - ta)
            eff = ta + (t0 - ta - B) * np.exp(-h * t) + B * np.exp(-lam * t)
        sigma = rng.uniform(0.02, 0.3)
        unit = ("degC", "K", "degF")[rng.integers(3)]
        if unit == "K":
            null, eff = null + 273.15, eff + 273.15
        elif unit == "degF":
            null, eff, sigma = null * 1.8 + 32, eff * 1.8 + 32, sigma * 1.8
        return t, null, eff, effect, unit, ["--units", unit], None, sigma
    if preset == "freefall":
        g = 9.81
        h0 = rng.uniform(0.5, 20.0)
        T = np.sqrt(2 * h0 / g) * rng.uniform(0.6, 0.95)
        n = int(np.exp(rng.uniform(np.log(30), np.log(2000))))
        t = _times(rng, n, T, irregular)
        null = h0 - 0.5 * g * t ** 2
        vmax = g * T
        vt = vmax * rng.uniform(1.2, 2.5)        # terminal speed, a few times the largest speed reached
        q = g / vt ** 2

        def rhs(_, y):
            return [y[1], -g + q * y[1] ** 2]
        eff = _ode(rhs, [h0, 0.0], t)[0]
        sigma = rng.uniform(0.0005, 0.005) * h0
        unit = ("m", "mm")[rng.integers(2)]
        if unit == "mm":
            null, eff, sigma = null * 1000, eff * 1000, sigma * 1000
        return t, null, eff, "quadratic_drag", unit, [], None, sigma
    if preset == "oscillator":
        f = rng.uniform(0.2, 5.0)
        k = (2 * np.pi * f) ** 2
        c = rng.uniform(0.0, 0.05) * 2 * np.sqrt(k)
        cycles = rng.uniform(5, 20)
        T = cycles / f
        per = rng.uniform(10, 30)
        n = int(min(max(cycles * per, 30), 400 if ode_small else 1500))
        t = _times(rng, n, T, irregular)
        x0 = rng.uniform(0.005, 0.5)
        beta = rng.uniform(0.08, 0.25) * k / x0 ** 2

        def lin(_, y):
            return [y[1], -k * y[0] - c * y[1]]

        def duff(_, y):
            return [y[1], -k * y[0] - c * y[1] - beta * y[0] ** 3]
        null, eff = _ode(lin, [x0, 0.0], t)[0], _ode(duff, [x0, 0.0], t)[0]
        sigma = rng.uniform(0.005, 0.03) * x0
        unit = ("m", "mm")[rng.integers(2)]
        if unit == "mm":
            null, eff, sigma = null * 1000, eff * 1000, sigma * 1000
        return t, null, eff, "cubic_stiffness", unit, [], f, sigma
    if preset == "pendulum":
        L = rng.uniform(0.1, 3.0)
        w2 = 9.81 / L
        f = np.sqrt(w2) / (2 * np.pi)
        c = rng.uniform(0.0, 0.04) * 2 * np.sqrt(w2)
        cycles = rng.uniform(5, 20)
        T = cycles / f
        n = int(min(max(cycles * rng.uniform(10, 30), 30), 400 if ode_small else 1500))
        t = _times(rng, n, T, irregular)
        th0 = rng.uniform(0.6, 1.2)

        def lin(_, y):
            return [y[1], -w2 * y[0] - c * y[1]]

        def full(_, y):
            return [y[1], -w2 * np.sin(y[0]) - c * y[1]]
        null, eff = _ode(lin, [th0, 0.0], t)[0], _ode(full, [th0, 0.0], t)[0]
        sigma = rng.uniform(0.002, 0.01)
        unit = "rad"
        return t, null, eff, "large_angle", unit, [], f, sigma
    raise ValueError(preset)


# --------------------------------------------------------------------------------------------------
# disturbances
def _pickup(rng, t, f_sys, near, amp):
    T = t[-1] - t[0]
    if f_sys is None:
        f = (rng.uniform(0.7, 3.0) if near else rng.uniform(5, 30)) / T
    elif near:
        f = f_sys * (1 + rng.choice([-1, 1]) * rng.uniform(0.08, 0.3))
    else:
        f = f_sys * rng.integers(2, 4) * (1 + rng.choice([-1, 1]) * rng.uniform(0.05, 0.2))
    nyq = 0.5 / float(np.median(np.diff(t)))
    f = min(f, 0.8 * nyq)
    return amp * np.cos(2 * np.pi * f * t + rng.uniform(0, 2 * np.pi)), f


def disturb(kind, rng, t, clean_pair, f_sys, sigma):
    """Apply one disturbance kind to both records (null and effect) with the same draws."""
    n = len(t)
    noise = sigma * rng.normal(size=n)
    add = np.zeros(n)
    info = {}
    if kind in ("pickup_near", "pickup_harmonic", "pickup_drift"):
        p, f = _pickup(rng, t, f_sys, kind != "pickup_harmonic", rng.uniform(1.5, 5.0) * sigma)
        add += p
        info["f"] = f
    if kind == "two_pickups":
        p1, f1 = _pickup(rng, t, f_sys, True, rng.uniform(1.5, 5.0) * sigma)
        p2, f2 = _pickup(rng, t, f_sys, False, rng.uniform(1.5, 5.0) * sigma)
        add += p1 + p2
        info["f"] = (f1, f2)
    if kind == "pickup_drift":
        add += rng.choice([-1, 1]) * rng.uniform(2, 6) * sigma * (t - t[0]) / (t[-1] - t[0])
    if kind == "step":
        ts = t[0] + rng.uniform(0.3, 0.7) * (t[-1] - t[0])
        add += rng.choice([-1, 1]) * rng.uniform(2, 6) * sigma * (t >= ts)
    if kind == "student_t":
        df = rng.uniform(2.0, 3.0)
        noise = sigma * rng.standard_t(df, size=n) / np.sqrt(df / (df - 2) if df > 2.05 else 3.0)
        info["df"] = df
    if kind == "ar1":
        phi = rng.uniform(0.85, 0.95)
        e = rng.normal(size=n) * np.sqrt(1 - phi ** 2)
        ar = np.empty(n)
        ar[0] = rng.normal()
        for i in range(1, n):
            ar[i] = phi * ar[i - 1] + e[i]
        noise = sigma * ar
        info["phi"] = phi
    out = []
    bits = int(rng.integers(8, 11))
    frac = rng.uniform(0.03, 0.10)
    top = rng.random() < 0.5
    for clean in clean_pair:
        y = clean + noise + add
        if kind == "adc":
            lo, hi = float(np.min(clean_pair[0])), float(np.max(clean_pair[0]))
            q = (hi - lo) * 1.2 / 2 ** bits
            y = lo - 0.1 * (hi - lo) + q * np.round((y - lo + 0.1 * (hi - lo)) / q)
            info["bits"] = bits
        if kind == "clip":
            rail = np.quantile(clean_pair[0], 1 - frac) if top else np.quantile(clean_pair[0], frac)
            y = np.minimum(y, rail) if top else np.maximum(y, rail)
            info["clip"] = round(frac, 3)
        out.append(y)
    return out, info


# --------------------------------------------------------------------------------------------------
def strength(preset, t, eff, sigma):
    """Residual RMS ratio of the noise-free effect record under the recalibrated base model."""
    from odnn_sep.mismatch import make_model
    from odnn_sep.mismatch.calibrate import calibrate
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        try:
            cal = calibrate(make_model(preset), t, eff)
        except Exception:  # noqa: BLE001
            return float("nan")
    return float(np.sqrt(1 + (cal.fit.rms / sigma) ** 2))


def run_cli(path, preset, extra, timeout):
    rep = path.with_suffix(".json")
    cmd = ["odnn-sep", "mismatch", str(path), "--model", preset, "--quiet", "--report", str(rep), *extra]
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        return {"rc": "timeout", "sec": time.time() - t0}
    out = {"rc": p.returncode, "sec": time.time() - t0, "stderr": p.stderr.strip()[-2000:]}
    if p.returncode == 0 and rep.exists():
        v = json.loads(rep.read_text())["verdict"]
        out["effects"] = [e["effect"] for e in v.get("effects", [])]
        out["equiv"] = sorted({q for e in v.get("effects", []) for q in e.get("equivalent_to", [])})
        out["disturbances"] = [d["effect"] for d in v.get("disturbances", [])]
        out["status"] = v.get("status")
    return out


def cases(seeds, presets, kinds, base):
    for preset in presets:
        for kind in kinds:
            for s in range(seeds):
                yield preset, kind, base + s


def one_case(preset, kind, seed, folder, ode_small, timeout):
    rng = np.random.default_rng([seed, PRESETS.index(preset), KINDS.index(kind), 7])
    t, null, eff, effect, unit, extra, f_sys, sigma = system(preset, rng, ode_small)
    (y_null, y_eff), info = disturb(kind, rng, t, (null, eff), f_sys, sigma)
    # the base models are linear in the record, so the ratio does not depend on the unit
    ratio = strength(preset, t, eff, sigma)
    row = {"preset": preset, "kind": kind, "seed": seed, "effect": effect, "unit": unit, "n": len(t),
           "irregular": bool(np.std(np.diff(t)) > 1e-9 * (t[-1] - t[0])), "ratio": ratio, **info}
    for tag, y in (("null", y_null), ("eff", y_eff)):
        path = Path(folder) / f"{preset}_{kind}_{seed}_{tag}.csv"
        head = {"cooling": "T", "freefall": "h", "oscillator": "x", "pendulum": "theta"}[preset]
        np.savetxt(path, np.column_stack([t, y]), delimiter=",", header=f"t,{head}", comments="", fmt="%.10g")
        row[tag] = run_cli(path, preset, extra, timeout)
    return row


def error_probes(folder):
    """Malformed inputs a user could give; each must end in one clear line (rows: what, rc, lines, message)."""
    f = Path(folder)
    t = np.linspace(0, 100, 50)
    cool = 20 + 50 * np.exp(-0.03 * t)
    files = {
        "no data rows": "t,T\n",
        "a NaN": "t,T\n" + "".join(f"{i},{'nan' if i == 3 else 90 - i}\n" for i in range(30)),
        "time not increasing": "t,T\n" + "".join(f"{i if i != 2 else 0.5},{90 - i}\n" for i in range(30)),
        "duplicate time": "t,T\n" + "".join(f"{max(i, 1)},{90 - i}\n" for i in range(30)),
        "text values": "t,T\n0,abc\n1,def\n",
        "one row": "t,T\n0,90\n",
        "';' separator": "t;T\n" + "".join(f"{a};{b}\n" for a, b in zip(t, cool, strict=True)),
        "constant record": "t,T\n" + "".join(f"{a},20\n" for a in t),
        "16 points": "t,T\n" + "".join(f"{a},{b}\n" for a, b in zip(t[:16], cool[:16], strict=True)),
    }
    runs = [(k, ["--model", "cooling"], v) for k, v in files.items()]
    good = "t,T\n" + "".join(f"{a},{b}\n" for a, b in zip(t, cool, strict=True))
    runs += [("unknown model", ["--model", "coolin"], good), ("unknown column", ["--model", "cooling", "--column", "Z"], good),
             ("--units on an oscillator", ["--model", "oscillator", "--units", "K"], good),
             ("unknown --disturbance", ["--model", "cooling", "--disturbance", "hvac"], good),
             ("--folds 1", ["--model", "cooling", "--folds", "1"], good),
             ("missing --input column", ["--model", "cooling", "--input", "P"], good)]
    rows = []
    for i, (what, args, text) in enumerate(runs):
        path = f / f"err{i}.csv"
        path.write_text(text)
        p = subprocess.run(["odnn-sep", "mismatch", str(path), "--quiet", *args], capture_output=True, text=True,
                           timeout=300)
        msg = [ln for ln in (p.stderr + p.stdout).splitlines() if ln.strip()]
        last = msg[-1].replace(str(path), "FILE")[:160] if msg else ""
        rows.append((what, p.returncode, len(msg), "Traceback" in p.stderr, last))
    missing = subprocess.run(["odnn-sep", "mismatch", str(f / "nope.csv"), "--model", "cooling"],
                             capture_output=True, text=True, timeout=300)
    m = [ln for ln in missing.stderr.splitlines() if ln.strip()]
    last = m[-1].replace(str(f / "nope.csv"), "FILE")[:160] if m else ""
    rows.append(("missing file", missing.returncode, len(m), "Traceback" in missing.stderr, last))
    return rows


def crashed(r):
    """A traceback, a timeout, or an exit code other than 0 (result) and 1-2 (a reported error)."""
    return r["rc"] == "timeout" or "Traceback" in r.get("stderr", "") or r["rc"] not in (0, 1, 2)


def unclear(r):
    """A reported error that takes more than one line."""
    return r["rc"] in (1, 2) and len([ln for ln in r.get("stderr", "").splitlines() if ln.strip()]) > 1


def summarise(rows):
    from _bench_md import md_table
    lines = []
    tab = []
    groups = [(k, [r for r in rows if r["kind"] == k]) for k in KINDS] + [("all", rows)]
    for name, rs in groups:
        if not rs:
            continue
        nulls = [r["null"] for r in rs if r["null"]["rc"] == 0]
        fp = sum(bool(r["effects"]) for r in nulls)
        strong = [r for r in rs if r["ratio"] >= STRONG and r["eff"]["rc"] == 0]
        exact = sum(r["eff"]["effects"] == [r["effect"]] and not r["eff"]["equiv"] for r in strong)
        among = sum(r["effect"] in r["eff"]["effects"] or r["effect"] in r["eff"]["equiv"] for r in strong)
        eqv = sum(bool(r["eff"]["equiv"]) for r in strong)
        cr = sum(crashed(r[t]) for r in rs for t in ("null", "eff"))
        un = sum(unclear(r[t]) for r in rs for t in ("null", "eff"))
        err = sum(r[t]["rc"] != 0 for r in rs for t in ("null", "eff"))
        secs = [r[t]["sec"] for r in rs for t in ("null", "eff")]
        pct = (lambda a, b: f"{100 * a / b:.0f}% ({a}/{b})" if b else "-")
        tab.append([name, len(rs), pct(fp, len(nulls)), pct(exact, len(strong)), pct(among, len(strong)),
                    pct(eqv, len(strong)), err, cr, un, f"{np.median(secs):.1f} / {max(secs):.1f}"])
    per_kind_fp, per_kind_named = [], []
    for name, rs in groups[:-1]:
        nulls = [r["null"] for r in rs if r["null"]["rc"] == 0]
        strong = [r for r in rs if r["ratio"] >= STRONG and r["eff"]["rc"] == 0]
        if nulls:
            per_kind_fp.append((100 * sum(bool(r["effects"]) for r in nulls) / len(nulls), name))
        if strong:
            per_kind_named.append((100 * sum(r["effect"] in r["eff"]["effects"] or r["effect"] in r["eff"]["equiv"]
                                             for r in strong) / len(strong), name))
    if per_kind_fp:
        worst = max(per_kind_fp)
        which = worst[1] if worst[0] > 0 else "every kind"
        lines.append(f"False physics on nulls over the kinds: median {np.median([v for v, _ in per_kind_fp]):.0f} %, "
                     f"worst {worst[0]:.0f} % ({which}); target <= 5 % for every kind.\n")
    if per_kind_named:
        worst = min(per_kind_named)
        lines.append(f"Strong effects (ratio >= {STRONG}) named, alone or among others or as a reported equivalence, "
                     f"over the kinds: median {np.median([v for v, _ in per_kind_named]):.0f} %, worst "
                     f"{worst[0]:.0f} % ({worst[1]}).\n")
    lines.append(md_table(["kind", "cases", "false physics on nulls", "strong effect named exactly",
                           "true effect among named (or equivalent)", "equivalence reported",
                           "runs with an error exit", "crashes", "unclear errors", "s per run median / worst"], tab))
    by_p = []
    for p in PRESETS:
        rs = [r for r in rows if r["preset"] == p]
        if not rs:
            continue
        nulls = [r["null"] for r in rs if r["null"]["rc"] == 0]
        strong = [r for r in rs if r["ratio"] >= STRONG and r["eff"]["rc"] == 0]
        by_p.append([p, len(rs), f"{sum(bool(r['effects']) for r in nulls)}/{len(nulls)}",
                     f"{sum(r['effect'] in r['eff']['effects'] for r in strong)}/{len(strong)}"])
    lines.append(md_table(["preset", "cases", "false physics on nulls", "strong effect named"], by_p))
    fps = [f"{r['preset']}/{r['kind']}/{r['seed']} ({r['unit']}, n={r['n']}): {'+'.join(r['null']['effects'])}"
           for r in rows if r["null"].get("effects")]
    miss = [f"{r['preset']}/{r['kind']}/{r['seed']} ({r['unit']}, n={r['n']}, ratio {r['ratio']:.2f}): "
            f"{r['effect']} -> {'+'.join(r['eff'].get('effects', [])) or r['eff'].get('status', r['eff']['rc'])}"
            for r in rows if r["ratio"] >= STRONG and r["effect"] not in r["eff"].get("effects", [])
            and r["effect"] not in r["eff"].get("equiv", [])]
    errs = [f"{r['preset']}/{r['kind']}/{r['seed']} {t}: rc {r[t]['rc']}: {r[t].get('stderr', '')[-200:]}"
            for r in rows for t in ("null", "eff") if r[t]["rc"] != 0]
    lines.append("False physics on nulls: " + ("; ".join(fps) or "none") + ".\n")
    lines.append("Strong effects not named: " + ("; ".join(miss) or "none") + ".\n")
    lines.append("Error exits: " + ("; ".join(errs) or "none") + ".\n")
    return "\n".join(lines)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=1, help="seeds per preset and kind")
    ap.add_argument("--dev", action="store_true", help="development seeds (0+) instead of evaluation (100+)")
    ap.add_argument("--presets", default=",".join(PRESETS), help="comma-separated presets")
    ap.add_argument("--kinds", default=",".join(KINDS), help="comma-separated disturbance kinds")
    ap.add_argument("--ode-small", action="store_true", help="at most 400 samples for ODE presets")
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per CLI run")
    ap.add_argument("--rows-jsonl", help="append each finished case here (JSON lines)")
    ap.add_argument("--from-jsonl", help="summarise these rows (comma-separated files) instead of running")
    ap.add_argument("--before-jsonl", help="rows of the same cases run with the version before (comma-separated): "
                    "summarised after the tables")
    ap.add_argument("--command", help="the reproducing command recorded in BENCHMARKS.md (default: this run's)")
    ap.add_argument("--errors", action="store_true", help="run the malformed-input checks with --from-jsonl too")
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--note", default="", help="text recorded before the tables")
    args = ap.parse_args(argv)
    sys.path.insert(0, str(Path(__file__).parent))
    rows = []
    if args.from_jsonl:
        for f in args.from_jsonl.split(","):
            rows += [json.loads(ln) for ln in Path(f).read_text().splitlines() if ln.strip()]
    else:
        base = 0 if args.dev else 100
        with tempfile.TemporaryDirectory() as folder:
            for preset, kind, seed in cases(args.seeds, args.presets.split(","), args.kinds.split(","), base):
                row = one_case(preset, kind, seed, folder, args.ode_small, args.timeout)
                rows.append(row)
                print(json.dumps({k: row[k] for k in ("preset", "kind", "seed", "unit", "n", "ratio", "effect")}),
                      "null:", row["null"].get("effects", row["null"]["rc"]), row["null"].get("disturbances"),
                      "eff:", row["eff"].get("effects", row["eff"]["rc"]), row["eff"].get("equiv"),
                      f"{row['null']['sec']:.1f}+{row['eff']['sec']:.1f}s", file=sys.stderr, flush=True)
                if args.rows_jsonl:
                    with open(args.rows_jsonl, "a") as fh:
                        fh.write(json.dumps(row, default=float) + "\n")
    body = summarise(rows)
    if not args.from_jsonl or args.errors:
        from _bench_md import md_table
        with tempfile.TemporaryDirectory() as folder:
            errs = error_probes(folder)
        body += ("\nMalformed inputs (each should end in one clear line, no traceback):\n\n" +
                 md_table(["input", "exit code", "lines of output", "traceback", "last line"],
                          [[w, rc, n, "yes" if tb else "no", msg.replace("|", "/")] for w, rc, n, tb, msg in errs]))
    print(body)
    if args.before_jsonl:
        old = [json.loads(ln) for f in args.before_jsonl.split(",") for ln in Path(f).read_text().splitlines()
               if ln.strip()]
        body += "\n**The version before, on the same cases:**\n\n" + summarise(old)
    if not (args.no_write or args.dev):
        from _bench_md import write_section
        cmd = args.command or f"python recipes/bench_mismatch_probe.py --seeds {args.seeds}"
        if not args.command:
            cmd += "".join(f" --{k} {getattr(args, k)}" for k in ("presets", "kinds")
                           if getattr(args, k) != ap.get_default(k))
            cmd += " --ode-small" if args.ode_small else ""
        doc = __doc__.split("\n\n")
        write_section(SECTION, "Mismatch finder: probe on records unlike the benchmark's (CLI)", cmd,
                      "\n\n".join(doc[:3]) + "\n\n" + (args.note + "\n\n" if args.note else "") + body)
    return 0


if __name__ == "__main__":
    sys.exit(main())
