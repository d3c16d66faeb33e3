"""Table 1 of the paper (section 4.5): parameter-identification error of ODNN and baselines.

For every synthetic dataset in ``odnn_sep.signals`` we draw ``--trials`` problems with random true
parameters (seeded), fit them with ODNN (exact and network solvers) and the baselines (regular DNN,
PINN-style penalty, OLS, SINDy), and report MAPE mean +- std (%) over the linear coefficients theta.
Where the basis has nonlinear parameters phi (biology growth rate, oscillator decay/frequency),
ODNN estimates phi itself (variable projection), and the baselines are handed the true phi
(which favours them); ODNN's phi error is reported in its own column.

Cone classes (convex, monotone) only set-identify theta; for them we report the width of the
identified interval and whether the truth lies inside it.

Run ``python recipes/table1.py`` (writes its section of BENCHMARKS.md) or ``--quick`` (seconds).
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402

#: The paper's ODNN column (Table 1) for the rows that match a dataset here.
PAPER_ODNN = {"synthetic": ("Synthetic system", 0.21), "pendulum": ("Driven pendulum", 0.86),
              "biology": ("Biology system", 0.84), "heat2d": ("Heat transfer", 0.92)}
PAPER_ROW = {"explicit_1d": "synthetic", "explicit_2d": "synthetic", "implicit_convex": "synthetic",
             "implicit_periodic": "synthetic", "implicit_symmetric": "synthetic", "implicit_monotone": "synthetic",
             "figure2": "synthetic", "pendulum": "pendulum", "biology": "biology", "heat2d": "heat2d"}
METHODS = ("odnn_exact", "odnn_network", "regular_dnn", "pinn_penalty", "ols", "sindy")


def mape(est: dict, true: dict, names) -> float:
    return float(np.mean([abs(est[k] - true[k]) / abs(true[k]) * 100 for k in names]))


def bound_mapes(ds) -> tuple[float, float | None]:
    """Cramér–Rao MAPE (%) of theta and of phi for this draw (see odnn_sep.core.bounds)."""
    from odnn_sep.core.bounds import efficiency_bound, expected_mape

    cov = efficiency_bound(ds.basis, ds.disturbance, ds.x, ds.theta_vector, ds.phi_true, sigma=ds.noise_sigma)
    p = ds.theta_vector.size
    phi = [ds.phi_true[k] for k in ds.basis.phi_names]
    return expected_mape(cov, ds.theta_vector), (expected_mape(cov[p:, p:], phi) if phi else None)


def run_dataset(name, *, trials, dnn_trials, network_trials, snr_db, net_epochs, dnn_epochs, seed0, progress):
    from odnn_sep.core import Separator
    from odnn_sep.core.baselines import ols, pinn_penalty, regular_dnn, sindy
    from odnn_sep.signals import GENERATORS

    gen = GENERATORS[name]
    errs = {m: [] for m in METHODS}
    phi_err, widths, true_widths, covered, net_unconv = [], [], [], [], 0
    bound, phi_bound = [], []
    identified = "point"
    for i in range(trials):
        ds = gen(snr_db=snr_db, random_state=seed0 + i)
        identified = ds.identified
        lin = ds.basis.names
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
        errs["odnn_exact"].append(mape(r.theta_dict(), ds.theta_true, lin))
        if r.phi:
            phi_err.append(mape(r.phi, ds.theta_true, list(r.phi)))
        if identified == "point":
            b, bp = bound_mapes(ds)
            bound.append(b)
            if bp is not None:
                phi_bound.append(bp)
        elif identified == "set":
            widths.append(float(np.mean((r.interval[:, 1] - r.interval[:, 0]) / np.abs(ds.theta_vector) * 100)))
            lo, hi = ds.extras["identified_set"]
            true_widths.append((hi - lo) / abs(ds.theta_true[lin[0]]) * 100)
            covered.append(bool(np.all((r.interval[:, 0] <= ds.theta_vector) & (ds.theta_vector <= r.interval[:, 1]))))
        if i < network_trials:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # non-convergence is counted and shown in the table
                rn = Separator(ds.basis, disturbance=ds.disturbance, solver="network", random_state=i,
                               epochs=net_epochs).fit(ds.x, ds.y).result_
            net_unconv += int(not rn.converged)
            errs["odnn_network"].append(mape(rn.theta_dict(), ds.theta_true, lin))
        F = ds.design()  # baselines get the true phi
        truth = ds.theta_true
        errs["ols"].append(mape(dict(zip(lin, ols(F, ds.y), strict=True)), truth, lin))
        errs["sindy"].append(mape(dict(zip(lin, sindy(F, ds.y), strict=True)), truth, lin))
        if i < dnn_trials:
            th = regular_dnn(ds.x, ds.y, F, epochs=dnn_epochs, random_state=i)
            errs["regular_dnn"].append(mape(dict(zip(lin, th, strict=True)), truth, lin))
            th = pinn_penalty(ds.x, ds.y, F, epochs=dnn_epochs, random_state=i)
            errs["pinn_penalty"].append(mape(dict(zip(lin, th, strict=True)), truth, lin))
        progress.update(1)
    return {"errs": errs, "phi_err": phi_err, "bound": bound, "phi_bound": phi_bound, "widths": widths, "true_widths": true_widths, "covered": covered,
            "identified": identified, "net_unconverged": net_unconv, "phi_names": list(ds.basis.phi_names), "lin": list(ds.basis.names)}


def fmt(v) -> str:
    if not v:
        return "—"
    return f"{np.mean(v):.3g} ± {np.std(v):.2g}"


def snr_sweep(names, trials, snrs, seed0):
    """ODNN exact only (cheap): per row, (ODNN MAPE, Cramér–Rao MAPE) at each noise level."""
    from odnn_sep.core import Separator
    from odnn_sep.signals import GENERATORS

    rows = []
    for k, name in enumerate(names):
        cells = []
        for snr in snrs:
            e, b = [], []
            for i in range(trials):
                ds = GENERATORS[name](snr_db=snr, random_state=seed0 + 1000 * k + i)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    r = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
                keys = ["mu"] if name == "biology" else list(ds.basis.names)
                e.append(mape({**r.theta_dict(), **r.phi}, ds.theta_true, keys))
                bt, bp = bound_mapes(ds)
                b.append(bp if name == "biology" else bt)
            cells.append((float(np.mean(e)), float(np.mean(b))))
        rows.append((name, cells))
    return rows


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="few trials and short training (seconds; for tests)")
    ap.add_argument("--trials", type=int, default=50, help="trials per dataset (ODNN exact, OLS, SINDy)")
    ap.add_argument("--dnn-trials", type=int, default=20, help="trials for regular DNN and PINN penalty")
    ap.add_argument("--network-trials", type=int, default=10, help="trials for the ODNN network solver")
    ap.add_argument("--snr-db", type=float, default=30.0, help="physics-to-noise power ratio (dB)")
    ap.add_argument("--datasets", default="", help="comma-separated subset of dataset names")
    ap.add_argument("--noise-only", action="store_true",
                    help="only the ODNN-exact vs Cramér–Rao noise table (a minute; no networks)")
    ap.add_argument("--no-write", action="store_true", help="print only; do not touch BENCHMARKS.md")
    args = ap.parse_args(argv)

    import torch
    from tqdm import tqdm

    from odnn_sep.signals import GENERATORS

    torch.set_num_threads(1)  # small nets: threads only add contention on a shared machine
    from _table1_systems import SYSTEM_PAPER, available, system_row

    names = [s for s in args.datasets.split(",") if s] or list(GENERATORS) + available()
    bad = [s for s in names if s not in GENERATORS and s not in SYSTEM_PAPER]
    if bad:
        ap.error(f"unknown dataset(s) {bad}; choose from {list(GENERATORS) + list(SYSTEM_PAPER)}")
    if args.quick:
        args.trials, args.dnn_trials, args.network_trials = 2, 1, 1
        net_epochs, dnn_epochs = 60, 60
    else:
        net_epochs, dnn_epochs = 1500, 1000
    dnn_trials = min(args.dnn_trials, args.trials)
    net_trials = min(args.network_trials, args.trials)

    if args.noise_only:
        noise_section(args, names)
        return 0
    t0 = time.time()
    res = {}
    with tqdm(total=len(names) * args.trials, file=sys.stderr, disable=not sys.stderr.isatty()) as bar:
        for k, name in enumerate(n for n in names if n in GENERATORS):
            bar.set_description(name)
            res[name] = run_dataset(name, trials=args.trials, dnn_trials=dnn_trials, network_trials=net_trials,
                                    snr_db=args.snr_db, net_epochs=net_epochs, dnn_epochs=dnn_epochs,
                                    seed0=1000 * k, progress=bar)
    elapsed = time.time() - t0

    from _bench_md import md_table, write_section

    header = ["dataset", "class", "ODNN exact", "bound (any unbiased estimator)", "ODNN network", "regular DNN", "PINN penalty", "OLS", "SINDy",
              "ODNN φ MAPE", "identified set width, % of θ: ODNN / noise-free truth; truth inside ODNN set", "paper ODNN", "target ≤ ½ paper"]
    rows = []
    for name in names:
        if name in SYSTEM_PAPER:  # engineering systems: their own recipes, their own draws
            rows.append(system_row(name, quick=args.quick, snr_db=args.snr_db))
            continue
        r = res[name]
        e = r["errs"]
        cls_s = type(GENERATORS[name](random_state=0).disturbance).__name__
        width = (f"{np.mean(r['widths']):.3g} / {np.mean(r['true_widths']):.3g}; {np.mean(r['covered']) * 100:.0f} %"
                 if r["widths"] else "point-identified")
        phi = f"{fmt(r['phi_err'])} ({', '.join(r['phi_names'])})" if r["phi_err"] else "—"
        paper = PAPER_ODNN.get(PAPER_ROW.get(name, ""))
        if paper is None:
            paper_s, target = "—", "—"
        else:
            paper_s = f"{paper[1]:.2f} ({paper[0]})"
            if r["identified"] == "set":
                target = "cannot hold: set-identified"
            else:
                bio = name == "biology"
                ours = np.mean(r["phi_err"]) if bio else np.mean(e["odnn_exact"])
                floor = np.mean(r["phi_bound"]) if bio else np.mean(r["bound"])
                target = f"{'met' if ours <= paper[1] / 2 else 'not met'} ({ours:.3g} vs {paper[1] / 2:.3g}"
                target += (f"; bound {floor:.3g}: unreachable at this noise level)" if floor > paper[1] / 2 else ")")
        net = fmt(e["odnn_network"])
        if r["net_unconverged"]:
            net += f" ({r['net_unconverged']} not conv.)"
        bnd = f"{np.mean(r['bound']):.3g}" if r["bound"] else "none (set-identified)"
        if r["phi_bound"]:
            bnd += f"; φ {np.mean(r['phi_bound']):.3g}"
        rows.append([name, cls_s, fmt(e["odnn_exact"]), bnd, net, fmt(e["regular_dnn"]), fmt(e["pinn_penalty"]),
                     fmt(e["ols"]), fmt(e["sindy"]), phi, width, paper_s, target])
    table = md_table(header, rows)
    notes = f"""
