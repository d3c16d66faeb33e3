"""Population benchmark of ``bench_audio.py``: odnn-sep against MNE spectrum_fit, pactools and an
iirnotch cascade on the generated cases of ``_audio_cases.py``, plus hum-free recordings.

Per case: SNR gain (10 log10 sum hum^2 / sum (output - host)^2), content damage away from the
lines (error power over host power in the 0.25 Hz bins farther than 2 Hz from every band the true
harmonics sweep through), and the lines odnn-sep removed that are not hum (harmonic numbers absent
from the true hum, further combs and tones, or every line of a wrong family). The anchors are given
the true lines: the true harmonics at the true mean fundamental (they cannot find them).
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time

import _audio_cases as cases
import numpy as np
from scipy import signal

PACTOOLS_MAX_SR = 16000
OURS_KW = {}   # options for odnn-sep (defaults; set only while developing)
ANCHORS = ("MNE spectrum_fit", "pactools dehummer", "iirnotch (Q=30)")


def gain_db(host, hum, out):
    err = np.asarray(out, float) - host
    return float(10 * np.log10(np.sum(hum ** 2) / max(np.sum(err ** 2), 1e-300)))


def damage_db(host, out, sr, truth):
    f, Ph = signal.welch(host, fs=sr, nperseg=4 * sr)
    _, Pe = signal.welch(np.asarray(out, float) - host, fs=sr, nperseg=4 * sr)
    away = f > 20.0
    for k in truth["ks"]:
        away &= (f < k * truth["f0_lo"] - 2.0) | (f > k * truth["f0_hi"] + 2.0)
    return float(10 * np.log10(max(Pe[away].sum(), 1e-300) / max(Ph[away].sum(), 1e-300)))


def false_lines(r, spec, truth) -> list[str]:
    """Lines odnn-sep removed that are not in the true hum."""
    if not r.harmonics and not r.tones and not r.extra_combs:
        return []
    wrong_family = r.nominal_hz is None or abs((r.mains_hz or 0.0) - truth["f0_mean"]) > 0.01 * spec["nominal"]
    out = []
    for nm in r.line_names:
        if nm.startswith("h") and not wrong_family and int(nm[1:]) in truth["ks"]:
            continue
        out.append(nm)
    return out


def run_anchors(y, sr, truth, pactools_out=None):
    from bench_audio import run_iirnotch, run_mne

    lines = [k * truth["f0_mean"] for k in truth["ks"]]
    res = {}
    t0 = time.perf_counter()
    res["MNE spectrum_fit"] = (run_mne(y, sr, lines), time.perf_counter() - t0)
    t0 = time.perf_counter()
    res["iirnotch (Q=30)"] = (run_iirnotch(y, sr, lines), time.perf_counter() - t0)
    if pactools_out is not None:
        res["pactools dehummer"] = pactools_out
    return res


def run_pactools_batch(items):
    """dehummer on every (y, sr, f0, hmax) in one torch-free subprocess: [(output, seconds)]."""
    with tempfile.TemporaryDirectory() as d:
        for i, (y, sr, f0, hmax) in enumerate(items):
            np.savez(f"{d}/in{i}.npz", y=y, sr=sr, f0=f0, hmax=hmax)
        code = ("import numpy as np, time, sys; from pactools.utils.dehummer import dehummer\n"
                f"for i in range({len(items)}):\n"
                f"    a = np.load('{d}/in%d.npz' % i); t = time.perf_counter()\n"
                "    y = dehummer(a['y'], int(a['sr']), enf=float(a['f0']), hmax=int(a['hmax']), progress_bar=False)\n"
                f"    np.savez('{d}/out%d.npz' % i, y=y[: len(a['y'])], t=time.perf_counter() - t)\n")
        subprocess.run([sys.executable, "-c", code], check=True, capture_output=True,
                       env={**os.environ, "OMP_NUM_THREADS": "1"})
        out = []
        for i in range(len(items)):
            b = np.load(f"{d}/out{i}.npz")
            out.append((b["y"], float(b["t"])))
    return out


def run_population(n_cases: int, seed0: int, *, quick: bool, anchors: bool = True, log=print):
    """Returns (rows, per-method lists of gains/damages, odnn-sep false-line counts on tonal hosts)."""
    from odnn_sep.audio import denoise

    specs = [cases.case_spec(i, seed0, quick=quick) for i in range(n_cases)]
    made = [cases.make_case(s) for s in specs]
    pact = [None] * n_cases
    if anchors and not quick:
        # pactools takes 40-80 s per case at 44.1/48 kHz on this machine: run at <= 16 kHz only
        sel = [i for i, (_, sr, _) in enumerate(made) if sr <= PACTOOLS_MAX_SR]
        got = run_pactools_batch([(made[i][0], made[i][1], made[i][2]["f0_mean"], made[i][2]["kmax"]) for i in sel])
        for i, g in zip(sel, got, strict=True):
            pact[i] = g
    rows, stats = [], {}
    for spec, (y, sr, truth), pa in zip(specs, made, pact, strict=True):
        t0 = time.perf_counter()
        r = denoise(y, sr, **OURS_KW)
        t_ours = time.perf_counter() - t0
        outs = {"odnn-sep": (r.y, t_ours)}
        if anchors:
            outs.update(run_anchors(y, sr, truth, pa))
        fl = false_lines(r, spec, truth)
        desc = (f"{spec['host']}, {spec['nominal']:g} Hz{' clock %+.2f%%' % (100 * spec['clock']) if spec['clock'] else ''}, "
                f"{truth['drift_desc']}, {spec['shape']} h1-{truth['kmax']}, {sr / 1000:g} kHz, "
                f"{spec['dur']:.0f} s, SNR {spec['snr_db']:+.1f} dB")
        g = {m: gain_db(truth["host"], truth["hum"], o) for m, (o, _) in outs.items()}
        dmg = {m: damage_db(truth["host"], o, sr, truth) for m, (o, _) in outs.items()}
        for m in outs:
            stats.setdefault(m, {"gain": [], "damage": [], "time": []})
            stats[m]["gain"].append(g[m])
            stats[m]["damage"].append(dmg[m])
            stats[m]["time"].append(outs[m][1])
        stats.setdefault("false_tonal", []).append(len(fl) if spec["host"] == "tonal" else 0)
        stats.setdefault("false_all", []).append(len(fl))
        stats.setdefault("ahead", []).append(all(g["odnn-sep"] > g[m] for m in outs if m != "odnn-sep"))
        row = [spec["seed"], desc] + [f"{g[m]:.1f} / {dmg[m]:.0f}" if m in g else "not run"
                                      for m in ("odnn-sep",) + ANCHORS]
        row += [", ".join(fl) if fl else "0", f"{t_ours:.2f}"]
        rows.append(row)
        log(" | ".join(str(v) for v in row))
    return rows, stats


def run_clean(quick: bool, log=print):
    """Hum-free recordings through denoise: output-minus-input energy (dB) and whether hum was found."""
    from odnn_sep.audio import denoise

    rows, worst = [], -np.inf
    for name, y, sr in cases.clean_hosts(quick):
        r = denoise(y, sr)
        d = np.sum((r.y - y) ** 2)
        ref = max(np.sum(y ** 2), 1e-300)
        db = 10 * np.log10(d / ref) if d > 0 else -np.inf
        worst = max(worst, db)
        found = "no hum found" if not r.line_names else f"removed {', '.join(r.line_names)}"
        rows.append([name, "identical" if d == 0 else f"{db:.1f}", found])
        log(" | ".join(rows[-1]))
    return rows, worst


def summary_rows(stats):
    out = []
    for m in ("odnn-sep",) + ANCHORS:
        if m not in stats:
            continue
        g, d = np.array(stats[m]["gain"]), np.array(stats[m]["damage"])
        out.append([m, f"{np.median(g):.1f}", f"{g.min():.1f}", f"{np.median(d):.0f}", f"{d.max():.0f}",
                    f"{np.median(stats[m]['time']):.2f}"])
    return out
