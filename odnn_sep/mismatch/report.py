"""Report of a mismatch analysis: the JSON the issue names, a text summary, and the figure."""
from __future__ import annotations

from odnn_sep.mismatch.effects import EFFECTS


def _params_table(fit):
    iv = fit.intervals()
    return {k: {"value": fit.params[k], "stderr": fit.stderr.get(k),
                "interval95": list(iv[k]) if k in iv else None} for k in fit.free}


def _fit_summary(fit, heldout):
    return {"effects": list(fit.model.effects), "residual_rms": fit.rms, "heldout_rmse": heldout,
            "bic": fit.bic, "n_params": len(fit.free), "parameters": _params_table(fit)}


def result_dict(res) -> dict:
    """JSON-ready dict with the keys verdict, candidates, calibration, where, fit (see the issue)."""
    base = res.calibration.fit
    v = res.verdict
    if v is None:
        verdict = {"effect": None,
                   "description": "nothing missing that the data can show: no effect improved the fit "
                                  "beyond the noise and disturbance (BIC and held-out test)",
                   "parameters": {}}
        after = _fit_summary(base, res.heldout_rmse_before)
    else:
        verdict = {"effect": v.effect, "description": EFFECTS[v.effect].description,
                   "parameters": v.effect_params,
                   "intervals": {k: [v.effect_params[k] - 1.96 * (v.fit.stderr.get(k) or 0.0),
                                     v.effect_params[k] + 1.96 * (v.fit.stderr.get(k) or 0.0)]
                                 for k in v.effect_params if k in v.fit.stderr},
                   "score": v.score, "heldout_improvement": v.cv_improvement,
                   # runners-up within 6 BIC units are not clearly worse ("positive" evidence at most)
                   "ambiguous_with": [c.effect for c in res.candidates
                                      if c is not v and abs(v.score - c.score) < 6.0],
                   "heldout_gain": v.heldout_gain, "heldout_p_value": v.cv_p_value}
        after = _fit_summary(v.fit, v.heldout_rmse)
        # how the calibrated parameters were biased by leaving the effect out
        after["bias_of_calibration"] = {
            k: {"without_effect": base.params[k], "with_effect": v.fit.params[k],
                "shift": base.params[k] - v.fit.params[k],
                "shift_in_stderr": ((base.params[k] - v.fit.params[k]) / v.fit.stderr[k]
                                    if v.fit.stderr.get(k) else None)}
            for k in base.free}
    return {
        "verdict": verdict,
        "candidates": [c.as_dict() for c in res.candidates],
        "calibration": res.calibration.as_dict(),
        "where": res.where,
        "fit": {"before": _fit_summary(base, res.heldout_rmse_before), "after": after},
        "noise_sigma": res.noise_sigma,
        "n_samples": int(len(res.y)),
    }


def _fmt(v):
    if v is None:
        return "-"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def summary_text(res) -> str:
    """Human-readable summary (what the CLI prints)."""
    d = result_dict(res)
    lines = []
    v = d["verdict"]
    if v["effect"] is None:
        lines.append(f"Verdict: {v['description']}")
    else:
        ps = ", ".join(f"{k}={_fmt(x)}" for k, x in v["parameters"].items())
        lines.append(f"Verdict: {v['effect']} — {v['description']} ({ps}); "
                     f"BIC drop {v['score']:.1f}, held-out RMSE {100 * v['heldout_improvement']:.1f}% lower "
                     f"(held-out gain {v['heldout_gain']:.1f})")
        if v.get("ambiguous_with"):
            lines.append(f"  not clearly better than: {', '.join(v['ambiguous_with'])} (BIC within 6)")
    lines.append("Calibration (without the effect):")
    for k, p in d["calibration"]["parameters"].items():
        lo, hi = p["interval95"] or (None, None)
        lines.append(f"  {k} = {_fmt(p['value'])} ± {_fmt(p['stderr'])}  [95%: {_fmt(lo)}, {_fmt(hi)}]")
    if d["where"]:
        lines.append("Where the residual exceeds the noise:")
        for w in d["where"][:8]:
            if w["kind"] == "time":
                lines.append(f"  time {w['start']:.4g}–{w['end']:.4g}: rms {w['rms_over_noise']:.2f}x noise "
                             f"(p={w['p_value']:.2g})")
            elif w["kind"] == "frequency":
                lines.append(f"  band {w['lo_hz']:.4g}–{w['hi_hz']:.4g} Hz (peak {w['peak_hz']:.4g}): "
                             f"power {w['power_over_noise']:.1f}x noise (p={w['p_value']:.2g})")
            else:
                lines.append(f"  region x {w['x'][0]:.3g}–{w['x'][1]:.3g}, y {w['y'][0]:.3g}–{w['y'][1]:.3g}: "
                             f"rms {w['rms_over_noise']:.2f}x noise (p={w['p_value']:.2g})")
    else:
        lines.append("Where: nowhere does the residual exceed the noise significantly.")
    lines.append("Candidates (score = BIC drop; a verdict needs score > 10 and held-out gain > 6):")
    for c in d["candidates"][:6]:
        hi = "" if c["heldout_gain"] is None else \
            f", held-out RMSE {100 * c['heldout_improvement']:+.1f}%, gain {c['heldout_gain']:.1f}"
        lines.append(f"  {c['effect']:<22} score {c['score']:9.1f}{hi}")
    b, a = d["fit"]["before"], d["fit"]["after"]
    lines.append(f"{'':22}{'before':>12}{'after':>12}")
    for key in ("residual_rms", "heldout_rmse", "bic"):
        lines.append(f"  {key:<20}{_fmt(b[key]):>12}{_fmt(a[key]):>12}")
    if "bias_of_calibration" in a:
        lines.append("Calibration bias from leaving the effect out (without -> with):")
        for k, s in a["bias_of_calibration"].items():
            lines.append(f"  {k}: {_fmt(s['without_effect'])} -> {_fmt(s['with_effect'])}"
                         f" ({_fmt(s['shift_in_stderr'])} stderr)")
    return "\n".join(lines)


