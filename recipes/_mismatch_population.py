"""The disturbance-kind population of ``bench_mismatch.py``: one effect, two effects, null twins.

Per case (system, disturbance kind, seed) the same random draws give three recordings: the
system with its effect (strength drawn so that the residual ratio is 1.25-1.8), with its effect
and a second one (each at ratio 1.4-1.9), and the null twin (no effect). The finder sees the
preset name and the data only. Development seeds (0-99) chose methods; reported numbers use
evaluation seeds (100+).
"""
from __future__ import annotations

import functools
import time
import warnings

import numpy as np
from _mismatch_kinds import SECOND, add_disturbance

from odnn_sep.mismatch import explain, make_model
from odnn_sep.mismatch.calibrate import calibrate

STRUCTURAL = ("harmonics", "sources", "t", "m", "L")
BASE_KEYS = ("k", "c", "w2", "h", "T_ambient", "g", "f0", "alpha", "h0")


def _user(spec):
    return {k: v for k, v in spec["params"].items() if k in STRUCTURAL}


@functools.lru_cache(maxsize=None)
def _leftover(name, effect, key, ref, extra_items, theta0):
    """Noise-free RMS left after recalibrating the preset (no effect) to one effect's output."""
    import bench_mismatch as bm
    spec = bm.SYSTEMS[name]
    x = bm.coords(spec)
    params = dict(spec["params"])
    if theta0 is not None:
        params["theta0"] = theta0
    m = make_model(spec["preset"], params).with_effect(effect, {key: ref, **dict(extra_items)})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cal = calibrate(make_model(spec["preset"], _user(spec)), x, m.predict(x))
    return cal.fit.rms


def strength_for(name, spec, effect, key, ref, extra, ratio, theta0=None):
    """Effect strength giving residual ratio ``ratio`` (the leftover is about linear in strength)."""
    if effect == "large_angle":
        # strength = release angle; the leftover grows like theta0^3
        amp = spec.get("amp_ref", ref)
        L = _leftover(name, effect, key, 1.0, (), amp)
        return amp * (np.sqrt(ratio ** 2 - 1) * spec["noise"] / L) ** (1 / 3)
    L = _leftover(name, effect, key, ref, tuple(sorted(extra.items())), theta0)
    return ref * np.sqrt(ratio ** 2 - 1) * spec["noise"] / L


def truth(name, spec, effects, theta0):
    """The true model with ``effects`` = [(effect, key, value, extra)] and its parameters."""
    params = dict(spec["params"])
    if spec["effect"] == "large_angle":
        params["theta0"] = theta0
    m = make_model(spec["preset"], params)
    for eff, key, val, extra in effects:
        if eff == "large_angle":
            m = m.with_effect(eff, {"s_angle": 1.0})
        else:
            m = m.with_effect(eff, {key: val, **extra})
    return m


def _named(res):
    """Named physics effects as [(effect, params, intervals, equivalents)], read off the final fit
    (what the report prints); works with the old single verdict too."""
    named = getattr(res, "named", None)
    if named is not None:
        final = res.final_fit
        iv = final.intervals()
        return [(c.effect, {k: final.params[k] for k in c.effect_params},
                 {k: iv.get(k) for k in c.effect_params}, list(getattr(c, "equivalent", []))) for c in named]
    v = res.verdict
    if v is None:
        return []
    iv = {k: (v.fit.params[k] - 1.96 * s, v.fit.params[k] + 1.96 * s) for k, s in v.fit.stderr.items()}
    return [(v.effect, v.effect_params, iv, [])]


def groups_match(named, equivalences, truth):
    """True when each named effect, widened by its reported equivalents, holds exactly one true effect."""
    groups = [{e} | set(equivalences.get(e, [])) for e in named]
    if not groups:
        return not truth
    return (len(groups) == len(truth) and all(len(g & set(truth)) == 1 for g in groups)
            and set().union(*groups) >= set(truth))