MAPE mean ± std (%) of the linear coefficients θ over random true parameters; measurement noise is
white Gaussian at **SNR {args.snr_db:g} dB relative to the physics signal** (10 log10(mean(physics²)/σ²);
the disturbance is not counted as noise). Trials per dataset: {args.trials} for ODNN exact, OLS and SINDy;
**{dnn_trials} for regular DNN and PINN penalty, {net_trials} for the ODNN network solver** (slow; CPU).
Network solver: {net_epochs} Adam epochs + L-BFGS; regular DNN / PINN penalty (λ = 1): MLP 64×3, {dnn_epochs}
Adam epochs, θ started at 0. Wall time {elapsed:.0f} s.

- "bound" is the Cramér–Rao bound for the same draws: the expected MAPE of the best *unbiased* estimator
  given the noise level and the disturbance class (`odnn_sep.core.bounds`). No method can be expected to
  beat it without extra knowledge; where it is above the target, the target is unreachable at this noise
  level, and the companion table below shows the same rows at 20, 30 and 40 dB.
- Rows with nonlinear φ (biology: growth rate μ; oscillator: γ, ω): ODNN estimates φ itself, the baselines
  are given the **true** φ (which favours them). ODNN's φ error is in the "ODNN φ MAPE" column; for the
  biology row the paper comparison uses the growth-rate error.
