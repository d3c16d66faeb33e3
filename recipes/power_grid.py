"""Power-grid line parameters and topology from partial measurements (paper 4.3 / C.7, Figure 14).

For each draw: an AC power flow (pandapower) over 15-minute load snapshots, behind-the-meter
generation convex in voltage at half of the loaded buses, metered real power and PMU voltages at a
subset of buses. Every complete bus equation is fitted by ODNN exact (class Convex() in v_i, none
at a bus without customer load: the identified interval of each candidate G_ik, B_ik, per three-day
piece of the record, pieces and line ends combined by inverse variance) and by OLS, SINDy, a regular
DNN (Eq. 2, network input v_i) and a PINN-style penalty on the same columns (whole record).

Reported per case: MAPE on the point-identified coefficients of true lines (every piece's interval
at most twice as wide as the metering noise alone makes it, combined interval narrower than 5 % of
the value) and on all true-line coefficients, how many are point-/set-identified, whether the
topology (every candidate pair: present iff an interval excludes zero, Bonferroni over the
candidates) is exact, median and worst draw.

Run ``python recipes/power_grid.py`` (writes BENCHMARKS.md and docs/power_grid.png) or ``--quick``.
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
TARGET = 0.25  # % (half the paper's 0.49 %)
SNAPSHOTS = 4608  # 48 days of 15-minute snapshots (development draws: 24 days gave 0.28 / 0.32 %, 48 days 0.14 / 0.25 %)
from odnn_sep.batch import positive_int  # noqa: E402
from odnn_sep.signals.grid_flow import CASES  # noqa: E402
from odnn_sep.signals.grid_identify import CHUNK  # noqa: E402  snapshots per separately fitted piece


def _line_mape(estimates: dict, ds) -> float:
    """MAPE (%) over true-line coefficients, the two ends of a line averaged (as ODNN combines them)."""
    by_key = {}
    for (q, i, k), v in estimates.items():
        by_key.setdefault((q, min(i, k), max(i, k)), []).append(v)
    errs = []
    for (q, i, k), vals in by_key.items():
        t = (ds.G if q == "G" else ds.B)[i, k]
        if abs(t) > 0:
            errs.append(abs(np.mean(vals) - t) / abs(t) * 100)
    return float(np.mean(errs))


def baselines(ds, *, epochs: int, seed: int) -> dict:
    """MAPE (%) over true-line coefficients for OLS, SINDy, regular DNN and PINN penalty."""
    from odnn_sep.core.baselines import ols, pinn_penalty, regular_dnn, sindy

    est = {"ols": {}, "sindy": {}, "regular_dnn": {}, "pinn_penalty": {}}
    for pr in ds.problems:
        F = pr.design()
        fits = {"ols": ols(F, pr.y)}
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fits["sindy"] = sindy(F, pr.y)
        if epochs:
            fits["regular_dnn"] = regular_dnn(pr.x, pr.y, F, epochs=epochs, random_state=seed)
            fits["pinn_penalty"] = pinn_penalty(pr.x, pr.y, F, epochs=epochs, random_state=seed)
        for m, theta in fits.items():
            for name, v in zip(pr.basis.names, theta):
                i, k = (int(u) for u in name[2:-1].split(","))
                est[m][(name[0], i, k)] = float(v)
    return {m: (_line_mape(e, ds) if e else float("nan")) for m, e in est.items()}


def run_case(case: str, seeds, *, snapshots: int, snr_db: float, epochs: int, progress=print) -> dict:
    """All methods on ``len(seeds)`` draws of ``case``; per-draw numbers plus the last draw's fit."""
    from odnn_sep.signals import make_dataset
    from odnn_sep.signals.grid_identify import identify_grid

    res = {k: [] for k in ("point", "point_B", "point_G", "all", "topo", "n_point", "n_set", "ols", "sindy",
                           "regular_dnn", "pinn_penalty", "sim_s", "fit_s")}
    last = None
    for s in seeds:
        t0 = time.perf_counter()
        ds = make_dataset("power_grid", case=case, snapshots=snapshots, snr_db=snr_db, random_state=s)
        sim_s = time.perf_counter() - t0
        fit = identify_grid(ds, random_state=s)
        c = fit.counts()
        base = baselines(ds, epochs=epochs, seed=s)
        for k, v in (("point", fit.mape_point()), ("point_B", fit.mape_point("B")), ("point_G", fit.mape_point("G")),
                     ("all", fit.mape_all()), ("topo", fit.topology_exact()),
                     ("n_point", c["point"]), ("n_set", c["set"]), ("sim_s", sim_s), ("fit_s", fit.seconds),
                     *base.items()):
            res[k].append(v)
        progress(f"{case} seed {s}: point {fit.mape_point():.3g} %, all {fit.mape_all():.3g} %, "
                 f"topology errors {fit.topology_errors()}, {c}, OLS {base['ols']:.3g} %")
        last = (ds, fit)
    res["last"] = last
    return res


