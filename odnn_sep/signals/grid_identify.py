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

from odnn_sep.core.linalg import Z95

#: Relative interval width (of |estimate|) below which a coefficient is called point-identified.
POINT_WIDTH = 0.05


@dataclass(frozen=True)
class GridFit:
    """Estimates for every candidate line quantity (G and B of each measured pair, i < k).

    ``table`` rows: (name, bus i, bus k, true value, estimate, lo, hi, line present, point-identified),
    both ends combined (:func:`combine_ends`); ``per_row`` holds the single-equation rows.
    """

    table: tuple
    seconds: float
    per_row: tuple = ()

    def lines_found(self) -> set:
        """Candidate pairs (i, k) whose G or B interval, at a family-wise 5 % level, excludes zero.

        Every candidate pair is a test; with m pairs, chance alone would put some 95 % intervals of
        absent lines off zero, so the intervals are widened about their centres by
        ``z(1 - 0.025 / m) / z(0.975)`` (Bonferroni).
        """
        from scipy.stats import norm

        m = max(len({(r[1], r[2]) for r in self.table}), 1)
        factor = float(norm.ppf(1 - 0.025 / m) / Z95)
        out = set()
        for _name, i, k, _t, _e, lo, hi, _present, _pt in self.table:
            if not (np.isfinite(lo) and np.isfinite(hi)):
                continue
            c, h = 0.5 * (lo + hi), 0.5 * (hi - lo) * factor
            if not c - h <= 0 <= c + h:
                out.add((i, k))
        return out

    def topology_errors(self) -> list:
        """Candidate pairs reported wrongly: (i, k, truly present)."""
        pairs = {(i, k): present for _n, i, k, _t, _e, _lo, _hi, present, _pt in self.table}
        found = self.lines_found()
        return [(i, k, p) for (i, k), p in sorted(pairs.items()) if ((i, k) in found) != p]

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


def combine_ends(table) -> tuple:
    """One row per line quantity: the two bus equations of a line (i, k) both constrain G_ik = G_ki and
    B_ik = B_ki, so the identified set is the **intersection** of their intervals (centre reported).

    Where the two intervals do not overlap (noise), the hull between them is kept and the estimate is
    the mean of the two. Rows: (name, i, k, true, estimate, lo, hi, present, point-identified).
    """
    by_key = {}
    for name, i, k, t, e, lo, hi, present, _pt in table:
        by_key.setdefault((name[0], min(i, k), max(i, k)), []).append((t, e, lo, hi, present))
    out = []
    for (q, i, k), ends in sorted(by_key.items()):
        t, present = ends[0][0], ends[0][4]
        lo, hi = max(x[2] for x in ends), min(x[3] for x in ends)
        if lo <= hi:
            est = 0.5 * (lo + hi) if np.isfinite(lo) and np.isfinite(hi) else float(np.mean([x[1] for x in ends]))
        else:
            lo, hi = hi, lo
            est = float(np.mean([x[1] for x in ends]))
        width = (hi - lo) / max(abs(est), 1e-300)
        out.append((f"{q}[{i}-{k}]", i, k, t, est, lo, hi, present, bool(np.isfinite(width) and width <= POINT_WIDTH)))
    return tuple(out)


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
    return GridFit(table=combine_ends(rows), seconds=time.perf_counter() - t0, per_row=tuple(rows))
