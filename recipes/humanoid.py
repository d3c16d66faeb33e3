"""Humanoid stand-up reward under disturbance (paper App. C.4): identification, ranking, policy search.

1. Identification: for each disturbance kind (sin z, sensor drift, periodic calibration error, all
   three) and several draws, the reward coefficients (height change, action energy) by ODNN exact
   (Subspace class), OLS, a regular DNN (Eq. 2, network input (z_after, time)) and a PINN penalty.
2. Why it matters: policies ranked by the true, the corrupted and the cleaned reward (ODNN's reward
   model); Kendall tau against the true ranking.
3. A short cross-entropy search over a 68-weight linear gait policy on the corrupted reward (sin z)
   and on the cleaned reward, each evaluated on the true reward.

Run ``python recipes/humanoid.py`` (writes BENCHMARKS.md) or ``--quick`` (seconds).
"""
from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402

from odnn_sep.batch import positive_int  # noqa: E402

TARGET = 0.84  # % (half the paper's 1.68 %)
KINDS = ("sin", "drift", "calibration", "all")


def mape(est, true) -> float:
    return float(np.mean(np.abs(np.asarray(est) - true) / np.abs(true)) * 100)


def identify(kind: str, seeds, *, snr_db: float, epochs: int, size: dict) -> dict:
    """MAPE (%) of the reward coefficients per draw, for every method."""
    from odnn_sep.core import Separator
    from odnn_sep.core.baselines import ols, pinn_penalty, regular_dnn
    from odnn_sep.core.bounds import efficiency_bound, expected_mape
    from odnn_sep.signals import make_dataset

    out = {m: [] for m in ("odnn", "bound", "ols", "regular_dnn", "pinn_penalty", "tau")}
    for s in seeds:
        ds = make_dataset("humanoid", disturbance=kind, snr_db=snr_db, random_state=s, **size)
        pr = ds.problem
        th = pr.theta_vector
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            r = Separator(pr.basis, disturbance=pr.disturbance).fit(pr.x, pr.y).result_
        out["odnn"].append(mape(r.theta, th))
        cov = efficiency_bound(pr.basis, pr.disturbance, pr.x, th, sigma=pr.noise_sigma)
        out["bound"].append(expected_mape(cov, th))
        out["tau"].append(ranking(ds, r.theta))
        F = pr.design()
        out["ols"].append(mape(ols(F, pr.y), th))
        xin = np.c_[ds.z_after, pr.x / pr.x.max()]
        if epochs:
            out["regular_dnn"].append(mape(regular_dnn(xin, pr.y, F, epochs=epochs, random_state=s), th))
            out["pinn_penalty"].append(mape(pinn_penalty(xin, pr.y, F, epochs=epochs, random_state=s), th))
    return out


def ranking(ds, theta_hat) -> tuple[float, float]:
    """Kendall tau of the policy ranking by corrupted and by cleaned return against the true return."""
    from scipy.stats import kendalltau

    pr = ds.problem
    cleaned = pr.design() @ theta_hat
    k = len(ds.policy_names)

    def per_policy(rew):
        return np.array([rew[ds.policy_id == j].sum() for j in range(k)])

    true = per_policy(pr.physics)
    return (float(kendalltau(true, per_policy(pr.y)).statistic),
            float(kendalltau(true, per_policy(cleaned)).statistic))