def med_only(v) -> str:
    """Median of the finite values, or a dash when there are none (no such point-identified coefficient)."""
    v = [x for x in v if np.isfinite(x)]
    return f"{np.median(v):.3g}" if v else "—"


def med_worst(v, worst=max) -> str:
    v = [x for x in v if np.isfinite(x)]
    return f"{np.median(v):.3g} / {worst(v):.3g}" if v else "—"


def figure(ds, fit, path: Path) -> None:
    """True vs estimated G and B among the measured buses (rows: complete bus equations)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from odnn_sep.io_utils import atomic_output

    m = list(ds.measured)
    idx = {b: j for j, b in enumerate(m)}
    rows = list(ds.rows)
    mats = {}
    for lab, M in (("G", ds.G), ("B", ds.B)):
        true = np.full((len(rows), len(m)), np.nan)
        est = np.full_like(true, np.nan)
        for r, i in enumerate(rows):
            for k in m:
                if k != i:
                    true[r, idx[k]] = M[i, k]
        for name, i, k, _t, e, lo, hi, _p, _pt in fit.per_row:
            if name[0] == lab:
                est[rows.index(i), idx[k]] = 0.0 if lo <= 0 <= hi else e
        mats[lab] = (true, est)
    fig, axes = plt.subplots(2, 2, figsize=(8.5, 5.2), constrained_layout=True)
    for c, lab in enumerate(("G", "B")):
        true, est = mats[lab]
        lim = np.nanmax(np.abs(true))
        for r, (title, A) in enumerate((("true", true), ("estimated (0 where the interval holds 0)", est))):
            ax = axes[r, c]
            im = ax.imshow(A, cmap="RdBu_r", vmin=-lim, vmax=lim)
            ax.set_title(f"{lab}: {title}", fontsize=9)
            ax.set_xticks(range(len(m)), m, fontsize=7)
            ax.set_yticks(range(len(rows)), rows, fontsize=7)
            ax.set_xlabel("bus k (measured)", fontsize=8)
            ax.set_ylabel("bus i (complete equation)", fontsize=8)
            for (a, b), val in np.ndenumerate(A):
                if np.isfinite(val) and val != 0:
                    ax.text(b, a, f"{val:.1f}", ha="center", va="center", fontsize=5.5)
        fig.colorbar(im, ax=axes[:, c], shrink=0.7)
    fig.suptitle(f"{ds.case}: line parameters from {len(ds.measured)} measured buses "
                 f"(unmeasured buses not shown)", fontsize=10)
    with atomic_output(path, suffix=".png") as tmp:
        fig.savefig(tmp, dpi=80, format="png")
    plt.close(fig)


def line_table(ds, fit) -> str:
    """Markdown: every candidate line quantity of one draw with truth, estimate, interval and status."""
    from _bench_md import md_table

    rows = []
    for name, i, k, t, e, lo, hi, present, pt in fit.table:
        found = (i, k) in fit.lines_found()
        status = "point" if pt else ("set" if np.isfinite(lo) and np.isfinite(hi) else "unbounded")
        err = f"{abs(e - t) / abs(t) * 100:.3g}" if present and abs(t) > 0 else "—"
        bias = max((abs(fit.bias.get(f"{name[0]}[{a},{b}]", 0.0)) for a, b in ((i, k), (k, i))), default=0.0)
        rows.append([name, "line" if present else "absent", f"{t:.4g}", f"{e:.4g}", f"[{lo:.4g}, {hi:.4g}]",
                     status, err, f"{bias:.2g}", "yes" if found else "no"])
    why = ", ".join(f"bus {b}: {r}" for b, r in ds.excluded.items())
    units = ", ".join(f"{b}: {u['kind']}" for b, u in sorted(ds.btm.items()))
    return (md_table(["quantity", "truth", "true value", "estimate", "identified interval", "identified",
                      "error %", "voltage-noise bias corrected (larger end)", "reported as line"], rows)
            + f"\nBuses without a usable equation: {why}. Behind-the-meter units: {units}.\n")


def lines_main(seed: int, snapshots: int, snr_db: float, write: bool) -> int:
    """One case14 draw, every candidate listed (own BENCHMARKS section)."""
    from _bench_md import write_section

    from odnn_sep.signals import make_dataset
    from odnn_sep.signals.grid_identify import identify_grid

    ds = make_dataset("power_grid", case="case14", snapshots=snapshots, snr_db=snr_db, random_state=seed)
    fit = identify_grid(ds, random_state=seed)
    body = line_table(ds, fit) + LINES_NOTES
    print(body)
    if write:
        write_section("power_grid_lines", "Power grid: every candidate line of one case14 draw",
                      f"python recipes/power_grid.py --lines {seed}", body)
    return 0


LINES_NOTES = """
"identified": point = in every three-day piece the identified interval is at most twice as wide as the
metering noise alone makes it, and the combined interval is narrower than 5 % of the estimate; set = a
wider interval (the convex class, or the noise, leaves a range of values that fit); unbounded = the class
cannot bound it. Pieces (their least-squares points) and both ends of a line are combined by inverse
noise variance (Birge-ratio widening where they disagree); the part of each piece's interval the class
leaves open, and the bias from voltage noise (subtracted), are added whole to the half-width. A
candidate whose interval (Bonferroni-widened) contains zero is reported absent, i.e. zero with that interval.
The susceptance columns follow the angles, which a function of v_i cannot follow: precise. The
conductance columns (v_i v_k cos δ_ik − v_i²) are largely affine in v_i, which the convex class contains:
identified, several times less precise. Transformer branches have G = 0 (no resistance in case14) but B ≠ 0.
"""


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="one small draw, short training (for tests)")
    # (0 draws wrote a table of nan, 0 snapshots a traceback after minutes)
    ap.add_argument("--seeds", type=positive_int, default=3, help="draws per case (report seeds start at 100)")
    ap.add_argument("--snapshots", type=positive_int, default=SNAPSHOTS, help="15-min snapshots per draw")
    ap.add_argument("--snr-db", type=float, default=60.0, help="metered-power-to-noise ratio (dB)")
    ap.add_argument("--cases", default="case14,case33bw", help="comma-separated pandapower cases")
    ap.add_argument("--no-write", action="store_true", help="print only")
    ap.add_argument("--lines", type=int, metavar="SEED", help="only list every candidate line of one case14 draw")
    args = ap.parse_args(argv)
    cases = [c.strip() for c in args.cases.split(",") if c.strip()]
    unknown = [c for c in cases if c not in CASES]
    if not cases or unknown:
        ap.error(f"--cases {args.cases!r}: give one or more of {', '.join(CASES)}, comma-separated")
    if args.lines is not None:
        return lines_main(args.lines, args.snapshots, args.snr_db, not args.no_write)
    import torch

    torch.set_num_threads(1)
    seeds = [100] if args.quick else list(range(100, 100 + args.seeds))
    snapshots = 40 if args.quick else args.snapshots
    epochs = 30 if args.quick else 400
    t0 = time.time()
    res = {c: run_case(c, seeds if c == "case14" else seeds[:1], snapshots=snapshots, snr_db=args.snr_db,
                       epochs=epochs, progress=lambda s: print(s, file=sys.stderr)) for c in cases}
    from _bench_md import md_table, write_section

    header = ["case", "draws", "ODNN point-identified MAPE % (median / worst)", f"target ≤ {TARGET}",
              "of which B / G (median)", "ODNN all true-line coeffs MAPE %", "coeffs point / set-identified (per draw)", "topology exact",
              "OLS", "SINDy", "regular DNN", "PINN penalty", "sim / fit s per draw"]
    rows = []
    for c, r in res.items():
        pt = [x for x in r["point"] if np.isfinite(x)]
        met = ("met" if pt and max(pt) <= TARGET else "not met") + (f" ({np.median(pt):.3g})" if pt else "")
        rows.append([c, len(r["topo"]), med_worst(r["point"]), met,
                     f"{med_only(r['point_B'])} / {med_only(r['point_G'])}", med_worst(r["all"]),
                     f"{np.median(r['n_point']):.0f} / {np.median(r['n_set']):.0f}",
                     f"{sum(r['topo'])} of {len(r['topo'])}", med_worst(r["ols"]), med_worst(r["sindy"]),
                     med_worst(r["regular_dnn"]), med_worst(r["pinn_penalty"]),
                     f"{np.median(r['sim_s']):.0f} / {np.median(r['fit_s']):.0f}"])
    body = md_table(header, rows) + NOTES.format(snr=args.snr_db, snap=snapshots, epochs=epochs,
                                                 wall=time.time() - t0, chunk=CHUNK)
    print(body)
    if "case14" in res and not args.quick and not args.no_write:
        ds, fit = res["case14"]["last"]
        figure(ds, fit, ROOT / "docs" / "power_grid.png")
        cmd = "python recipes/power_grid.py" + (f" --seeds {args.seeds}" if args.seeds != 3 else "")
        write_section("power_grid", "Power grid: line parameters and topology (paper 4.3 / C.7)", cmd, body)
    return 0


NOTES = """
Every draw: {snap} snapshots of 15 min (independent residential/commercial load profiles with appliance
noise, tap-changer steps at the substation, generator dispatch and voltage schedules), behind-the-meter
generation (boost converter c v²/(1−D)², power-law P0 v^α, exponential P0 e^(κ(v−1))) at half the loaded
buses, metered power noise at **{snr:g} dB relative to each bus's physics power** (0.1 % metering), PMU
noise 1e-6 p.u. in magnitude and 1e-6 rad in angle. The AC power flow of every snapshot is solved by
Newton's method on pandapower's admittance matrix, and the first and last snapshot of every draw are
solved again by `pandapower.runpp` (must agree to 1e-7). Candidates per bus: every measured bus within
two branches in the network model (open switches included); absent candidates must come out as zero.
case14: buses 0–6 and 8 measured, rows 0–4 complete; case33bw: buses 0–9, 18, 22, 25 measured, rows 0–8.
Regular DNN / PINN penalty: MLP 64×3 on v_i, {epochs} Adam epochs. Wall time {wall:.0f} s (shared 2-core machine).

