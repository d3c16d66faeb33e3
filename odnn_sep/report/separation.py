"""Figure for a generic separation: data and parts (1-D) or the fields (2-D).

1-D: the data, the physics with a shaded band (the physics over the 95 % intervals of theta, or over
the identified set for cone classes), the disturbance, and the residual below, in the data's units.
2-D: data, physics and disturbance on one colour scale (so they can be compared), the residual on
its own, each with a labelled colour bar.
"""
from __future__ import annotations

import itertools

import numpy as np

from odnn_sep.report.figures import pyplot, save_figure

MAX_BAND_TERMS = 4  # the band's corners grow as 2**terms


def physics_band(F, res):
    """(low, high) of the physics over the corners of theta's intervals, or None if unavailable.

    Examples
    --------
    >>> from types import SimpleNamespace
    >>> lo, hi = physics_band(np.c_[np.ones(2), [0.0, 1.0]], SimpleNamespace(interval=[[1, 2], [0, 1]]))
    >>> lo.tolist(), hi.tolist()
    ([1.0, 1.0], [2.0, 3.0])
    """
    if F is None or res.interval is None:
        return None
    iv = np.asarray(res.interval, dtype=float).reshape(-1, 2)
    if iv.shape[0] != F.shape[1] or iv.shape[0] > MAX_BAND_TERMS or not np.isfinite(iv).all():
        return None
    curves = np.array([F @ np.array(c) for c in itertools.product(*iv)])
    return curves.min(0), curves.max(0)


def _band_label(res) -> str:
    if res.identified != "point":
        return "physics over the identified set of θ"
    return "physics over the 95 % intervals of θ"


def plot_separation(x, y, res, grid_shape, out, *, F=None, x_name="x", y_name="value") -> None:
    """Write the separation figure to ``out`` (atomic).

    Parameters
    ----------
    x, y : coordinates (n,) or (n, 2) and data (n,)
    res : core Result
    grid_shape : (ny, nx) for a 2-D field, None for a 1-D signal
    F : (n, k) basis matrix at ``x`` (draws the interval band in 1-D), optional
    x_name, y_name : axis names from the input file (units are those of the data)

    Examples
    --------
    >>> import os, tempfile
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 41); y = 2 * x + x**2
    >>> res = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, y).result_
    >>> out = os.path.join(tempfile.mkdtemp(), "fit.png")
    >>> plot_separation(x, y, res, None, out, F=np.c_[x])
    >>> os.path.getsize(out) > 0
    True
    """
    plt = pyplot()
    if grid_shape is None:
        fig = _plot_1d(plt, x, y, res, F, x_name, y_name)
    else:
        fig = _plot_2d(plt, x, y, res, grid_shape, y_name)
    save_figure(fig, out)


def _plot_1d(plt, x, y, res, F, x_name, y_name):
    order = np.argsort(x)
    fig, ax = plt.subplots(2, 1, figsize=(8, 5.8), sharex=True, height_ratios=(2.2, 1))
    ax[0].plot(x[order], y[order], ".", ms=2, color="0.55", label="data")
    band = physics_band(F, res)
    if band is not None:
        ax[0].fill_between(x[order], band[0][order], band[1][order], color="C0", alpha=0.25, lw=0,
                           label=_band_label(res))
    ax[0].plot(x[order], res.physics[order], lw=1.5, color="C0", label="physics (fitted θ)")
    ax[0].plot(x[order], res.disturbance[order], lw=1.2, color="C1", label=f"disturbance ({res.disturbance_class})")
    ax[0].legend(loc="best", fontsize=8)
    ax[0].set_ylabel(f"{y_name} (data units)")
    ax[0].set_title(res.summary().splitlines()[0], fontsize=9)
    ax[1].plot(x[order], res.residual[order], lw=0.8, color="k", label="residual = data − physics − disturbance")
    ax[1].axhline(0, color="0.7", lw=0.6)
    ax[1].legend(loc="best", fontsize=8)
    ax[1].set_ylabel(f"residual ({y_name} units)")
    ax[1].set_xlabel(f"{x_name} (data units)")
    for a in ax:
        a.ticklabel_format(useOffset=False, axis="both", style="plain")
    fig.tight_layout()
    return fig


def _plot_2d(plt, x, y, res, grid_shape, y_name):
    fig, ax = plt.subplots(1, 4, figsize=(15, 3.6))
    ext = [float(x[:, 0].min()), float(x[:, 0].max()), float(x[:, 1].min()), float(x[:, 1].max())]
    shared = np.concatenate([y, res.physics, res.disturbance])
    lo, hi = float(np.min(shared)), float(np.max(shared))
    r = float(np.max(np.abs(res.residual))) or 1e-12
    panels = [("data", y, (lo, hi), "inferno"), ("physics", res.physics, (lo, hi), "inferno"),
              ("disturbance", res.disturbance, (lo, hi), "inferno"),
              ("residual (own scale)", res.residual, (-r, r), "RdBu_r")]
    for a, (title, v, lim, cmap) in zip(ax, panels):
        im = a.imshow(v.reshape(grid_shape), origin="lower", cmap=cmap, extent=ext, aspect="auto", vmin=lim[0],
                      vmax=lim[1])
        a.set_title(title)
        a.set_xlabel("x")
        a.set_ylabel("y")
        cb = fig.colorbar(im, ax=a, shrink=0.85)
        cb.set_label(f"{y_name} (data units)")
    fig.tight_layout()
    return fig
