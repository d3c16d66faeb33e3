"""Identify line parameters and topology from a :class:`~odnn_sep.signals.power_grid.GridDataset`.

Each complete bus equation is a ``Separator`` problem (x = v_i, class ``Convex()``, or none at a bus
without customer load). The record is cut into pieces of ``chunk`` snapshots (a few days each) and
every piece is fitted on its own: the core returns the identified interval of every candidate G_ik
and B_ik per piece. The pieces, and the two bus equations that share a line, are then combined by
inverse-variance weighting (:func:`combine`): each interval is read as estimate +- 1.96 standard
errors, and the combined interval is widened by the Birge ratio when the pieces disagree more than
their widths allow. Why pieces: the cone fit's cost grows faster than linearly with the number of
samples, and weeks of 15-minute data are what makes the estimates precise.

A candidate line is reported present when the combined interval of G_ik or B_ik excludes zero at a
family-wise 5 % level. A coefficient counts as **point-identified** when its combined interval is
narrower than ``POINT_WIDTH`` of its value and every piece bounded it; the rest are set-identified
(or unbounded) and reported only as intervals.
"""
from __future__ import annotations

import warnings
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.core.linalg import Z95, noise_variance, solve, stderr_from_cov
from odnn_sep.errors import InputError

#: Relative interval width (of |estimate|) above which a coefficient is never called point-identified.
POINT_WIDTH = 0.05
#: Largest ratio of a piece's identified half-width to the half-width the metering noise alone gives
#: (same columns, no disturbance class beyond its free constant and line) for a point-identified coefficient.
NOISE_RATIO = 2.0


@dataclass(frozen=True)
class GridFit:
    """Estimates for every candidate line quantity (G and B of each measured pair, i < k).

    ``table`` rows: (name, bus i, bus k, true value, estimate, lo, hi, line present, point-identified),
    pieces and both ends combined (:func:`combine`); ``per_row`` holds one row per bus equation
    (pieces combined, ends apart).

    Attributes
    ----------
    table : tuple of tuple
        One row per line quantity, as above.
    seconds : float
        Time the fit took.
    per_row : tuple of tuple
        One row per bus-equation quantity, same layout.
    bias : dict
        Single-fit name -> first-order bias from voltage noise (:func:`voltage_noise_bias`).

    Examples
    --------
    >>> table = (("G[0-1]", 0, 1, 4.0, 4.02, 3.98, 4.06, True, True),
    ...          ("B[0-1]", 0, 1, -12.0, -11.9, -12.3, -11.5, True, False),
    ...          ("G[0-2]", 0, 2, 0.0, 0.01, -0.05, 0.07, False, False),
    ...          ("B[0-2]", 0, 2, 0.0, 0.02, -0.1, 0.14, False, False))
    >>> fit = GridFit(table=table, seconds=0.1)
    >>> fit.lines_found(), fit.topology_exact(), fit.topology_errors()
    ({(0, 1)}, True, [])
    >>> round(fit.mape_point(), 3), round(fit.mape_all(), 3), fit.counts()
    (0.5, 0.667, {'point': 1, 'set': 1})
    """

    table: tuple
    seconds: float
    per_row: tuple = ()
    bias: dict = field(default_factory=dict)

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

    def mape_point(self, quantity: str | None = None) -> float:
        """MAPE (%) over the point-identified coefficients of true lines (NaN if there are none);
        ``quantity`` "G" or "B" restricts it to conductances or susceptances."""
        e = [abs(est - t) / abs(t) * 100 for name, _i, _k, t, est, _lo, _hi, present, pt in self.table
             if present and pt and abs(t) > 0 and quantity in (None, name[0])]
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


#: Snapshots per separately fitted piece of the record (three days of 15-minute data).
CHUNK = 288