- **Set-identified rows (implicit_convex, implicit_monotone)**: a convex/monotone disturbance class cannot
  exclude a small multiple of the physics (x² + c sin 5x stays convex for |c| ≤ 0.08), so θ is only known
  to lie in an interval; the paper's sub-percent claim **cannot hold** there for any method. ODNN exact
  reports the interval centre; the ODNN network number is wherever gradient descent stopped inside the set.
  The width column compares ODNN's reported set (95 % profile-likelihood set from the noisy data) with
  the exact noise-free identified set of the generator; "truth inside" is how often ODNN's set contains θ.
- "paper ODNN" is the paper's Table 1 ODNN column for the matching row (all C.1/C.2/Figure 2 cases are
  compared with its "Synthetic system" row); target: ours ≤ half of it. The paper states no measurement
  noise level for these rows. Explicit 1-D uses `Band`
  (physics off the DFT bins, so OLS is biased by leakage); in explicit 2-D the disturbance is exactly
  orthogonal on the grid, so OLS coincides with ODNN there, as the theory says it must. In figure2 and
  implicit_symmetric OLS is also unbiased (even disturbance, odd basis, symmetric grid).
- OLS/SINDy use only the physics columns: in `population` the intercept log N0 lives in the periodic
  class (not in the basis), so they put it into the growth term (errors of hundreds of %); ODNN absorbs it.