def _equivalences(r):
    """Reported equivalences, without effects that are themselves named (the tool drops those too;
    rows recorded before it did are read the same way)."""
    eq = {k: [e for e in v if e not in r["named"]] for k, v in (r.get("equivalences") or {}).items()}
    return {k: v for k, v in eq.items() if v}


def exact(r):
    """Named exactly the true effects, and no equivalence reported on them."""
    return sorted(r["named"]) == sorted(r["truth"]) and not _equivalences(r)


def equivalence_reported(r):
    """Not exact, but the true effects are named up to a reported equivalence."""
    eq = _equivalences(r)
    return bool(eq) and groups_match(r["named"], eq, r["truth"])


def _final_fit(res):
    f = getattr(res, "final_fit", None)
    if f is not None:
        return f
    return res.calibration.fit if res.verdict is None else res.verdict.fit


def run_population_case(job):
    """job = (system, kind, seed, mode) with mode 'effect', 'pair' or 'null'. Returns a row dict."""
    import bench_mismatch as bm
    name, kind, seed, mode = job
    spec = bm.SYSTEMS[name]
    sys_i = list(bm.SYSTEMS).index(name)
    rng = np.random.default_rng([seed, sys_i, ("slow", "periodic", "coloured", "spikes",
                                               "quantisation").index(kind)])
    r1, r2a, r2b = rng.uniform(1.25, 1.8), rng.uniform(1.4, 1.9), rng.uniform(1.4, 1.9)
    x = bm.coords(spec)
    noise_rng = np.random.default_rng(rng.integers(2 ** 32))
    e1 = (spec["effect"], spec["key"], spec["ref"], spec.get("extra", {}))
    theta0 = None
    if spec["effect"] == "large_angle":
        theta0 = strength_for(name, spec, *e1, r2a if mode == "pair" else r1)
    aux = None
    truth_effects = []
    if mode == "effect" and spec.get("coupling"):
        truth_effects = [(e1[0], e1[1], None, {})]    # kappa is set below from the ratio
    elif mode == "effect":
        truth_effects = [(e1[0], e1[1], strength_for(name, spec, *e1, r1), e1[3])]
    elif mode == "pair":
        e2 = SECOND[name]
        truth_effects = [(e1[0], e1[1], strength_for(name, spec, *e1, r2a), e1[3]),
                         (e2[0], e2[1], strength_for(name, spec, *e2, r2b, theta0=theta0), e2[3])]
    if spec.get("coupling"):
        b = bm.aux_channel(spec, x, noise_rng)
        aux = {"B": b}
        clean = truth(name, spec, [], theta0).predict(x)
        if truth_effects:
            kappa = np.sqrt(r1 ** 2 - 1) * spec["noise"]
            truth_effects = [(e1[0], e1[1], kappa, {})]
            clean = clean + kappa * b
    else:
        clean = truth(name, spec, truth_effects, theta0).predict(x)
    y, dinfo = add_disturbance(kind, spec, x, clean, noise_rng)
    t0 = time.time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain(spec["preset"], x, y, params=_user(spec), aux=aux)
    dt = time.time() - t0
    named = _named(res)
    names = [n for n, _, _, _ in named]
    want = [e for e, _, _, _ in truth_effects]
    row = {"system": name, "kind": kind, "seed": seed, "mode": mode, "truth": want, "named": names,
           "disturbances": [d.get("effect") for d in getattr(res, "disturbances", []) or []],
           "failed": [c.effect for c in getattr(res, "failed", []) or []], "seconds": dt,
           "ratio": None, "errors": [], "covered": [], "base_covered": [], "covered_by": {},
           "equivalences": {n: eq for n, _, _, eq in named if eq},
           "rivals": {c.effect: c.rivals for c in getattr(res, "named", []) if getattr(c, "rivals", None)}}
    base = res.calibration.fit
    if mode == "effect":
        c = next((c for c in res.candidates if c.effect == want[0]), None)
        row["ratio"] = base.rms / c.fit.rms if c is not None else float("nan")
    for eff, key, val, _ in truth_effects:
        hit = next(((p, iv) for n, p, iv, _ in named if n == eff), None)
        if hit is None or eff == "channel_coupling" or key not in hit[0]:
            continue
        true_v = 1.0 if eff == "large_angle" else val
        row["errors"].append(abs(hit[0][key] - true_v) / abs(true_v))
        if key in hit[1] and hit[1][key] is not None:
            lo, hi = hit[1][key]
            row["covered"].append(bool(lo <= true_v <= hi))
            row["covered_by"].setdefault(key, []).append(bool(lo <= true_v <= hi))
    if sorted(names) == sorted(want):
        # the final model is the true one: its base parameters have a known truth too
        f = _final_fit(res)
        iv = f.intervals()
        true_p = dict(spec["params"], **({"theta0": theta0} if theta0 is not None else {}))
        for k in BASE_KEYS:
            if k in iv and isinstance(true_p.get(k), float):
                lo, hi = iv[k]
                row["covered_by"].setdefault(k, []).append(bool(lo <= true_p[k] <= hi))
    if mode == "null" and not names:
        # coverage of the calibrated model's own parameters on nulls (the truth is known there)
        f = _final_fit(res)
        iv = getattr(res, "final_intervals", None) or f.intervals()
        true_p = dict(spec["params"])
        if theta0 is not None:
            true_p["theta0"] = theta0
        for k, v in true_p.items():
            if k in iv and k not in STRUCTURAL and isinstance(v, float) and k in ("k", "c", "w2", "h",
                                                                                   "T_ambient", "g", "f0",
                                                                                   "alpha", "h0"):
                lo, hi = iv[k]
                row["base_covered"].append(bool(lo <= v <= hi))
    return row