def policy_search(seed: int, *, iters: int, pop: int, steps: int, snr_db: float, size: dict) -> dict:
    """CEM on corrupted (sin z) vs cleaned vs true reward; every result scored on the true reward."""
    from odnn_sep.core import Separator
    from odnn_sep.signals import make_dataset
    from odnn_sep.signals.humanoid_policies import cem, make_env, rollout

    ds = make_dataset("humanoid", disturbance="sin", snr_db=snr_db, random_state=seed, **size)
    pr = ds.problem
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        th_hat = Separator(pr.basis, disturbance=pr.disturbance).fit(pr.x, pr.y).result_.theta
    th = pr.theta_vector
    env = make_env(ds.extras["frame_skip"])
    rng = np.random.default_rng(seed)

    def reward(kind):
        def fn(rec):
            F = np.c_[rec["z_after"] - rec["z_before"], rec["ctrl_sq"]]
            if kind == "cleaned":
                return F @ th_hat
            base = F @ th
            return base + ds.corruption.amp_sin * np.sin(rec["z_after"]) if kind == "corrupted" else base
        return fn

    out = {}
    for kind in ("corrupted", "cleaned", "true"):
        fn = reward(kind)
        w, _ = cem(lambda pol, fn=fn: float(fn(rollout(env, pol, steps, seed=seed, rng=rng)).sum()),
                   iters=iters, pop=pop, elite=max(2, pop // 4), rng=np.random.default_rng(seed + 1))
        from odnn_sep.signals.humanoid_policies import LinearGait

        evals = [float(reward("true")(rollout(env, LinearGait(w), steps, seed=10_000 + e, rng=rng)).sum())
                 for e in range(3)]
        out[kind] = float(np.mean(evals))
    env.close()
    return out


def med_worst(v) -> str:
    return f"{np.median(v):.3g} / {max(v):.3g}" if v else "—"


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="tiny sizes (for tests)")
    # (0 draws wrote a table of nan into BENCHMARKS.md)
    ap.add_argument("--seeds", type=positive_int, default=5, help="draws per disturbance kind (report seeds from 100)")
    ap.add_argument("--snr-db", type=float, default=30.0, help="true-reward-to-noise ratio (dB)")
    ap.add_argument("--no-write", action="store_true", help="print only")
    args = ap.parse_args(argv)
    import torch

    torch.set_num_threads(1)
    q = args.quick
    seeds = [100] if q else list(range(100, 100 + args.seeds))
    size = dict(policies=4, episodes=1, steps=60) if q else dict(policies=8, episodes=4, steps=100)
    epochs = 20 if q else 500
    t0 = time.time()
    ident = {k: identify(k, seeds, snr_db=args.snr_db, epochs=epochs, size=size) for k in KINDS}
    search = policy_search(100, iters=2 if q else 6, pop=4 if q else 12, steps=30 if q else 80,
                           snr_db=args.snr_db, size=size)
    from _bench_md import md_table, write_section

    rows = []
    for k in KINDS:
        e = ident[k]
        tc = [r[0] for r in e["tau"]]
        tl = [r[1] for r in e["tau"]]
        met = "met" if max(e["odnn"]) <= TARGET else "not met"
        rows.append([k, len(seeds), med_worst(e["odnn"]), f"{np.median(e['bound']):.3g}",
                     f"{met} (worst {max(e['odnn']):.3g})",
                     med_worst(e["ols"]), med_worst(e["regular_dnn"]), med_worst(e["pinn_penalty"]),
                     f"{np.median(tc):.2f} / {min(tc):.2f}", f"{np.median(tl):.2f} / {min(tl):.2f}"])
    header = ["disturbance", "draws", "ODNN exact MAPE % (median / worst)", "bound (median)",
              f"target ≤ {TARGET} (worst draw)", "OLS",
              "regular DNN", "PINN penalty", "Kendall τ corrupted (median / worst)", "Kendall τ cleaned"]
    body = md_table(header, rows)
    body += md_table(["policy search on", "true return of the result (mean of 3 held-out episodes)"],
                     [[k, f"{v:.3g}"] for k, v in search.items()])
    body += NOTES.format(snr=args.snr_db, n=size["policies"] * size["episodes"] * size["steps"], epochs=epochs,
                         eps=size["episodes"], steps=size["steps"],
                         k=size["policies"], wall=time.time() - t0)
    print(body)
    if not q and not args.no_write:
        cmd = "python recipes/humanoid.py" + (f" --seeds {args.seeds}" if args.seeds != 5 else "")
        write_section("humanoid", "Humanoid stand-up reward under disturbance (paper C.4)", cmd, body)
    return 0


NOTES = """
Every draw: gymnasium `HumanoidStandup-v5` (MuJoCo), frame skip 3–7 (frame time 9–21 ms), {k} policies
(zero, uniformly random, linear gaits with random weights) × {eps} episodes of {steps} steps, recorded
round-robin (every policy once, then again), {n} transitions. True reward per step
θ_up (z_after − z_before) + θ_ctrl Σa², θ_up = w/Δt with w ∈ [0.5, 1.5], θ_ctrl ∈ [−0.2, −0.05]; noise at
**{snr:g} dB relative to the true reward**. Disturbances: A sin(z_after) (A ∈ [0.5, 2]), a cubic sensor
drift in time, a sawtooth calibration error with a 50-step period, and all three. ODNN class: Subspace
(Legendre polynomials of z_after to degree 9, of time to degree 5, calibration-phase indicators):
point-identified. Regular DNN / PINN penalty: MLP 64×3 on (z_after, time), {epochs} Adam epochs.
Wall time {wall:.0f} s (shared 2-core machine).

- "bound": Cramér–Rao bound for the same draws (`odnn_sep.core.bounds`), the expected MAPE of the best
  unbiased estimator given the noise and the disturbance class; a draw's error fluctuates around it.
- Kendall τ compares the ranking of the {k} policies by summed reward (corrupted or cleaned = ODNN's
  reward model θ̂·f) with the ranking by the true reward (1 = identical).
- Policy search: cross-entropy method over the 68 gait weights (12 candidates × 6 iterations, 80-step
  episodes, one training seed) on each reward, the resulting policy scored on the true reward over 3
  held-out episodes. sin z rewards being high rather than rising; drift and calibration errors add
  the same to every policy and cannot mislead a search, so only sin z is used here.
- **Why the worst draws were 1.00 % (drift) and 1.38 % (all) before.** The action-energy coefficient
  θ_ctrl carried the error (θ_up was within 0.15 %): Σa² is mostly a per-policy level (zero for the
  zero policy, ~constant for the random one), and with the episodes recorded policy after policy that
  level was a step function of the recording time, which the drift class (polynomials of time to
  degree 5) partly imitates. The class was not too small (the drift is a cubic, inside it); the
  errors matched the Cramér–Rao bound of that design (development draws 1–5: θ_ctrl bound 0.9–1.7 %
  with drift). Recording the episodes round-robin removes that collinearity (bound 0.5–1.1 % at the
  same 1600 transitions), and 4 episodes per policy instead of 2 (3200 transitions, about twice the
  simulation time) halve it again (0.27–0.55 %). Both choices were made on development draws 1–5;
  the table reports draws 100–104. Before (same seeds, episodes policy after policy, 1600
  transitions), ODNN MAPE % median / worst (bound median): sin 0.284 / 0.762 (0.192), drift
  0.566 / 1.00 (0.325), calibration 0.279 / 0.352 (0.156), all 0.724 / 1.38 (0.366).
- The paper's literal reward z/Δt is not separable from sin z by any class of functions of z (a linear
  term is convex, concave and monotone at once); see `odnn_sep/signals/humanoid.py`.
"""

if __name__ == "__main__":
    sys.exit(main())
