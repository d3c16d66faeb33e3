"""Figure for a generic separation: data and parts (1-D) or the three fields (2-D)."""
from __future__ import annotations

import numpy as np

from odnn_sep.report.figures import pyplot, save_figure


def plot_separation(x, y, res, grid_shape, out) -> None:
    plt = pyplot()
    if grid_shape is None:
        order = np.argsort(x)
        fig, ax = plt.subplots(2, 1, figsize=(8, 5.5), sharex=True)
        ax[0].plot(x[order], y[order], ".", ms=2, color="0.5", label="data")
        ax[0].plot(x[order], res.physics[order], lw=1.5, label="physics")
        ax[0].plot(x[order], res.disturbance[order], lw=1.2, label="disturbance")
        ax[0].legend(loc="best", fontsize=8)
        ax[0].set_title(res.summary().splitlines()[0], fontsize=9)
        ax[1].plot(x[order], res.residual[order], lw=0.8, color="k")
        ax[1].set_ylabel("residual")
        ax[1].set_xlabel("x")
    else:
        fig, ax = plt.subplots(1, 4, figsize=(14, 3.4))
        for a, (title, v) in zip(ax, [("data", y), ("physics", res.physics), ("disturbance", res.disturbance),
                                       ("residual", res.residual)]):
            im = a.imshow(v.reshape(grid_shape), origin="lower", cmap="inferno")
            a.set_title(title)
            fig.colorbar(im, ax=a, shrink=0.8)
    save_figure(fig, out)