def population_jobs(systems, kinds_for, seeds):
    """Jobs: every system x applicable kind x seed x (effect, pair where defined, null)."""
    jobs = []
    for name in systems:
        for kind in kinds_for(name):
            for seed in seeds(name):
                jobs.append((name, kind, seed, "effect"))
                if name in SECOND:
                    jobs.append((name, kind, seed, "pair"))
                jobs.append((name, kind, seed, "null"))
    # the periodic pickup first, then by seed: a run cut short still covers every system
    order = {"periodic": 0, "slow": 1, "coloured": 2, "spikes": 3, "quantisation": 4}
    return sorted(jobs, key=lambda j: (j[2], order[j[1]]))


def _pct(x):
    return "-" if x is None or not np.isfinite(x) else f"{x:.0%}"


def _rate(rows, fn):
    return float(np.mean([fn(r) for r in rows])) if rows else float("nan")


def summarize_population(rows):
    """Tables by disturbance kind and by system, and the overall numbers the issue's targets name."""
    from _bench_md import md_table
    header = ["group", "effect cases (ratio >= 1.2)", "named exactly", "true effect among named",
              "two-effect cases", "both named, nothing else", "equivalence reported (effect / two-effect)",
              "nulls", "false physics on nulls",
              "median / worst param error", "95% interval coverage (effect / base on nulls)", "fits failed",
              "s per case"]

    def line(label, rr):
        eff = [r for r in rr if r["mode"] == "effect" and (r["ratio"] or 0) >= 1.2]
        pair = [r for r in rr if r["mode"] == "pair"]
        nul = [r for r in rr if r["mode"] == "null"]
        errs = [e for r in rr if r["mode"] != "null" for e in r["errors"]]
        cov = [c for r in rr for c in r["covered"]]
        bcov = [c for r in rr for c in r["base_covered"]]
        return [label, str(len(eff)), _pct(_rate(eff, exact)),
                _pct(_rate(eff, lambda r: r["truth"][0] in r["named"])), str(len(pair)),
                _pct(_rate(pair, exact)),
                f"{_pct(_rate(eff, equivalence_reported))} / {_pct(_rate(pair, equivalence_reported))}",
                str(len(nul)),
                _pct(_rate(nul, lambda r: bool(r["named"]))),
                f"{np.median(errs):.1%} / {np.max(errs):.0%}" if errs else "-",
                f"{_pct(np.mean(cov) if cov else None)} (n={len(cov)}) / "
                f"{_pct(np.mean(bcov) if bcov else None)} (n={len(bcov)})",
                str(sum(len(r["failed"]) for r in rr)), f"{np.mean([r['seconds'] for r in rr]):.1f}"]

    kinds = [k for k in ("slow", "periodic", "coloured", "spikes", "quantisation") if any(r["kind"] == k for r in rows)]
    by_kind = [line(k, [r for r in rows if r["kind"] == k]) for k in kinds] + [line("all", rows)]
    systems = sorted({r["system"] for r in rows})
    by_sys = [line(s, [r for r in rows if r["system"] == s]) for s in systems]
    eff = [r for r in rows if r["mode"] == "effect" and (r["ratio"] or 0) >= 1.2]
    overall = {
        "naming_exact_ratio_ge_1.2": _rate(eff, exact),
        "naming_worst_kind": min((_rate([r for r in eff if r["kind"] == k], exact), k)
                                 for k in kinds) if eff else None,
        "both_named_rate": _rate([r for r in rows if r["mode"] == "pair"], exact),
        "equivalence_effect": _rate(eff, equivalence_reported),
        "equivalence_pair": _rate([r for r in rows if r["mode"] == "pair"], equivalence_reported),
        "false_physics_nulls": _rate([r for r in rows if r["mode"] == "null"], lambda r: bool(r["named"])),
        "false_physics_worst_kind": max((_rate([r for r in rows if r["mode"] == "null" and r["kind"] == k],
                                               lambda r: bool(r["named"])), k) for k in kinds),
        "coverage_effect": float(np.mean(c)) if (c := [c for r in rows for c in r["covered"]]) else None,
        "coverage_base_nulls": float(np.mean(c)) if (c := [c for r in rows for c in r["base_covered"]]) else None,
        # the same effect intervals, only where the final model is the true one: a model that leaves
        # out one true effect biases the other's parameter, which no interval of that model can cover
        "coverage_effect_true_model": float(np.mean(c)) if (c := [c for r in rows if r["mode"] != "null"
                                                                  and sorted(r["named"]) == sorted(r["truth"])
                                                                  for c in r["covered"]]) else None,
        "coverage_effect_true_model_n": len([c for r in rows if r["mode"] != "null"
                                             and sorted(r["named"]) == sorted(r["truth"]) for c in r["covered"]]),
        "fits_failed": sum(len(r["failed"]) for r in rows),
    }
    confusions = {}
    for r in rows:
        if not exact(r):   # the order effects were found in is not an error
            eq = _equivalences(r)
            got = "+".join(n + (f" (or {'/'.join(eq[n])})" if n in eq else "") for n in r["named"]) or "none"
            k = f"{r['mode']} {r['kind']}: {'+'.join(r['truth']) or 'none'} -> {got}"
            confusions[k] = confusions.get(k, 0) + 1
    return overall, confusions, md_table(header, by_kind), md_table(header, by_sys), coverage_table(rows)


def coverage_table(rows):
    """95% interval coverage per parameter (effect parameters when named; base parameters when the
    final model is the true one), by disturbance kind."""
    from _bench_md import md_table
    keys = sorted({k for r in rows for k in (r.get("covered_by") or {})})
    kinds = [k for k in ("slow", "periodic", "coloured", "spikes", "quantisation") if any(r["kind"] == k for r in rows)]
    table = []
    for key in keys:
        cells = []
        for kind in kinds + ["all"]:
            c = [v for r in rows if kind in ("all", r["kind"]) for v in (r.get("covered_by") or {}).get(key, [])]
            cells.append(f"{_pct(np.mean(c) if c else None)} (n={len(c)})")
        table.append([key] + cells)
    table.append(["all parameters"] + [
        f"{_pct(np.mean(c) if c else None)} (n={len(c)})" for c in
        [[v for r in rows if kind in ('all', r['kind']) for vs in (r.get('covered_by') or {}).values() for v in vs]
         for kind in kinds + ["all"]]])
    return md_table(["parameter"] + kinds + ["all kinds"], table)