def plot(res, out) -> None:
    """Figure: data with both fits, residual before/after, and the flagged locations."""
    import numpy as np

    from odnn_sep.report.figures import pyplot, save_figure

    plt = pyplot()
    base = res.calibration.fit
    after = base if res.verdict is None else res.verdict.fit
    t, y = res.t, res.y
    if t.ndim == 2:
        fig, ax = plt.subplots(1, 3, figsize=(13, 4))
        for a, (vals, title) in zip(ax, [(y, "data"), (base.residual, "residual before"),
                                         (after.residual, "residual after")], strict=True):
            sc = a.scatter(t[:, 0], t[:, 1], c=vals, s=8, cmap="RdBu_r" if "res" in title else "viridis")
            fig.colorbar(sc, ax=a)
            a.set_title(title)
        for w in res.where:
            ax[1].add_patch(plt.Rectangle((w["x"][0], w["y"][0]), w["x"][1] - w["x"][0], w["y"][1] - w["y"][0],
                                          fill=False, ec="k", lw=1.5))
    else:
        fig, ax = plt.subplots(3, 1, figsize=(10, 8), sharex=True)
        ax[0].plot(t, y, ".", ms=2, color="0.5", label="data")
        ax[0].plot(t, base.prediction + base.disturbance, lw=1, label="calibrated model")
        if res.verdict is not None:
            ax[0].plot(t, after.prediction + after.disturbance, lw=1, label=f"+ {res.verdict.effect}")
        ax[0].legend(loc="best", fontsize=8)
        ax[1].plot(t, base.residual, lw=0.7, label=f"before (rms {base.rms:.3g})")
        ax[1].plot(t, after.residual, lw=0.7, label=f"after (rms {after.rms:.3g})")
        ax[1].legend(loc="best", fontsize=8)
        ax[1].set_ylabel("residual")
        for w in res.where:
            if w["kind"] == "time":
                for a in ax[:2]:
                    a.axvspan(w["start"], w["end"], color="red", alpha=0.1)
        # where: residual RMS over the noise level per window, before and after
        sigma = res.noise_sigma or 1.0
        nw = int(np.clip(len(t) // 50, 4, 20))
        edges = np.linspace(0, len(t), nw + 1).astype(int)
        for fit_, lab in ((base, "before"), (after, "after")):
            vals = [np.sqrt(np.mean(fit_.residual[a:b] ** 2)) / sigma for a, b in zip(edges[:-1], edges[1:],
                                                                                     strict=True)]
            ax[2].step(np.r_[t[edges[:-1]], t[-1]], vals + vals[-1:], where="post", label=lab)
        ax[2].axhline(1.0, color="k", lw=0.7, ls="--")
        ax[2].set_ylabel("residual RMS / noise")
        ax[2].legend(loc="best", fontsize=8)
        if np.any(base.disturbance):
            ax[0].plot(t, base.disturbance + np.mean(y), lw=0.8, color="C2", label="disturbance (shifted)")
            ax[0].legend(loc="best", fontsize=8)
        ax[2].set_xlabel("t")
        title = "verdict: " + (res.verdict.effect if res.verdict else "nothing missing")
        ax[0].set_title(title)
    save_figure(fig, out)