def combine(rows, key, bias: dict | None = None) -> tuple:
    """Combine estimates of the same quantity (pieces of the record, ends of a line) by inverse variance.

    Parameters
    ----------
    rows : iterable of tuples
        (name, i, k, true, estimate, lo, hi, present, noise ratio) for single fits (the ratio of the
        identified half-width to the noise-only half-width, see :func:`noise_only_stderr`).
    key : callable
        Row -> (name, i, k) of the combined quantity.
    bias : dict, optional
        Single-fit name -> first-order bias from voltage noise (:mod:`odnn_sep.signals.grid_eiv`):
        every estimate is shifted by it, and the combined interval widened by the weighted |bias|.

    Returns
    -------
    tuple of (name, i, k, true, estimate, lo, hi, present, point-identified), sorted by key.
    Each piece's half-width is split (:func:`split_half_width`) into the part its metering noise
    explains (standard error = that part / 1.96) and the rest, which the disturbance class leaves
    open. The estimates are weighted by the inverse noise variance; the combined standard error is
    multiplied by ``max(1, sqrt(chi2 / (m - 1)))`` (Birge ratio) of the m estimates. The combined
    half-width is 1.96 combined standard errors **plus** the weighted mean of the pieces' remaining
    parts and of their |voltage-noise bias|: what the class or the voltage noise can shift in every
    piece alike is not averaged away by more pieces. An unbounded piece leaves the quantity to the
    bounded ones; with none bounded the quantity is unbounded. Point-identified: every piece
    bounded, every piece's noise ratio at most ``NOISE_RATIO``, the bias from voltage noise smaller
    than the noise half-width, combined width below ``POINT_WIDTH`` of the estimate.

    Examples
    --------
    Two pieces of bus 0's equation and one of bus 1's, for the same line:

    >>> rows = [("G[0,1]", 0, 1, 4.0, 4.1, 3.9, 4.3, True, 1.0),
    ...         ("G[0,1]", 0, 1, 4.0, 3.9, 3.7, 4.1, True, 1.0),
    ...         ("G[1,0]", 1, 0, 4.0, 4.0, 3.8, 4.2, True, 1.0)]
    >>> [(r[0], r[4], round(r[5], 3), round(r[6], 3)) for r in combine(rows, line_key)]
    [('G[0-1]', 4.0, 3.885, 4.115)]
    >>> [(r[0], round(r[5], 3), round(r[6], 3)) for r in combine(rows, equation_key)]
    [('G[0,1]', 3.804, 4.196), ('G[1,0]', 3.8, 4.2)]
    """
    bias = bias or {}
    groups = {}
    for r in rows:
        groups.setdefault(key(r), []).append(r)
    return tuple(_combine_group(name, i, k, grp, bias) for (name, i, k), grp in sorted(groups.items()))


def _combine_group(name, i, k, grp, bias) -> tuple:
    """One combined row of :func:`combine` from the single-fit rows ``grp`` of one quantity."""
    t, present = grp[0][3], grp[0][7]
    fin = [r for r in grp if np.isfinite(r[5]) and np.isfinite(r[6])]
    if not fin:
        return (name, i, k, t, float(np.mean([r[4] for r in grp])), -np.inf, np.inf, present, False)
    b = np.array([bias.get(r[0], 0.0) for r in fin])
    noise_half, set_half = split_half_width([(r[6] - r[5]) / 2 for r in fin], [r[8] for r in fin])
    se_each = noise_half / Z95
    est, se = _inverse_variance(np.array([r[4] for r in fin]) - b, se_each)
    w = 1.0 / np.maximum(se_each, 1e-300) ** 2
    widen = float(np.sum(w * np.abs(b)) / np.sum(w))  # voltage-noise bias, itself estimated
    systematic = float(np.sum(w * set_half) / np.sum(w))  # what the class leaves open in a piece
    half = Z95 * se + systematic + widen
    point = (len(fin) == len(grp) and all(r[8] <= NOISE_RATIO for r in grp) and widen <= Z95 * se
             and 2 * half <= POINT_WIDTH * abs(est))
    return (name, i, k, t, est, float(est - half), float(est + half), present, bool(point))


