"""The 2D heat-field preset: point sources (instant or continuous), an ambient level, several frames.

Field of source ``i`` (strength ``S_i``) at distance ``r`` and time ``t`` after it started:

- instant release (default): ``S_i exp(-r^2 / (4 alpha t)) / (4 pi alpha t)``;
- continuous source (``--param continuous=1``, a constant power switched on at t = 0):
  ``S_i E1(r^2 / (4 alpha t)) / (4 pi alpha)``, ``E1`` the exponential integral; at the source
  itself ``r^2`` is floored at ``1e-4 * 4 alpha t`` (the point source is singular there).

``--param ambient=1`` adds a fitted ambient level ``T_amb`` (physics: the field relaxes to it).
Several frames in time: frame ``k`` is taken at ``t + k * frame_dt`` and its points are stored
with ``x`` shifted by ``k * frame_dx`` (the reader sets both; one axis keeps the 2D machinery).

Effects: ``extra_source`` (a source the model lacks) and ``source_moved`` (a given source sits
elsewhere: source ``k_src`` displaced by ``dx_src, dy_src``). An extra source is never placed on
top of a given one: it acts at least ``R = sqrt(alpha t)`` (half the kernel's 1/e radius, first
frame) away from every given source (:func:`extra_position`), so what is found closer is a moved
(or misjudged) given source.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.mismatch.presets_base import INF, Preset

R2_FLOOR = 1e-4     # continuous source: r^2 floored at this fraction of 4 alpha t


def kernel(r2, alpha, t, continuous=False):
    """Field of a unit source at squared distance ``r2`` after time ``t`` (instant or continuous).

    Examples
    --------
    >>> import numpy as np
    >>> round(float(kernel(np.array([0.0]), 0.01, 1.0)[0]), 4)          # 1 / (4 pi 0.01)
    7.9577
    >>> round(float(kernel(np.array([0.04]), 0.01, 1.0, continuous=True)[0]), 4)   # E1(1) / (4 pi 0.01)
    1.7458
    """
    s2 = 4.0 * alpha * t
    if not continuous:
        return np.exp(-r2 / s2) / (np.pi * s2)
    from scipy.special import exp1
    return exp1(np.maximum(r2, R2_FLOOR * s2) / s2) / (4.0 * np.pi * alpha)


def frames(xy, p):
    """``(x, y, t)`` of every point: frame ``k = round(x / frame_dx)`` at time ``t + k frame_dt``.

    Examples
    --------
    >>> import numpy as np
    >>> x, y, t = frames(np.array([[0.2, 0.1], [10.2, 0.1]]), {"t": 1.0, "frame_dx": 10.0, "frame_dt": 0.5})
    >>> x.round(6).tolist(), t.tolist()
    ([0.2, 0.2], [1.0, 1.5])
    """
    x, y = xy[:, 0], xy[:, 1]
    dx = float(p.get("frame_dx", 0.0))
    if dx <= 0:
        return x, y, np.full(len(x), float(p["t"]))
    k = np.rint(x / dx)
    return x - k * dx, y, float(p["t"]) + k * float(p.get("frame_dt", 0.0))


class Heat2D(Preset):
    """2D heat field from point sources sampled at points ``xy`` (shape (n, 2)); see the module docstring.

    Examples
    --------
    >>> import numpy as np
    >>> pre = Heat2D()
    >>> p = {**pre.params, "sources": "0.5:0.5", "S1": 1.0}
    >>> z = pre.build(())(np.array([[0.5, 0.5], [0.9, 0.5]]), p)
    >>> z.shape, round(float(z[0]), 4)
    ((2,), 7.9577)
    >>> pre.extra_params({"ambient": 1.0})
    {'T_amb': 0.0}
    """

    name = "heat2d"
    family = "heat2d"
    description = ("2D heat field at time t from point sources: "
                   "sum_i S_i exp(-r_i^2 / (4 alpha t)) / (4 pi alpha t) (+ T_amb with ambient=1)")
    params = {"alpha": 0.01, "t": 1.0, "sources": "0.5:0.5", "continuous": 0.0, "ambient": 0.0,
              "frame_dt": 0.0, "frame_dx": 0.0}
    bounds = {"alpha": (1e-12, INF)}
    fixed = frozenset({"t", "sources", "continuous", "ambient", "frame_dt", "frame_dx"})
    native = frozenset({"extra_source", "offset", "source_moved"})
    ndim = 2

    def extra_params(self, start):
        """Parameters the structural settings add: the ambient level ``T_amb`` when ``ambient`` is on."""
        return {"T_amb": 0.0} if float(start.get("ambient", 0.0)) else {}

    def build(self, effects):
        effects = frozenset(effects) & self.native

        def predict(xy, p):
            x, y, tt = frames(xy, p)
            srcs = [list(s) for s in parse_sources(p["sources"])]
            if "source_moved" in effects:
                k = int(round(p["k_src"])) - 1
                if 0 <= k < len(srcs):
                    srcs[k] = [srcs[k][0] + p["dx_src"], srcs[k][1] + p["dy_src"]]
            cont = bool(p.get("continuous", 0.0))
            terms = [(sx, sy, p[f"S{i + 1}"]) for i, (sx, sy) in enumerate(srcs)]
            if "extra_source" in effects:
                terms.append((*extra_position(p), p["S_extra"]))
            out = np.zeros(len(xy))
            for sx, sy, S in terms:
                out += S * kernel((x - sx) ** 2 + (y - sy) ** 2, p["alpha"], tt, cont)
            out += p.get("T_amb", 0.0)
            if "offset" in effects:
                out += p["offset"]
            return out

        return predict

    def canonical(self, effects, p):
        """An extra source found in another frame's copy of the plane is the same source in frame 0."""
        dx = float(p.get("frame_dx", 0.0))
        if "extra_source" not in effects or dx <= 0 or abs(p["xs"]) <= 0.5 * dx:
            return None
        return {**p, "xs": p["xs"] - np.rint(p["xs"] / dx) * dx}

    def initial_guess(self, xy, z, p):
        p = {**self.params, **p}
        srcs = parse_sources(p["sources"])
        x, y, tt = frames(xy, p)
        t_ref = float(np.min(tt))
        ext = max(np.ptp(x), np.ptp(y))
        amb = bool(float(p.get("ambient", 0.0)))
        best = None
        for a in np.geomspace(1e-4, 1.0, 40) * ext ** 2 / t_ref:
            cols = [kernel((x - sx) ** 2 + (y - sy) ** 2, a, tt, bool(p["continuous"])) for sx, sy in srcs]
            F = np.column_stack(cols + ([np.ones(len(z))] if amb else []))
            coef = solve(F, z, method="lstsq")
            rss = float(np.sum((F @ coef - z) ** 2))
            if best is None or rss < best[0]:
                best = (rss, a, coef)
        out = {"alpha": float(best[1])}
        out.update({f"S{i + 1}": float(c) for i, c in enumerate(best[2][:len(srcs)])})
        if amb:
            out["T_amb"] = float(best[2][-1])
        return out


