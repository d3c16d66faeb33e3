"""Copies of a tiled text mark cut by the image border, found and registered so they are removed too.

A mark tiled over a photo (a stock photo's diagonal grid of "SAMPLE") has copies that the image border
cuts: the search (``locate.search``, ``locate.repeats``) matches whole renderings inside the image and
never places them. They stayed in the output, which ``residual_copies`` then rightly called still
visible (exit 3): on a 451 x 300 photo with one whole copy and eight cut ones, nothing could be
removed at all.

Once one copy is registered, the others are the same rendering (font, size, angle) elsewhere. Its edge
map is correlated with the input's over every placement that overlaps the image by at least
``residual_copies.MIN_OVERLAP`` of its edge energy (the image padded with zeros, the copies already
placed blanked; ``residual_copies``' search, on the input instead of the output). Each candidate is
registered by its position only (the blend model's residual, as ``register.refine``, with the size
and angle held at the found copy's) and kept when the held-out detection statistic on the part inside
the image reaches ``CUT_FACTOR`` times the threshold: a part of a copy is less data than a whole one,
and many placements were tried, so it must stand out further (as a later look of the search must).
"""
from __future__ import annotations

import numpy as np

# A cut copy counts at this multiple of the detection threshold (the search's later looks use 1.3).
CUT_FACTOR = 1.3
# At most this many candidate placements are looked at.
MAX_CANDIDATES = 24
# A candidate is registered only when its detection score before registration reaches this multiple
# of the threshold (a copy placed a pixel off still scores well above it: 1.3 in the first example).
PRESCREEN = 0.5


def _template(text, p):
    """(coverage of the whole rendering of placement ``p`` (h, w), its centre (x, y) in that array)."""
    from odnn_sep.image.register import render_at
    from odnn_sep.image.render import render_text

    side = int(np.ceil(np.hypot(*render_text(text, p.font, p.size).shape))) + 8
    c = (side / 2.0, side / 2.0)
    m, (x0, y0, _, _) = render_at(text, p.font, p.size, p.angle, c, (side, side))
    return np.asarray(m, dtype=np.float32), (c[0] - x0, c[1] - y0)


def cut_candidates(E: np.ndarray, T: np.ndarray, blank: np.ndarray, n: int, *, min_overlap: float = 0.2,
                   min_corr: float = 0.2) -> list[tuple[float, int, int]]:
    """(correlation, top, left) of the best ``n`` distinct placements of the edge template ``T`` on the
    edge map ``E``, placements cut by the border included, ``blank`` pixels left out.

    The correlation is normalised by the template's energy over the part inside the image only (and
    the image's under it): a copy cut by the border then scores as its visible part matches, where a
    correlation over the whole template window (``cv2.TM_CCOEFF_NORMED`` on the zero-padded map) drew
    its peak towards placements that put more of the template inside, 25 px off a copy cut in half.
    (It favours small overlaps in turn; the lattice of a tile, ``lattice_points``, finds what it misses.)

    Examples
    --------
    >>> import numpy as np
    >>> T = np.zeros((10, 20)); T[2:8, 3:17] = np.arange(1, 7)[:, None]
    >>> E = np.zeros((40, 60)); E[-4:, 10:24] = T[2:6, 3:17]      # a copy's top, cut by the bottom border
    >>> cut_candidates(E, T, np.zeros(E.shape, bool), 1)[0][1:]
    (34, 7)
    """
    import cv2

    from odnn_sep.image.residual_copies import best_peaks, padded_for_full_match

    th, tw = T.shape
    Ep, Ip = padded_for_full_match(E, blank, T.shape)
    T = T.astype(np.float32)
    t_in = cv2.matchTemplate(Ip, T * T, cv2.TM_CCORR)                       # the template's energy inside
    e_in = cv2.matchTemplate(Ep * Ep, (T > 0).astype(np.float32), cv2.TM_CCORR)  # the image's under it
    R = cv2.matchTemplate(Ep, T, cv2.TM_CCORR) / np.sqrt(np.maximum(t_in * e_in, 1e-12))
    # (FFT round-off leaves tiny sums where the image has no edges under the template: not a match)
    R[~np.isfinite(R) | (t_in < min_overlap * float((T * T).sum())) | (e_in <= 1e-4 * float(e_in.max()))] = -1.0
    return best_peaks(R, (th, tw), n, min_corr)


