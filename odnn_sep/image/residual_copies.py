"""Copies of a mark left outside what was removed: tiled or repeated marks cut by the image border.

The residual mark (``residual.measure``) is read in the removed box only. A mark tiled over the image
has copies the search does not place: those cut by the border (``Prev`` at the right edge, ``only``
at the left) do not match the whole rendering. The output keeps them as they were, and a removal
that calls itself complete is then wrong.

The output's edge map (gradient magnitude, on a copy reduced so that the mark is about ``TEMPLATE_PX``
high, but its strokes at least ``STROKE_PX`` wide) is correlated with the edge map of one removed
copy's coverage, every placement overlapping the image by at least ``MIN_OVERLAP`` of the template's
edge energy (copies cut by the border included; the image is padded with zeros, the removed copies
are blanked), over the whole template window and over its part inside the image. A tiled mark of
which only some copies were found is caught the same way. The best ``N_PEAKS`` placements of each are
refined on the full-resolution output, and the best ``N_CHECKS`` are checked with the detection
statistic itself (``detect.detection_score``, the same held-out blend test and threshold that find
the mark) and a contrast of at least ``residual.VISIBLE_LEVELS``: a copy counts as left only when the
data there hold a blend of the mark's shape, so a photo that happens to have edges like the letters
does not. A copy found at a shift d from the removed one puts the tile's lattice at k d: those
places are checked too, and every copy found is counted.
"""
from __future__ import annotations

import numpy as np

# The template's smaller side on the reduced copy (pixels); the image is reduced with it.
TEMPLATE_PX = 48
# Largest side of the reduced copy (pixels): bounds the cost on large photos.
WORK_PX = 1200
# A placement must overlap the image by this share of the template's edge energy (a copy cut by the
# border down to about a quarter of its letters is still looked at).
MIN_OVERLAP = 0.2
# The reduced copy keeps the mark's strokes at least this wide (px): reduced to 1 px, as a 44 px serif
# text reduced to a 48 px template was, the edge correlation ranked photo edges above the copies.
STROKE_PX = 3.0
# Placements checked with the detection statistic (by each of two correlations), and the edge
# correlation they need first.
N_PEAKS = 6
MIN_CORR = 0.2
# Refined candidates checked with the detection statistic (the best by their edge correlation).
N_CHECKS = 10
# Multiples of a copy's shift looked at (a tiled mark's lattice), each way.
LATTICE_STEPS = 6


