"""Make docs/figure.png for the README: Proposition 1 (regular DNN vs ODNN) and a set-identified case.

Run: python recipes/readme_figure.py
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))


def main() -> None:
    from odnn_sep.core import Basis, Convex, Separator
    from odnn_sep.core.baselines import regular_dnn
    from odnn_sep.errors import IdentifiabilityWarning
    from odnn_sep.report.figures import pyplot, save_figure
    from odnn_sep.signals import make_dataset

    ds = make_dataset("figure2", theta={"theta": 0.5}, random_state=0)
    F = ds.basis.evaluate(ds.x)
    ode = Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y).result_
    th_dnn = regular_dnn(ds.x, ds.y, F, random_state=0)
    plt = pyplot()
    fig, ax = plt.subplots(1, 3, figsize=(14, 3.8))
    ax[0].plot(ds.x, ds.y, ".", ms=2, color="0.6", label="data y")
    ax[0].plot(ds.x, ds.physics, "k", lw=2.5, label="true physics 0.5 x² sin 5x")
    ax[0].plot(ds.x, ode.physics, "C0--", lw=1.6, label=f"ODNN (Even class): θ = {ode.theta[0]:.4f}")
    ax[0].plot(ds.x, F[:, 0] * th_dnn[0], "C3", lw=1.2, label=f"regular DNN (Eq. 2): θ = {th_dnn[0]:.3f}")
    ax[0].set_title("Proposition 1: an unconstrained network absorbs physics")
    ax[0].legend(fontsize=7, loc="lower left")
    ax[1].plot(ds.x, ds.disturbance_true, "k", lw=2.5, label="true disturbance cos x")
    ax[1].plot(ds.x, ode.disturbance, "C0--", lw=1.6, label="ODNN disturbance (even part)")
    ax[1].set_title("the disturbance estimate")
    ax[1].legend(fontsize=7)
    x = np.linspace(-2, 2, 401)
    y = x ** 2 + np.sin(5 * x)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", IdentifiabilityWarning)
        r = Separator(Basis([lambda x: np.sin(5 * x)], names=["c"]), disturbance=Convex()).fit(x, y).result_
    lo, hi = r.interval[0]
    for c, col in ((lo, "C2"), (hi, "C1")):
        ax[2].plot(x, y - c * np.sin(5 * x), color=col, lw=1.4, label=f"g = y − {c:.3f} sin 5x (convex)")
    ax[2].plot(x, y, ".", ms=1.5, color="0.6", label="y = x² + sin 5x")
    ax[2].set_title(f"Convex class: θ only set-identified, [{lo:.3f}, {hi:.3f}]")
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    save_figure(fig, ROOT / "docs" / "figure.png")
    print(f"ODNN theta {ode.theta[0]:.5f}, regular DNN theta {th_dnn[0]:.4f}, convex set [{lo:.4f}, {hi:.4f}]")


if __name__ == "__main__":
    main()