def _register_shift(y, text, p, center, random_state):
    """The placement of ``p``'s rendering near ``center``, its position refined by the blend residual
    (size and angle held); None when the crop holds no edge patches."""
    from odnn_sep.errors import NotIdentifiableError
    from odnn_sep.image.estimate import fit_blend
    from odnn_sep.image.register import Placed, _objective, nelder_mead, render_at
    from odnn_sep.image.render import place, render_text

    H, W = y.shape[:2]
    _, box = render_at(text, p.font, p.size, p.angle, center, (H, W))
    if box[2] <= box[0] or box[3] <= box[1]:
        return None
    pad = 4
    bx = (max(0, box[0] - pad), max(0, box[1] - pad), min(W, box[2] + pad), min(H, box[3] + pad))
    crop = np.asarray(y[bx[1]:bx[3], bx[0]:bx[2]], dtype=np.float64)
    crop = crop[:, :, None] if crop.ndim == 2 else crop
    upright = render_text(text, p.font, p.size)
    local = (center[0] - bx[0], center[1] - bx[1])
    shape = crop.shape[:2]

    def cov(q):
        m, (a0, b0, a1, b1) = place(upright, shape, (local[0] + q[0], local[1] + q[1]), p.angle)
        full = np.zeros(shape)
        full[b0:b1, a0:a1] = m
        return full

    M = cov(np.zeros(2))
    if M.max() <= 0.5:
        return None
    try:
        fit0 = fit_blend(crop, M, random_state=random_state)
        obj = _objective(crop, M, fit0, cov, lambda q: (upright, (local[0] + q[0], local[1] + q[1]), p.angle),
                         random_state)
        if obj is not None:
            q, f = nelder_mead(obj, np.zeros(2), np.array([0.5, 0.5]), 40)
            if f <= obj(np.zeros(2)) and np.hypot(*q) < 3.0:
                M = cov(q)
                center = (center[0] + float(q[0]), center[1] + float(q[1]))
        fit = fit_blend(crop, M, random_state=random_state)
    except NotIdentifiableError:
        return None
    return Placed(p.font, p.size, p.angle, center, bx, M, fit)


def border_copies(y, text: str, placed: list, max_new: int, min_score: float, *, random_state=0) -> list:
    """Registered copies of the mark ``placed[0]`` that the border cuts (or the search missed).

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    placed : list of Placed
        The copies registered so far (``placed[0]``: the template).
    max_new : int
        Most copies added.
    min_score : float
        The detection threshold; a cut copy needs ``CUT_FACTOR`` times it.
    random_state : int or Generator, default 0
        Seed of the fits.

    Returns
    -------
    list of Placed
        The copies found, each with its box clipped to the image.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.register import refine
    >>> from odnn_sep.image.synth import add_text_watermark, photo_like
    >>> clean = photo_like((200, 260), random_state=1)
    >>> y, _ = add_text_watermark(clean, "SAMPLE", size=30, center=(130, 100), alpha=0.5, tile=(150, 0))
    >>> y = y / 255.0      # copies centred at x -20 and 280 are cut by the border
    >>> p = refine(y, "SAMPLE", "DejaVuSans-Bold", 30, 0.0, (130, 100))
    >>> sorted(round(q.center[0]) for q in border_copies(y, "SAMPLE", [p], 8, 0.19))
    [-20, 280]
    """
    import cv2

    from odnn_sep.image.detect import detection_score
    from odnn_sep.image.register import render_at
    from odnn_sep.image.residual_copies import MIN_OVERLAP, TEMPLATE_PX, WORK_PX, _edges, _reduced_grey

    if max_new <= 0 or not placed:
        return []
    H, W = y.shape[:2]
    best = placed[0]
    T, (tcx, tcy) = _template(text, best)
    th, tw = T.shape
    f = min(1.0, TEMPLATE_PX / max(1, min(th, tw)), WORK_PX / max(H, W))
    g = _reduced_grey(y, f)
    fy, fx = g.shape[0] / H, g.shape[1] / W
    Tr = cv2.resize(T, (max(1, round(tw * fx)), max(1, round(th * fy))), interpolation=cv2.INTER_AREA) if f < 1 else T
    Te = _edges(Tr)
    if min(Te.shape) < 4 or not Te.any():
        return []
    foot = np.zeros((H, W), np.uint8)
    for q in placed:
        x0, y0, x1, y1 = q.box
        foot[y0:y1, x0:x1] |= (q.coverage > 0.05).astype(np.uint8)
    foot = cv2.dilate(foot, np.ones((5, 5), np.uint8))
    blank = cv2.resize(foot, (g.shape[1], g.shape[0]), interpolation=cv2.INTER_NEAREST) > 0 if f < 1 else foot > 0
    # the template's centre on the reduced grid: sx = (x + 0.5) * fx - 0.5 for full-resolution x
    rcx, rcy = (tcx + 0.5) * Tr.shape[1] / tw - 0.5, (tcy + 0.5) * Tr.shape[0] / th - 0.5
    out: list = []
    near = 0.35 * min(th, tw)

    def consider(c) -> None:
        if len(out) >= max_new or any(np.hypot(c[0] - q.center[0], c[1] - q.center[1]) < near for q in placed + out):
            return
        m, (x0, y0, x1, y1) = render_at(text, best.font, best.size, best.angle, c, (H, W))
        if m.size == 0 or m.max() <= 0.5 or m.sum() < MIN_OVERLAP * T.sum():
            return
        # a first look where it is put (a pixel or so off on the reduced grid): only a place that
        # already holds a blend of the mark's shape is registered (each registration costs a fit)
        if detection_score(y[y0:y1, x0:x1], m, random_state=random_state) < PRESCREEN * min_score:
            return
        q = _register_shift(y, text, best, c, random_state)
        if q is not None and detection_score(y[q.box[1]:q.box[3], q.box[0]:q.box[2]], q.coverage,
                                             random_state=random_state) >= CUT_FACTOR * min_score:
            out.append(q)

    for _corr, top, left in cut_candidates(_edges(g), Te, blank, MAX_CANDIDATES, min_overlap=MIN_OVERLAP):
        consider(((left + rcx + 0.5) / fx - 0.5, (top + rcy + 0.5) / fy - 0.5))
    # a tile is a lattice: the places it predicts from the copies found (a copy cut to a corner draws
    # the correlation peak off its place, 16 px in the first example above)
    for c in lattice_points([q.center for q in placed + out], (W, H), (tw, th)):
        consider(c)
    return out


