"""Table 1 rows for the two engineering systems (power grid, humanoid reward), via their own recipes.

They need optional packages (pandapower; gymnasium[mujoco]); a row is left out when its package is
missing. Cells follow recipes/table1.py's header.
"""
from __future__ import annotations

import importlib.util

import numpy as np

SYSTEM_PAPER = {"power_grid": ("Power grids", 0.49), "humanoid": ("Robotics", 1.68)}
_NEEDS = {"power_grid": ("pandapower",), "humanoid": ("gymnasium", "mujoco")}


def available() -> list[str]:
    """System rows whose optional packages are installed."""
    return [n for n, mods in _NEEDS.items() if all(importlib.util.find_spec(m) for m in mods)]


def _fmt(v) -> str:
    v = [x for x in v if np.isfinite(x)]
    return f"{np.mean(v):.3g} ± {np.std(v):.2g}" if v else "—"


def system_row(name: str, *, quick: bool, snr_db: float) -> list:
    """One Table 1 row: dataset, class, ODNN exact, bound, network, DNN, PINN, OLS, SINDy, φ, width,
    paper, target."""
    paper, half = SYSTEM_PAPER[name][0], SYSTEM_PAPER[name][1] / 2
    if name == "power_grid":
        import power_grid as pg

        # the grid keeps its own meter-grade noise (60 dB); 30 dB leaves every line set-identified
        r = pg.run_case("case14", [100] if quick else [100, 101, 102], snapshots=40 if quick else pg.SNAPSHOTS,
                        snr_db=60.0, epochs=30 if quick else 400, progress=lambda s: None)
        ours = [x for x in r["point"] if np.isfinite(x)]
        target = (f"{'met' if ours and np.mean(ours) <= half else 'not met'} "
                  f"({np.mean(ours) if ours else float('nan'):.3g} vs {half:.3g}, point-identified lines)")
        width = (f"{np.median(r['n_set']):.0f} of {np.median(r['n_point']) + np.median(r['n_set']):.0f} line "
                 f"coefficients set-identified; topology exact {sum(r['topo'])}/{len(r['topo'])}")
        return ["power_grid (case14, 60 dB)", "Convex per bus in v_i (none at buses without load)",
                _fmt(r["point"]) + " (point-identified)", "none (set-identified class)", "—", _fmt(r["regular_dnn"]), _fmt(r["pinn_penalty"]), _fmt(r["ols"]),
                _fmt(r["sindy"]), "—", width, f"{SYSTEM_PAPER[name][1]:.2f} ({paper})", target]
    import humanoid as hu

    size = dict(policies=4, episodes=1, steps=60) if quick else dict(policies=8, episodes=2, steps=100)
    r = hu.identify("sin", [100] if quick else list(range(100, 105)), snr_db=snr_db, epochs=20 if quick else 500,
                    size=size)
    target = f"{'met' if np.mean(r['odnn']) <= half else 'not met'} ({np.mean(r['odnn']):.3g} vs {half:.3g})"
    return ["humanoid (sin z)", "Subspace (functions of z_after)", _fmt(r["odnn"]), f"{np.mean(r['bound']):.3g}", "—", _fmt(r["regular_dnn"]),
            _fmt(r["pinn_penalty"]), _fmt(r["ols"]), "—", "—", "point-identified",
            f"{SYSTEM_PAPER[name][1]:.2f} ({paper})", target]