def extra_position(p):
    """Where the extra source acts: ``(xs, ys)``, kept at least ``R = sqrt(alpha t)`` from every given source.

    Within ``2 R`` of the nearest given source the distance ``s`` is mapped smoothly to
    ``R + s^2 / (4 R)`` (same value and slope at ``2 R``, at least ``R`` on top of the source), so
    the extra source never sits on a given one and a fit started there still moves; beyond ``2 R``
    the position is ``(xs, ys)`` itself.

    Examples
    --------
    >>> p = {"alpha": 0.01, "t": 1.0, "sources": "0.5:0.5", "xs": 0.5, "ys": 0.5}
    >>> [round(float(v), 3) for v in extra_position(p)]                 # on top: pushed out to R = 0.1
    [0.6, 0.5]
    >>> [round(float(v), 3) for v in extra_position({**p, "xs": 0.8})]    # beyond 2 R: unchanged
    [0.8, 0.5]
    """
    R = np.sqrt(p["alpha"] * float(p["t"]))
    xs, ys = float(p["xs"]), float(p["ys"])
    dx = float(p.get("frame_dx", 0.0))
    shift = np.rint(xs / dx) * dx if dx > 0 else 0.0
    xs -= shift
    sx, sy = min(parse_sources(p["sources"]), key=lambda s: (xs - s[0]) ** 2 + (ys - s[1]) ** 2)
    s = float(np.hypot(xs - sx, ys - sy))
    if s >= 2 * R:
        return xs + shift, ys
    ux, uy = ((xs - sx) / s, (ys - sy) / s) if s > 1e-12 else (1.0, 0.0)
    s_eff = R + s * s / (4 * R)
    return sx + s_eff * ux + shift, sy + s_eff * uy