- **Estimator.** Each bus equation is fitted separately on pieces of {chunk} snapshots (the cone fit's
  cost grows faster than linearly with the samples, so pieces make weeks of data affordable). Each
  piece gives its least-squares point and its identified interval; the interval's half-width is split
  into the part the metering noise explains (least squares on the same columns) and the rest, which
  the convex class leaves open. The pieces and the two ends of a line are combined by inverse noise
  variance (Birge-ratio widening where they disagree); the combined half-width is the combined noise
  part **plus** the pieces' remaining part and voltage-noise bias, which more pieces do not average
  away (the same class imitates the same column in every piece). A candidate is reported as a line
  when that interval, widened for the number of candidates (Bonferroni), excludes zero; otherwise it
  is reported absent (zero) with its interval. A bus without customer load (the slack bus of both
  cases) cannot carry behind-the-meter generation: its equation has no disturbance class (least squares).
- **Identifiability.** The class is Convex() in v_i at every bus with customer load (the user does
  not know which of them carry such generation). A convex function of v_i contains every affine function
  of v_i and can imitate the part of a column that is a convex function of v_i. A coefficient is
  called point-identified when in every piece its identified interval is at most twice as wide as
  the metering noise alone makes it (least squares on the same columns plus the class's free constant
  and line) and the combined interval is narrower than 5 % of the value; otherwise set-identified
  (interval reported, not a point). The susceptances B_ik follow the angles, which a function of v_i
  cannot follow: precise. The conductances G_ik of this transmission case multiply v_i v_k cos δ_ik − v_i²,
  which is largely affine in v_i: they are identified, but the class leaves them ~5–10 times less
  precise than the B_ik (column "of which B / G"). The self-conductance column v_i² lies inside the
  convex class: G_ii is not identifiable together with a convex disturbance, which is why the row-sum
  form G_ii = −Σ_k G_ik (no shunt conductance) is used.