def split_half_width(half, ratio) -> tuple[np.ndarray, np.ndarray]:
    """Split identified half-widths into the part the metering noise explains and the rest.

    A piece's identified interval is the noise interval of its point estimate widened by the range
    the disturbance class leaves open (a set). Combining pieces shrinks the first like
    1/sqrt(pieces), never the second: the same class imitates the same column in every piece.

    Parameters
    ----------
    half : sequence of float
        Identified half-widths, one per piece.
    ratio : sequence of float
        Each piece's ratio of its half-width to the noise-only half-width (:func:`noise_only_stderr`);
        NaN or a value <= 1 counts the whole half-width as noise.

    Returns
    -------
    noise_half, set_half : ndarray
        ``half / max(ratio, 1)`` and the remainder ``half - noise_half``.

    Examples
    --------
    >>> noise, rest = split_half_width([2.0, 1.0, 3.0], [2.0, 0.8, float("nan")])
    >>> noise.tolist(), rest.tolist()
    ([1.0, 1.0, 3.0], [1.0, 0.0, 0.0])
    """
    h = np.asarray(half, dtype=float)
    q = np.asarray(ratio, dtype=float)
    q = np.where(np.isfinite(q), np.maximum(q, 1.0), 1.0)
    noise = h / q
    return noise, h - noise


def _inverse_variance(values, stderr) -> tuple[float, float]:
    """Weighted mean and its standard error, widened by the Birge ratio when the values disagree."""
    c = np.asarray(values, dtype=float)
    w = 1.0 / np.maximum(np.asarray(stderr, dtype=float), 1e-300) ** 2
    sol = solve(np.ones((c.size, 1)), c, weights=w, return_cov=True)
    est = float(sol.theta[0])
    birge2 = noise_variance(c - est, c.size - 1, w) if c.size > 1 else 1.0
    return est, float(np.sqrt(sol.cov_unscaled[0, 0] * max(1.0, birge2)))


def noise_only_stderr(F: np.ndarray, x: np.ndarray, sigma) -> np.ndarray:
    """Standard errors the metering noise alone would give: least squares on the physics columns with
    the convex class's free part (a constant and a line in x), at the fitted noise level ``sigma``.

    A coefficient whose identified interval is about this wide is limited by noise only (point-
    identified); a much wider one is limited by what the disturbance class can imitate (set-identified).

    Parameters
    ----------
    F : (n, p) ndarray
        Physics columns of the bus equation.
    x : (n,) ndarray
        The class's coordinate (v_i).
    sigma : float or None
        Fitted noise standard deviation; None or NaN gives NaN errors.

    Returns
    -------
    (p,) ndarray
        Standard error of each column's coefficient.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0.95, 1.05, 50)
    >>> F = np.c_[np.sin(20 * x), np.cos(30 * x)]
    >>> noise_only_stderr(F, x, 0.01).round(4).tolist()
    [0.013, 0.019]
    >>> noise_only_stderr(F, x, None).tolist()
    [nan, nan]
    """
    if sigma is None or not np.isfinite(sigma):
        return np.full(F.shape[1], np.nan)
    sol = solve(np.c_[F, np.ones_like(x), x], np.zeros_like(x), return_cov=True)
    return stderr_from_cov(sol.cov_unscaled, float(sigma) ** 2)[:F.shape[1]]


def line_key(row) -> tuple:
    """Both ends of line (i, k) as one quantity ``G[i-k]`` / ``B[i-k]`` with i < k.

    Parameters
    ----------
    row : tuple
        A single-fit row ``(name, i, k, ...)`` (see :func:`combine`).

    Returns
    -------
    tuple
        ``(name, i, k)`` of the line, ends sorted.

    Examples
    --------
    >>> line_key(("G[3,1]", 3, 1)), line_key(("B[1,3]", 1, 3))
    (('G[1-3]', 1, 3), ('B[1-3]', 1, 3))
    """
    i, k = min(row[1], row[2]), max(row[1], row[2])
    return (f"{row[0][0]}[{i}-{k}]", i, k)