def _edges(g: np.ndarray) -> np.ndarray:
    """Gradient magnitude (Sobel) of a (h, w) float32 image smoothed over a pixel."""
    import cv2

    g = cv2.GaussianBlur(np.ascontiguousarray(g, dtype=np.float32), (0, 0), 1.0)
    return np.hypot(cv2.Sobel(g, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(g, cv2.CV_32F, 0, 1, ksize=3))


def _reduced_grey(y, f: float) -> np.ndarray:
    """The mean of the colour channels of ``y`` (array or ``io.FloatView``), reduced by ``f``."""
    import cv2

    H, W = y.shape[:2]
    w, h = max(1, round(W * f)), max(1, round(H * f))
    if hasattr(y, "reduced"):
        r = y.reduced(w, h) if f < 1 else y.full()
    else:
        r = np.asarray(y, dtype=np.float32)
        r = cv2.resize(r, (w, h), interpolation=cv2.INTER_AREA) if f < 1 else r
    r = np.asarray(r, dtype=np.float32)
    return r.mean(axis=2) if r.ndim == 3 else r


def _candidates(E: np.ndarray, T: np.ndarray, blank: np.ndarray, n: int) -> list[tuple[float, int, int]]:
    """(correlation, top, left) of the best ``n`` distinct placements of ``T`` on ``E`` (reduced
    pixels; negative or beyond the image for copies cut by the border), ``blank`` pixels excluded."""
    import cv2

    th, tw = T.shape
    Ep, Ip = padded_for_full_match(E, blank, T.shape)
    T2 = (T * T).astype(np.float32)
    seen = cv2.matchTemplate(Ip, T2, cv2.TM_CCORR) / max(float(T2.sum()), 1e-12)
    R = cv2.matchTemplate(Ep, T.astype(np.float32), cv2.TM_CCOEFF_NORMED)
    R[~np.isfinite(R) | (seen < MIN_OVERLAP)] = -1.0
    return best_peaks(R, (th, tw), n, MIN_CORR)


def padded_for_full_match(E: np.ndarray, blank: np.ndarray, shape: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """``E`` with its ``blank`` pixels zeroed, and the mask of the pixels kept, both padded with zeros by
    a template of ``shape`` less one on every side: every placement that overlaps the image, copies cut
    by the border included, is then a position of ``cv2.matchTemplate``.

    Examples
    --------
    >>> Ep, Ip = padded_for_full_match(np.ones((4, 5)), np.zeros((4, 5), bool), (3, 2))
    >>> Ep.shape, float(Ip.sum())
    ((8, 7), 20.0)
    """
    import cv2

    th, tw = shape
    E = np.where(blank, 0.0, E).astype(np.float32)
    inside = (~blank).astype(np.float32)
    pad = (th - 1, th - 1, tw - 1, tw - 1)
    return (cv2.copyMakeBorder(E, *pad, cv2.BORDER_CONSTANT, value=0),
            cv2.copyMakeBorder(inside, *pad, cv2.BORDER_CONSTANT, value=0))


def best_peaks(R: np.ndarray, shape: tuple[int, int], n: int, min_corr: float) -> list[tuple[float, int, int]]:
    """(correlation, top, left) of the best ``n`` distinct peaks of a full-mode correlation map ``R``
    of a template of ``shape`` (the image padded by the template's size less one on every side), each
    at least ``min_corr``. A peak blanks half the template's size around it, so that one copy is not
    counted twice. ``R`` is changed in place.

    Examples
    --------
    >>> R = np.full((10, 10), -1.0); R[2, 3] = 0.9; R[2, 4] = 0.8; R[7, 7] = 0.5
    >>> best_peaks(R, (4, 4), 3, 0.2)
    [(0.9, -1, 0), (0.5, 4, 4)]
    """
    th, tw = shape
    out = []
    ry, rx = max(1, th // 2), max(1, tw // 2)
    for _ in range(n):
        i, j = np.unravel_index(int(np.argmax(R)), R.shape)
        if R[i, j] < min_corr:
            break
        out.append((float(R[i, j]), int(i) - th + 1, int(j) - tw + 1))
        R[max(0, i - ry):i + ry + 1, max(0, j - rx):j + rx + 1] = -1.0
    return out


def _footprint(M: np.ndarray) -> np.ndarray:
    """Pixels of the removed copies, grown by 2 px (bool, the shape of ``M``)."""
    import cv2

    return cv2.dilate((M > 0.05).astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)


def _scale(Mc: np.ndarray, H: int, W: int) -> float:
    """The reduction of the output for the edge search: the template's smaller side ``TEMPLATE_PX``,
    but strokes kept at least ``STROKE_PX`` wide, and the image at most ``WORK_PX``.

    Examples
    --------
    >>> c = np.zeros((160, 250)); c[20:140, 10:14] = 1; c[20:24, 10:240] = 1
    >>> round(_scale(c, 512, 512), 2)    # 3.8 px strokes: reduced to 0.79, not to 48 / 160 = 0.3
    0.79
    """
    from odnn_sep.image.estimate import stroke_width

    th, tw = Mc.shape
    keep = STROKE_PX / max(stroke_width(Mc), 1.0)
    return float(min(1.0, max(TEMPLATE_PX / max(1, min(th, tw)), keep), WORK_PX / max(H, W)))


def _output_crop(y, out_box, box, sy0, sy1, sx0, sx1) -> np.ndarray:
    """(h, w, C) float64 output over rows ``sy0:sy1``, columns ``sx0:sx1``: the input with the restored
    ``box`` (``out_box``) where they overlap."""
    x0, y0, x1, y1 = box
    crop = np.array(y[sy0:sy1, sx0:sx1], dtype=np.float64)
    crop = crop[:, :, None] if crop.ndim == 2 else crop
    iy0, iy1, ix0, ix1 = max(sy0, y0), min(sy1, y1), max(sx0, x0), min(sx1, x1)
    if iy1 > iy0 and ix1 > ix0:
        crop[iy0 - sy0:iy1 - sy0, ix0 - sx0:ix1 - sx0] = out_box[iy0 - y0:iy1 - y0, ix0 - x0:ix1 - x0]
    return crop


def _refine(y, out_box, box, foot, Tf, a0, b0, dy, dx, r) -> tuple[int, int, float]:
    """The full-resolution shift (dy, dx) within ``r`` px of the given one where the output's edges best
    match the copy's edge template ``Tf`` (the reduced search places a copy only to 1 / f px, and the
    detection statistic needs it to a pixel: 0.76 at the copy, 0.01 two pixels off), and the normalised
    correlation there."""
    import cv2

    H, W = foot.shape
    th, tw = Tf.shape
    gy0, gx0 = a0 + dy - r - 2, b0 + dx - r - 2            # window, 2 px more for the edge filter
    gy1, gx1 = a0 + dy + th + r + 2, b0 + dx + tw + r + 2
    sy0, sy1, sx0, sx1 = max(0, gy0), min(H, gy1), max(0, gx0), min(W, gx1)
    if sy1 - sy0 < 3 or sx1 - sx0 < 3:
        return dy, dx, 0.0
    g = _output_crop(y, out_box, box, sy0, sy1, sx0, sx1).mean(axis=2).astype(np.float32)
    E = np.zeros((gy1 - gy0, gx1 - gx0), np.float32)
    E[sy0 - gy0:sy1 - gy0, sx0 - gx0:sx1 - gx0] = np.where(foot[sy0:sy1, sx0:sx1], 0.0, _edges(g))
    R = cv2.matchTemplate(E[2:-2, 2:-2], Tf.astype(np.float32), cv2.TM_CCORR_NORMED)
    R[~np.isfinite(R)] = -1.0
    i, j = np.unravel_index(int(np.argmax(R)), R.shape)
    return dy + int(i) - r, dx + int(j) - r, float(R[i, j])


def copies_left(y, out_box: np.ndarray, M: np.ndarray, box: tuple, *, copy_box: tuple | None = None,
                threshold: float | None = None, random_state=0) -> dict | None:
    """The copies of the mark still in the output outside the removed copies, or None.

    Parameters
    ----------
    y : np.ndarray or io.FloatView
        (H, W, C) float input in [0, 1] (outside ``box`` the output is the input).
    out_box : np.ndarray
        (h, w, C) the restored ``box``.
    M : np.ndarray
        (H, W) coverage of the removed mark (every copy removed).
    box : tuple of int
        (x0, y0, x1, y1) of the restored area (``out_box``).
    copy_box : tuple of int, optional
        (x0, y0, x1, y1) of one copy of the mark; its coverage is the template (default: all of ``M``).
    threshold : float, optional
        Detection threshold (default ``detect.THRESHOLD``).
    random_state : int, default 0
        Seed of the detection statistic's patch subset.

    Returns
    -------
    dict or None
        ``{"at": [x, y], "score": s, "contrast_levels": c, "count": n, "positions": [[x, y], ...]}``: the
        best scoring copy detected in the output (top-left corner of the copy's coverage, full-resolution
        pixels; negative where it runs off the image), and the number and top-left corners of all the
        copies detected (at most ``N_PEAKS`` looked at, best score first), or None.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_copies import copies_left
    >>> rng = np.random.default_rng(0)
    >>> I = 0.5 + 0.02 * rng.standard_normal((120, 200, 1))
    >>> c = np.zeros((30, 70)); c[5:25, 10:15] = 1; c[5:10, 5:65] = 1; c[20:25, 20:60] = 1
    >>> M = np.zeros((120, 200)); M[60:90, 60:130] = c            # the copy found and removed
    >>> other = np.zeros((120, 200)); other[5:35, 165:200] = c[:, :35]   # a copy cut by the border
    >>> y = (1 - 0.4 * (M + other)[..., None]) * I + 0.4 * (M + other)[..., None]
    >>> box = (56, 56, 134, 94); done = I[56:94, 56:134]
    >>> left = copies_left(y, done, M, box)
    >>> left["at"], left["count"]
    ([170, 10], 1)
    >>> y2 = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None]
    >>> copies_left(y2, done, M, box) is None
    True
    """
    import cv2

    from odnn_sep.image.border_copies import cut_candidates
    from odnn_sep.image.detect import THRESHOLD, detection_score
    from odnn_sep.image.residual import VISIBLE_LEVELS, contrast_levels

    threshold = THRESHOLD if threshold is None else threshold
    H, W = y.shape[:2]
    cx0, cy0, cx1, cy1 = copy_box if copy_box is not None else (0, 0, W, H)
    nz = np.nonzero(M[cy0:cy1, cx0:cx1] > 0.05)
    if not nz[0].size:
        return None
    a0, b0 = int(nz[0].min()) + cy0, int(nz[1].min()) + cx0
    a1, b1 = int(nz[0].max()) + 1 + cy0, int(nz[1].max()) + 1 + cx0
    th, tw = a1 - a0, b1 - b0
    Mc = np.ascontiguousarray(M[a0:a1, b0:b1], dtype=np.float32)
    f = _scale(Mc, H, W)
    T = _edges(cv2.resize(Mc, (max(1, round(tw * f)), max(1, round(th * f))), interpolation=cv2.INTER_AREA)
               if f < 1 else Mc)
    if min(T.shape) < 4 or not T.any():
        return None
    x0, y0, x1, y1 = box
    g = _reduced_grey(y, f)
    # the output, reduced: the input with the restored box pasted
    ry0, ry1, rx0, rx1 = round(y0 * f), round(y1 * f), round(x0 * f), round(x1 * f)
    if ry1 > ry0 and rx1 > rx0:
        ob = np.asarray(out_box, dtype=np.float32)
        ob = ob.mean(axis=2) if ob.ndim == 3 else ob
        g[ry0:ry1, rx0:rx1] = cv2.resize(ob, (rx1 - rx0, ry1 - ry0), interpolation=cv2.INTER_AREA) if f < 1 else ob
    foot = _footprint(M)
    blank = cv2.resize(foot.astype(np.uint8), (g.shape[1], g.shape[0]), interpolation=cv2.INTER_NEAREST) > 0 \
        if f < 1 else foot
    blank = cv2.dilate(blank.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    E = _edges(g)
    # two correlations: over the whole template window, and over the part inside the image only (a copy
    # cut by the border scores as its visible part matches; border_copies.cut_candidates)
    cands = _candidates(E, T, blank, N_PEAKS) + cut_candidates(E, T, blank, N_PEAKS, min_overlap=MIN_OVERLAP,
                                                                min_corr=MIN_CORR)
    Tf = _edges(Mc)
    # each candidate refined within the reduction's rounding, and within a quarter of the copy: the peak
    # of a copy cut by the border lies up to 16 px off it (a quarter of the template's smaller side)
    # (and where it was found: the output's edges can match better a few pixels off a copy than on it)
    radii = sorted({0, int(np.ceil(1.5 / f)) + 1, max(int(np.ceil(1.5 / f)) + 1, min(th, tw) // 4)})
    # the candidates refined first, and only the best ``N_CHECKS`` by their refined edge correlation
    # checked with the detection statistic (0.1 s each on a 12-megapixel photo)
    refined: list[tuple[float, int, int]] = []
    for _corr, top, left in cands:
        for rr in radii:
            dy, dx, corr = _refine(y, out_box, box, foot, Tf, a0, b0, round(top / f) - a0, round(left / f) - b0, rr)
            if not any(abs(dy - p) <= 3 and abs(dx - q) <= 3 for _c, p, q in refined):
                refined.append((corr, dy, dx))
    refined.sort(key=lambda c: -c[0])
    # (full-resolution shift of the copy from the removed one, search radius around it; 0: refined)
    queue = [(dy, dx, 0) for _c, dy, dx in refined[:N_CHECKS]]
    found: list[dict] = []
    tried: list[tuple[int, int]] = []
    mass = float(Mc.sum())
    while queue:
        dy, dx, rr = queue.pop(0)
        if rr:
            dy, dx, _corr = _refine(y, out_box, box, foot, Tf, a0, b0, dy, dx, rr)
        if (dy, dx) in tried or \
                any(abs(dy - c["shift"][0]) < th / 2 and abs(dx - c["shift"][1]) < tw / 2 for c in found):
            continue                                              # looked at already, or a copy found
        tried.append((dy, dx))
        sy0, sy1, sx0, sx1 = max(0, a0 + dy - 4), min(H, a1 + dy + 4), max(0, b0 + dx - 4), min(W, b1 + dx + 4)
        if sy1 - sy0 < 8 or sx1 - sx0 < 8:
            continue
        Ms = np.zeros((sy1 - sy0, sx1 - sx0))
        ya, xa = max(sy0, a0 + dy), max(sx0, b0 + dx)
        yb, xb = min(sy1, a1 + dy), min(sx1, b1 + dx)
        Ms[ya - sy0:yb - sy0, xa - sx0:xb - sx0] = M[ya - dy:yb - dy, xa - dx:xb - dx]
        Ms[foot[sy0:sy1, sx0:sx1]] = 0.0                         # no coverage over the removed copies
        if not (Ms > 0.5).any() or Ms.sum() < MIN_OVERLAP * mass:
            continue
        crop = _output_crop(y, out_box, box, sy0, sy1, sx0, sx1)
        s = detection_score(crop, Ms, random_state=random_state)
        if s < threshold:
            continue
        levels = contrast_levels(crop, Ms, random_state=random_state)
        if levels >= VISIBLE_LEVELS:
            found.append({"at": [int(b0 + dx), int(a0 + dy)], "score": round(float(s), 4),
                          "contrast_levels": round(float(levels), 2), "shift": (dy, dx)})
            # a tiled mark repeats on a lattice: a copy at shift d implies copies at k d, which the
            # edge correlation misses where the photo's own edges are stronger
            queue += [(k * dy, k * dx, 2) for k in range(-LATTICE_STEPS, LATTICE_STEPS + 1) if k not in (0, 1)
                      and -th < a0 + k * dy < H and -tw < b0 + k * dx < W]
    if not found:
        return None
    found.sort(key=lambda c: -c["score"])
    best = {k: v for k, v in found[0].items() if k != "shift"}
    return {**best, "count": len(found), "positions": [c["at"] for c in found]}


__all__ = ["copies_left", "LATTICE_STEPS", "STROKE_PX", "TEMPLATE_PX", "WORK_PX", "MIN_OVERLAP", "N_PEAKS", "N_CHECKS", "MIN_CORR"]
