"""Identify line parameters and topology from a :class:`~odnn_sep.signals.power_grid.GridDataset`.

Each complete bus equation is one ``Separator`` problem (x = v_i, class ``Convex()``); the core
returns the identified interval of every candidate G_ik and B_ik. A candidate line is reported
present when the interval of G_ik or B_ik excludes zero, absent when both contain zero. A coefficient
counts as **point-identified** when its interval is narrower than ``POINT_WIDTH`` of its value; the
rest are set-identified and reported only as intervals.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass

import numpy as np

#: Relative interval width (of |estimate|) below which a coefficient is called point-identified.
POINT_WIDTH = 0.05


@dataclass(frozen=True)
class GridFit:
    """Per-coefficient estimates for every usable bus row.

    ``table`` rows: (name, bus i, bus k, true value, estimate, lo, hi, line present, point-identified).
    """

    table: tuple
    seconds: float

    def lines_found(self) -> set:
        """Candidate pairs (i, k) whose G or B interval excludes zero."""
        out = set()
        for _name, i, k, _t, _e, lo, hi, _present, _pt in self.table:
            if not lo <= 0 <= hi:
                out.add((i, k))
        return out

    def topology_exact(self) -> bool:
        """Every true line found, no absent candidate reported."""
        pairs = {(i, k): present for _n, i, k, _t, _e, _lo, _hi, present, _pt in self.table}
        found = self.lines_found()
        return all((pair in found) == present for pair, present in pairs.items())

    def mape_point(self) -> float:
        """MAPE (%) over the point-identified coefficients of true lines (NaN if there are none)."""
        e = [abs(est - t) / abs(t) * 100 for _n, _i, _k, t, est, _lo, _hi, present, pt in self.table
             if present and pt and abs(t) > 0]
        return float(np.mean(e)) if e else float("nan")

    def mape_all(self) -> float:
        """MAPE (%) over every non-zero coefficient of a true line."""
        e = [abs(est - t) / abs(t) * 100 for _n, _i, _k, t, est, _lo, _hi, present, _pt in self.table
             if present and abs(t) > 0]
        return float(np.mean(e)) if e else float("nan")

    def counts(self) -> dict:
        """Numbers of true-line coefficients that are point- and set-identified."""
        true = [r for r in self.table if r[7] and abs(r[3]) > 0]
        return {"point": sum(r[8] for r in true), "set": sum(not r[8] for r in true)}


def _parse(name: str) -> tuple[int, int]:
    i, k = name[2:-1].split(",")
    return int(i), int(k)


def identify_grid(ds, *, solver: str = "exact", random_state: int = 0) -> GridFit:
    """Fit every bus row of ``ds`` with ``Separator(basis, Convex())`` and collect intervals.

    Parameters
    ----------
    ds : GridDataset
    solver : {"exact", "network"}
        Passed to :class:`odnn_sep.core.Separator`.
    random_state : int

    Returns
    -------
    GridFit
    """
    import time

    from odnn_sep.core import Separator

    t0 = time.perf_counter()
    rows = []
    for pr in ds.problems:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # set-identification warnings are reported in the table
            r = Separator(pr.basis, disturbance=pr.disturbance, solver=solver,
                          random_state=random_state).fit(pr.x, pr.y).result_
        lines = set(pr.extras["lines"])
        for name, est, (lo, hi) in zip(r.names, r.theta, r.interval):
            i, k = _parse(name)
            width = (hi - lo) / max(abs(est), 1e-300)
            rows.append((name, i, k, float(pr.theta_true[name]), float(est), float(lo), float(hi), k in lines,
                         bool(np.isfinite(width) and width <= POINT_WIDTH)))
    return GridFit(table=tuple(rows), seconds=time.perf_counter() - t0)