- Cone rows: ODNN's 95 % set is a profile set from the noisy data (Cp-corrected profile RSS, threshold
  calibrated by a parametric bootstrap). "truth inside" is its measured coverage; it can fall below 95 %
  because a cone fit absorbs noise unevenly across θ, and the set can be narrower than the noise-free one.
- "not conv." counts network-solver runs that ended with a θ-gradient above tolerance (ConvergenceWarning).
- Engineering systems (rows power_grid, humanoid; recipes/power_grid.py and recipes/humanoid.py hold
  their full tables): power_grid is case14 with metered power at 60 dB and 1e-6 PMU noise, 3 draws, MAPE over
  the point-identified line coefficients (conductances are mostly set-identified under the convex class);
  humanoid is the sin z reward corruption, 5 draws, both reward coefficients.
- Differences from the paper's set-ups (see `odnn_sep/signals` docstrings): pendulum separated by
  periodicity (both terms are even in t), heat transfer with a symmetric disturbance and asymmetric
  physics sources (the paper's reverse is not identifiable), biology as N0·exp(μt) with an
  Aiba–Edwards μ and an additive daily disturbance.
"""
    body = table + notes
    print(body)
    if not args.no_write and not args.quick:
        write_section("table1", "Table 1: parameter identification error (synthetic datasets)", command(args), body)
    noise_section(args, names)
    return 0


def command(args, extra: str = "") -> str:
    return "python recipes/table1.py" + extra + "".join(
        f" {flag} {val}" for flag, val, default in (
            ("--trials", args.trials, 50), ("--dnn-trials", args.dnn_trials, 20),
            ("--network-trials", args.network_trials, 10), ("--snr-db", f"{args.snr_db:g}", "30"),
            ("--datasets", args.datasets, "")) if val != default)


def noise_section(args, names) -> None:
    """ODNN exact against the Cramér–Rao bound at three noise levels (cheap: no networks)."""
    from _bench_md import md_table, write_section

    from odnn_sep.signals import GENERATORS

    sweep_names = [n for n in names if n in PAPER_ROW and GENERATORS[n](random_state=0).identified == "point"]
    if not sweep_names:
        return
    snrs = (20.0, 30.0, 40.0)
    sweep = snr_sweep(sweep_names, args.trials, snrs, 500_000)
    rows = []
    ratios = [ours / bound for _, cells in sweep for ours, bound in cells]
    for name, cells in sweep:
        half = PAPER_ODNN[PAPER_ROW[name]][1] / 2
        rows.append([name, f"{half:.3g}", *[f"{ours:.3g} / {bound:.3g}" for ours, bound in cells]])
    body = md_table(["dataset", "target (½ paper)", *[f"{s:g} dB: ODNN exact / bound" for s in snrs]], rows)
    body += f"""
MAPE (%) of θ (biology: of the growth rate μ), ODNN exact, {args.trials} draws per cell (seeds differ from the
main table), against the Cramér–Rao bound for the same draws: the expected MAPE of the best unbiased
estimator when the noise is white Gaussian and the disturbance may be anything in its class
(`odnn_sep.core.bounds.efficiency_bound`: information J^T (I − P_G) J / σ², J the physics columns and
their φ-derivatives, P_G the projector onto the disturbance class). ODNN exact / bound ranges
{min(ratios):.2f}–{max(ratios):.2f} over these cells (a mean of {args.trials} absolute errors carries about
±{100 / np.sqrt(args.trials) * 0.76:.0f} % sampling error), i.e. the exact solver is efficient: where a row misses its
target at some noise level, no unbiased estimator could meet it there.
"""
    print(body)
    if not args.no_write and not args.quick:
        write_section("table1_noise", "Table 1 companion: error against the best achievable, by noise level",
                      command(args, " --noise-only"), body)


if __name__ == "__main__":
    sys.exit(main())