- Buses with an unmeasured neighbour give incomplete equations and are left out; zero-injection buses
  give homogeneous equations (scale not determined) and are left out too.
- OLS, SINDy, DNN and PINN (whole record, the two ends of a line averaged) put the behind-the-meter
  generation into the line parameters (errors of tens to hundreds of %).
- Method choices (three-day pieces rather than one-day ones, the noise-ratio factor 2, the voltage-noise
  correction, no class at buses without load) were made on development draws (seeds 1–3 of case14, seed 1
  of case33bw); the table reports draws from seed 100 on.
- **Changes against the previous version of this table** (chosen on the development draws, then run
  once on the report draws): (1) pieces combined by their noise part, the class's part added whole
  (before: the whole identified half-width was treated as noise and shrank like 1/√pieces, so with
  48 days a shift the class allows in every piece alike came out as a "line": case14 draw 100 line
  2–8, case33bw lines 1–22 and 4–6); (2) each piece contributes its least-squares point rather than
  the centre of its identified interval (the centre leans to the side the convex class leaves open,
  alike in every piece; development draw 1 of case14: point-identified MAPE 0.151 → 0.118 %);
  (3) the voltage-noise correction solves the corrected normal equations up to a noise share of 0.8
  of the column spread (before 0.5, first order beyond): the feeder's buses 4–6 have a share of 0.6,
  and the first-order correction left B[6-25] at 4.4 instead of 0 (false lines 4–6, 6–25 on
  development draw 1 of case33bw; with the full correction none, all-coefficient MAPE 5.2 → 1.9 %).
  Before these changes (same report draws, same 48 days): case14 point-identified MAPE 0.154 / 0.332 %
  (median / worst), all true-line coefficients 0.474 / 0.507 %, 15 point / 2 set-identified,
  topology exact 2 of 3; case33bw 0.331 %, 10.2 %, 2 / 22, topology 0 of 1. With 24 days (earlier
  run): case14 0.304 / 0.329 %, topology exact 3 of 3, case33bw topology exact.
- **Voltage noise (errors-in-variables).** The columns are built from measured voltages. The bias this
  causes is estimated from the stated PMU noise (corrected normal equations, `odnn_sep/signals/grid_eiv.py`,
  while the noise is under 0.8 of the column spread in every direction, first order beyond);
  estimates are shifted by it and their intervals widened by it, and a coefficient whose bias exceeds its
  noise half-width is not called point-identified. In case14 the bias is small. On the distribution
  feeder (case33bw) adjacent voltages differ by ~1e-3 p.u. and the admittances are ~10³ p.u.: the
  voltage noise makes up 6–60 % of the column spread in some directions (development draw), and
  most coefficients come out as wide intervals ("limited by voltage noise", set-identified) rather
  than points. The data cannot tell them more precisely at 1e-6 p.u.
"""

if __name__ == "__main__":
    sys.exit(main())