def moved_starts(p, r, tt, base, model, t):
    """Starts of ``source_moved``: for each given source, the least-squares displacement (one linear step).

    Parameters
    ----------
    p : dict
        Calibrated parameters.
    r : ndarray
        Calibrated residual.
    tt : None
        (time series only; unused).
    base : Fit
        Calibration.
    model : Model
        The model with the effect.
    t : ndarray (n, 2)
        Coordinates.

    Returns
    -------
    list of dict
        One start per given source, the best-fitting first.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> g = np.linspace(0, 1, 15); X, Y = np.meshgrid(g, g); xy = np.column_stack([X.ravel(), Y.ravel()])
    >>> base = make_model("heat2d", {"sources": "0.3:0.4;0.7:0.6", "S1": 1.0, "S2": 0.7})
    >>> moved = base.with_effect("source_moved", {"k_src": 2.0, "dx_src": 0.02, "dy_src": 0.0})
    >>> cal = fit(base, xy, moved.predict(xy))
    >>> s = moved_starts(cal.params, cal.residual, None, cal, base.with_effect("source_moved"), xy)[0]
    >>> s["k_src"], round(s["dx_src"], 2), abs(round(s["dy_src"], 2))
    (2.0, 0.02, 0.0)
    """
    out = []
    q0 = {**model.start, **p, "dx_src": 0.0, "dy_src": 0.0}
    h = 1e-4 * max(np.ptp(np.asarray(t)[:, 1]), 1e-9)
    for k in range(1, len(parse_sources(p["sources"])) + 1):
        q = {**q0, "k_src": float(k)}
        f0 = model.predict(t, q)
        cols = np.column_stack([(model.predict(t, {**q, "dx_src": h}) - f0) / h,
                                (model.predict(t, {**q, "dy_src": h}) - f0) / h])
        d = solve(cols, r, method="lstsq")
        gain = float(np.sum((cols @ d) ** 2))
        out.append((gain, {**p, "k_src": float(k), "dx_src": float(d[0]), "dy_src": float(d[1])}))
    out.sort(key=lambda g: -g[0])
    return [s for _, s in out]


def parse_sources(spec):
    """Parse ``"x:y;x:y"`` into a list of (x, y) floats.

    Parameters
    ----------
    spec : str or sequence of pairs
        Source positions, ``"x:y"`` pairs separated by ``;`` (or already a list of pairs).

    Returns
    -------
    list of tuple of float
        The source positions.

    Raises
    ------
    InputError
        When ``spec`` is malformed or empty.

    Examples
    --------
    >>> parse_sources("0.3:0.4; 0.6:0.5")
    [(0.3, 0.4), (0.6, 0.5)]
    """
    from odnn_sep.errors import InputError
    if isinstance(spec, (list, tuple)):
        return [(float(a), float(b)) for a, b in spec]
    out = []
    for part in str(spec).split(";"):
        part = part.strip()
        if not part:
            continue
        try:
            a, b = part.split(":")
            out.append((float(a), float(b)))
        except ValueError:
            raise InputError(f"sources must be x:y pairs separated by ';' (e.g. 0.3:0.4;0.6:0.5); "
                             f"got {spec!r}") from None
    if not out:
        raise InputError(f"sources must name at least one x:y pair; got {spec!r}")
    return out