def equation_key(row) -> tuple:
    """One quantity per bus equation (pieces of the record combined, ends kept apart).

    Parameters
    ----------
    row : tuple
        A single-fit row ``(name, i, k, ...)`` (see :func:`combine`).

    Returns
    -------
    tuple
        ``(name, i, k)`` as in the row.

    Examples
    --------
    >>> equation_key(("G[3,1]", 3, 1, 4.0))
    ('G[3,1]', 3, 1)
    """
    return (row[0], row[1], row[2])


def parse_name(name: str) -> tuple[int, int]:
    """``"G[3,4]"`` -> (3, 4).

    Parameters
    ----------
    name : str
        A coefficient name of a bus equation, ``G[i,k]`` or ``B[i,k]``.

    Returns
    -------
    tuple of int
        The bus ``i`` of the equation and the candidate neighbour ``k``.

    Examples
    --------
    >>> parse_name("G[3,4]"), parse_name("B[12,0]")
    ((3, 4), (12, 0))
    """
    i, k = name[2:-1].split(",")
    return int(i), int(k)


def fit_pieces(pr, chunk: int, *, solver: str = "exact", random_state: int = 0) -> list:
    """Fit one bus equation piece by piece: one single-fit row per piece and candidate coefficient.

    Parameters
    ----------
    pr : Dataset
        One bus equation of a :class:`~odnn_sep.signals.power_grid.GridDataset`.
    chunk : int
        Snapshots per piece (the record is split into ``n // chunk`` near-equal pieces, at least one).
    solver : {"exact", "network"}
    random_state : int

    Returns
    -------
    list of tuple
        ``(name, i, k, true, estimate, lo, hi, present, noise ratio)`` as :func:`combine` takes them.

    Examples
    --------
    >>> from odnn_sep.signals.power_grid import three_bus_chain
    >>> ds, names = three_bus_chain()
    >>> rows = fit_pieces(ds.problems[0], 60)
    >>> len(rows), rows[0][:3]
    (4, ('G[1,0]', 1, 0))
    """
    from odnn_sep.core import Basis, Separator

    F, lines, rows = pr.design(), set(pr.extras["lines"]), []
    for part in np.array_split(np.arange(pr.y.size), max(1, pr.y.size // chunk)):
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # set-identification warnings are reported in the table
            r = Separator(Basis.from_matrix(F[part], pr.basis.names), disturbance=pr.disturbance,
                          solver=solver, random_state=random_state).fit(pr.x[part], pr.y[part]).result_
        ratio = r.stderr / noise_only_stderr(F[part], pr.x[part], r.diagnostics.get("sigma"))
        # the least-squares point of a cone fit, not the centre of its identified interval: the
        # centre is shifted towards the side the class leaves open, alike in every piece, while
        # the least-squares point scatters about the truth with the noise (averages out)
        point = r.diagnostics.get("theta_least_squares", r.theta)
        for name, est, (lo, hi), q in zip(r.names, point, r.interval, ratio):
            i, k = parse_name(name)
            rows.append((name, i, k, float(pr.theta_true[name]), float(est), float(lo), float(hi),
                         k in lines, float(q)))
    return rows


def identify_grid(ds, *, chunk: int = CHUNK, solver: str = "exact", random_state: int = 0) -> GridFit:
    """Fit every bus equation of ``ds`` piece by piece with ``Separator`` and combine the intervals.

    Parameters
    ----------
    ds : GridDataset
    chunk : int
        Snapshots per separately fitted piece (the record is split into ``n // chunk`` near-equal
        pieces, at least one).
    solver : {"exact", "network"}
        Passed to :class:`odnn_sep.core.Separator`.
    random_state : int

    Returns
    -------
    GridFit

    Raises
    ------
    odnn_sep.errors.InputError
        For a ``chunk`` that is not an integer >= 2.

    Examples
    --------
    A three-bus chain (lines 0-1, 1-2) with bus 1's equation complete, its candidates 0 and 2
    (:func:`~odnn_sep.signals.power_grid.three_bus_chain`):

    >>> from odnn_sep.signals.power_grid import three_bus_chain
    >>> ds, names = three_bus_chain()
    >>> fit = identify_grid(ds, chunk=60)
    >>> [(name, round(est, 2), point) for name, _i, _k, _t, est, _lo, _hi, _pr, point in fit.table]
    [('B[0-1]', 12.0, True), ('B[1-2]', 15.0, True), ('G[0-1]', -4.0, True), ('G[1-2]', -5.0, True)]
    >>> sorted(fit.lines_found()), fit.topology_exact()
    ([(0, 1), (1, 2)], True)
    """
    import time

    if isinstance(chunk, bool) or not isinstance(chunk, (int, np.integer)) or chunk < 2:
        raise InputError(f"chunk must be an integer number of snapshots >= 2; got {chunk!r}")
    t0 = time.perf_counter()
    rows = [row for pr in ds.problems for row in fit_pieces(pr, chunk, solver=solver, random_state=random_state)]
    bias = voltage_noise_bias(ds, rows)
    return GridFit(table=combine(rows, line_key, bias), seconds=time.perf_counter() - t0,
                   per_row=combine(rows, equation_key, bias), bias=bias)


def voltage_noise_bias(ds, rows) -> dict:
    """Single-fit name -> first-order bias from the voltage noise, at each equation's combined estimate.

    Parameters
    ----------
    ds : GridDataset
        The record (its ``sigma_v`` and ``sigma_delta`` are the meters' noise levels).
    rows : list of tuple
        Single-fit rows, as for :func:`combine`.

    Returns
    -------
    dict
        Coefficient name -> bias (empty when the voltages are noise-free).

    Examples
    --------
    A three-bus chain (lines 0-1, 1-2) with bus 1's equation complete, its candidates 0 and 2
    (:func:`~odnn_sep.signals.power_grid.three_bus_chain`):

    >>> from odnn_sep.signals.power_grid import three_bus_chain
    >>> ds, names = three_bus_chain(sigma_meter=1e-4)
    >>> rows = [(nm, 1, k, 0.0, est, est - 0.1, est + 0.1, True, 1.0)
    ...         for nm, k, est in zip(names, [0, 0, 2, 2], [-4.0, 12.0, -5.0, 15.0])]
    >>> bias = voltage_noise_bias(ds, rows)
    >>> sorted(bias), all(abs(b) < 0.01 for b in bias.values())
    (['B[1,0]', 'B[1,2]', 'G[1,0]', 'G[1,2]'], True)
    """
    from odnn_sep.signals.grid_eiv import column_jacobian, regressor_noise_bias

    if ds.sigma_v == 0 and ds.sigma_delta == 0:
        return {}
    est = {r[0]: r[4] for r in combine(rows, equation_key)}
    nb = ds.G.shape[0]
    v, delta = np.zeros((ds.v.shape[0], nb)), np.zeros((ds.v.shape[0], nb))
    v[:, list(ds.measured)], delta[:, list(ds.measured)] = ds.v, ds.delta
    out = {}
    for pr in ds.problems:
        i, names = pr.extras["bus"], pr.basis.names
        others = [parse_name(nm)[1] for nm in names[::2]]
        b = regressor_noise_bias(pr.design(), pr.x, column_jacobian(v, delta, i, others), ds.sigma_v,
                                 ds.sigma_delta, np.array([est[nm] for nm in names]),
                                 free_part=pr.identified == "set")
        out.update(zip(names, b.tolist()))
    return out
