"""Copies of a mark left outside what was removed: tiled or repeated marks cut by the image border.

The residual mark (``residual.measure``) is read in the removed box only. A mark tiled over the image
has copies the search does not place: those cut by the border (``Prev`` at the right edge, ``only``
at the left) do not match the whole rendering. The output keeps them as they were, and a removal
that calls itself complete is then wrong.

The output's edge map (gradient magnitude, on a copy reduced so that the mark is at most
``TEMPLATE_PX`` high) is correlated with the edge map of one removed copy's coverage, every placement
overlapping the image by at least ``MIN_OVERLAP`` of the template's edge energy (copies cut by the
border included; the image is padded with zeros, the removed copies are blanked). A tiled mark of
which only some copies were found is caught the same way. The best ``N_PEAKS`` distinct placements are then checked with the detection statistic
itself (``detect.detection_score``, the same held-out blend test and threshold that find the mark) and
a contrast of at least ``residual.VISIBLE_LEVELS``: a copy counts as left only when the data there
hold a blend of the mark's shape, so a photo that happens to have edges like the letters does not.
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
# Placements checked with the detection statistic, and the edge correlation they need first.
N_PEAKS = 6
MIN_CORR = 0.2


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


def copies_left(y, out_box: np.ndarray, M: np.ndarray, box: tuple, *, copy_box: tuple | None = None,
                threshold: float | None = None, random_state=0) -> dict | None:
    """The best copy of the mark still in the output outside the removed copies, or None.

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
        ``{"at": [x, y], "score": s, "contrast_levels": c}`` of a copy detected in the output (top-left
        corner of the copy's coverage, full-resolution pixels; negative where it runs off the image),
        or None.

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
    >>> copies_left(y, done, M, box)["at"]
    [170, 10]
    >>> y2 = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None]
    >>> copies_left(y2, done, M, box) is None
    True
    """
    import cv2

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
    f = min(1.0, TEMPLATE_PX / max(1, min(th, tw)), WORK_PX / max(H, W))
    Mc = np.ascontiguousarray(M[a0:a1, b0:b1], dtype=np.float32)
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
    for _corr, top, left in _candidates(_edges(g), T, blank, N_PEAKS):
        dy, dx = round(top / f) - a0, round(left / f) - b0      # full-resolution shift of the copy
        sy0, sy1, sx0, sx1 = max(0, a0 + dy - 4), min(H, a1 + dy + 4), max(0, b0 + dx - 4), min(W, b1 + dx + 4)
        if sy1 - sy0 < 8 or sx1 - sx0 < 8:
            continue
        Ms = np.zeros((sy1 - sy0, sx1 - sx0))
        ya, xa = max(sy0, a0 + dy), max(sx0, b0 + dx)
        yb, xb = min(sy1, a1 + dy), min(sx1, b1 + dx)
        Ms[ya - sy0:yb - sy0, xa - sx0:xb - sx0] = M[ya - dy:yb - dy, xa - dx:xb - dx]
        Ms[foot[sy0:sy1, sx0:sx1]] = 0.0                         # no coverage over the removed copies
        crop = np.array(y[sy0:sy1, sx0:sx1], dtype=np.float64)
        crop = crop[:, :, None] if crop.ndim == 2 else crop
        iy0, iy1, ix0, ix1 = max(sy0, y0), min(sy1, y1), max(sx0, x0), min(sx1, x1)
        if iy1 > iy0 and ix1 > ix0:                              # the output where the box overlaps
            crop[iy0 - sy0:iy1 - sy0, ix0 - sx0:ix1 - sx0] = out_box[iy0 - y0:iy1 - y0, ix0 - x0:ix1 - x0]
        if not (Ms > 0.5).any():
            continue
        s = detection_score(crop, Ms, random_state=random_state)
        if s < threshold:
            continue
        levels = contrast_levels(crop, Ms, random_state=random_state)
        if levels >= VISIBLE_LEVELS:
            return {"at": [int(b0 + dx), int(a0 + dy)], "score": round(float(s), 4),
                    "contrast_levels": round(float(levels), 2)}
    return None


__all__ = ["copies_left", "TEMPLATE_PX", "WORK_PX", "MIN_OVERLAP", "N_PEAKS", "MIN_CORR"]