def lattice_points(centres, size, extent, tol: float = 2.5) -> list:
    """Centres (x, y) that the lattice through ``centres`` places where a copy of ``extent`` (w, h)
    overlaps an image of ``size`` (W, H), those already in ``centres`` left out; [] when fewer than
    two centres, or when they do not lie on one lattice within ``tol`` px (all of them, or all but one).

    Examples
    --------
    >>> pts = lattice_points([(100, 50), (300, 50), (200, 150)], (400, 200), (60, 20))
    >>> sorted((round(x), round(y)) for x, y in pts)
    [(0, 150), (400, 150)]
    >>> lattice_points([(10, 10), (50, 13), (90, 30)], (400, 200), (20, 10))
    []
    """
    c = np.asarray(centres, dtype=float)
    out = _lattice_points(c, size, extent, tol)
    if not out and len(c) > 3:
        # a copy registered off its place (on the letters of a copy cut by the border) breaks the
        # lattice: the others, without it
        for k in range(len(c)):
            out = _lattice_points(np.delete(c, k, axis=0), size, extent, tol)
            if out:
                return [q for q in out if np.hypot(c[:, 0] - q[0], c[:, 1] - q[1]).min() > tol]
    return out


def _lattice_points(c, size, extent, tol):
    if len(c) < 2:
        return []
    d = c[1:] - c[0]
    d = d[np.argsort(np.hypot(d[:, 0], d[:, 1]))]
    u = d[0]
    if np.hypot(*u) < 1.0:
        return []
    others = [v for v in d[1:] if abs(u[0] * v[1] - u[1] * v[0]) > 0.3 * np.hypot(*u) * np.hypot(*v)]
    basis = np.array([u, others[0]]).T if others else None
    rel = c - c[0]
    # the copies' indices on the lattice, then its vectors fitted to all of them by least squares (one
    # neighbour's offset is a pixel off, and that error grows with every step out)
    if basis is None:   # one row of copies
        K = np.round(rel @ u / (u @ u))[:, None]
    else:
        K = np.round(np.linalg.solve(basis, rel.T).T)
    if np.linalg.matrix_rank(K) < K.shape[1]:
        return []
    fitted = np.linalg.lstsq(K, rel, rcond=None)[0]          # (1 or 2, 2): the lattice vectors as rows
    if np.abs(rel - K @ fitted).max() > tol:
        return []
    if basis is None:
        u = fitted[0]
        basis = np.array([u, [-u[1], u[0]]]).T   # the second direction unused (only j = 0 below)
        rows = [0]
    else:
        basis = fitted.T
        rows = None
    W, H = size
    reach = np.hypot(W, H) + np.hypot(*extent)
    n = int(np.ceil(reach / max(1.0, min(np.hypot(*basis[:, 0]), np.hypot(*basis[:, 1]))))) + 1
    out = []
    for i in range(-n, n + 1):
        for j in rows if rows is not None else range(-n, n + 1):
            x, y = c[0] + basis @ np.array([i, j], dtype=float)
            if -extent[0] / 2 < x < W + extent[0] / 2 and -extent[1] / 2 < y < H + extent[1] / 2 \
                    and np.hypot(c[:, 0] - x, c[:, 1] - y).min() > tol:
                out.append((float(x), float(y)))
    return out


__all__ = ["border_copies", "cut_candidates", "lattice_points", "CUT_FACTOR", "MAX_CANDIDATES", "PRESCREEN"]
