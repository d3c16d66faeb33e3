"""Reference-image (logo) mode of ``unwatermark``: find the user's logo, fit its opacity, undo the blend.

The blend is ``y = (1 - alpha M) I + alpha M L``. For a one-colour logo, ``L`` is a colour fitted as
in text mode (``estimate.fit_blend``: the photo a plane per edge patch, projected out). For a logo
with several colours, ``L`` is the logo's own colours and only ``alpha`` is fitted, by the same
likelihood of the restored photo (``logo_colour.ColouredProfile``). The logo counts as found when the blend
predicts the edge patches out of sample (``detect.detection_score``: the opacity fitted on one half
of the mark predicts the other half) with a score of at least ``MIN_SCORE``; then the blend is
inverted and only pixels whose information is gone are inpainted. What is left of the mark in the
output is measured by ``residual.residual_mark``.
"""
from __future__ import annotations

import logging
import time

import numpy as np

from odnn_sep.errors import MarkNotFoundError
from odnn_sep.image.logo import Placement, prepare_logo, render
from odnn_sep.image.logo_colour import coloured_detection_score, fit_coloured

log = logging.getLogger(__name__)

# Found: the held-out detection score (``detect.detection_score``, or ``coloured_detection_score``)
# reaches this (chosen on development seeds of recipes/bench_logo.py: clean photos searched for
# absent logos vs watermarked ones).
MIN_SCORE = 0.19
# Coarse matches refined and judged by the blend model, per level of the pyramid (half by each rank).
N_CANDIDATES = 6


def _fit(crop, M, L, coloured, random_state):
    """(alpha, colour (C,) or None for the logo's own colours, explained)."""
    from odnn_sep.image.estimate import fit_blend

    if coloured:
        a, e = fit_coloured(crop, M, L, random_state=random_state)
        return a, None, e
    f = fit_blend(crop, M, random_state=random_state)
    return f.alpha, f.color, f.explained


def locate(y, logo, angle_range: float, max_copies: int, judge) -> list[tuple[Placement, float]]:
    """Placements of the logo in ``y`` (float array or ``io.FloatView``) with ``judge(placement)``
    (the blend's explained share), best first. The best ``N_CANDIDATES`` distinct coarse matches are
    refined and judged by the blend model, not by the edge correlation alone (small templates reach
    high correlations by chance); tiled copies of the winner are refined and judged too.

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    logo : Logo
        The prepared logo.
    angle_range : float
        Largest rotation, degrees either way.
    max_copies : int
        Most placements returned.
    judge : callable
        ``judge(placement)``: the detection score of a placement.

    Returns
    -------
    list of tuple
        (Placement, judged score), the best first, then its tiled copies.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> from odnn_sep.image.refmode import locate
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96, 1), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M[..., None] * (L - 0.3)
    >>> [(round(p.cx), round(p.cy), round(p.scale, 1)) for p, _ in locate(photo, logo, 0.0, 1, lambda p: p.score)]
    [(40, 30, 1.0)]
    """
    from odnn_sep.image import logo_search as ls
    from odnn_sep.image.logo_features import luminance

    H, W = y.shape[:2]
    f = min(1.0, ls.COARSE_PX / max(H, W))

    def level(g):
        if g >= 1.0 and hasattr(y, "full"):
            return luminance(y.full())
        return luminance(y.reduced(max(1, round(W * g)), max(1, round(H * g))) if hasattr(y, "reduced")
                            else _resize(y, g))

    g = min(1.0, ls.FINE_PX / max(H, W))
    # on a large photo the search looks no finer than the refinement level (FINE_PX)
    cands = ls.coarse(level, logo, f, ls.scale_grid(logo, (H, W)), angle_range, cap=g)
    grey_g = level(g)
    picked: list[Placement] = []
    for lv in sorted({c[3] for c in cands}):  # ranks compare within a level of the pyramid only
        for col in (0, 1):  # the best distinct matches under each ranking
            n = 0
            for c in sorted((c for c in cands if c[3] == lv), key=lambda t: -t[col]):
                p = c[2]
                if n >= N_CANDIDATES // 2:
                    break
                if all(np.hypot(p.cx - q.cx, p.cy - q.cy) > 6 / f or abs(np.log(p.scale / q.scale)) > 0.3
                       for q in picked):
                    picked.append(p)
                    n += 1
    judged = []
    for p in picked:
        r = ls.refine(grey_g, logo, p, g, 1.0, (0.6 * g / f, 0.6 * g / f, 0.06, 3.0))
        judged.append((r, judge(r)))
    if not judged:
        return []
    judged.sort(key=lambda t: -t[1])
    if g < 1.0:  # a last refinement at full resolution, in a crop around the mark
        q = _refine_full(y, logo, judged[0][0])
        judged[0] = (q, judge(q))
    best = judged[0][0]
    out = [judged[0]]
    if max_copies > 1:
        fl = ls.level_for(best.scale, logo, f, g)
        for c in ls.copies(level, logo, best, f, 4 * max_copies, cap=g):
            if len(out) >= max_copies:
                break
            if all(np.hypot(c.cx - o.cx, c.cy - o.cy) > 0.5 * min(logo.M.shape) * best.scale for o, _ in out):
                # same scale and angle as the best copy: a short refinement of the position
                c = Placement(c.cx, c.cy, best.scale, best.angle, c.score)
                r = ls.refine(grey_g, logo, c, g, 1.0, (0.6 * g / fl, 0.6 * g / fl, 0.01, 0.5), maxiter=80)
                out.append((r, judge(r)))
    return out


def _refine_full(y, logo, p: Placement) -> Placement:
    """``p`` refined on the full-resolution crop around it (a placement from a reduced copy is off by
    a fraction of its pixels, which the blend inversion shows)."""
    from odnn_sep.image import logo_search as ls
    from odnn_sep.image.logo_features import luminance

    H, W = y.shape[:2]
    half = 0.5 * np.hypot(*logo.M.shape) * p.scale * 1.15 + 8
    x0, y0 = int(max(0, p.cx - half)), int(max(0, p.cy - half))
    x1, y1 = int(min(W, p.cx + half + 1)), int(min(H, p.cy + half + 1))
    grey = luminance(y[y0:y1, x0:x1])
    q = ls.refine(grey, logo, Placement(p.cx - x0, p.cy - y0, p.scale, p.angle), 1.0, 1.0, (0.7, 0.7, 0.01, 0.5),
                  maxiter=120)
    return Placement(q.cx + x0, q.cy + y0, q.scale, q.angle, q.score)


def _resize(y, f):
    import cv2

    a = np.asarray(y, np.float32)
    r = cv2.resize(a, (max(1, round(a.shape[1] * f)), max(1, round(a.shape[0] * f))), interpolation=cv2.INTER_AREA)
    return r[:, :, None] if r.ndim == 2 else r


def place_all(logo, placements, shape):
    """(M (H, W), L (H, W, C)) of all placements (overlaps: the larger coverage wins).

    Parameters
    ----------
    logo : Logo
        The prepared logo.
    placements : list of Placement
        Where it is.
    shape : tuple of int
        (H, W) of the photo.

    Returns
    -------
    M : np.ndarray
        (H, W) coverage.
    L : np.ndarray
        (H, W, C) colours (0 where no logo).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo
    >>> from odnn_sep.image.refmode import place_all
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L = place_all(logo, [Placement(20, 20, 1.0, 0.0), Placement(70, 40, 1.0, 0.0)], (64, 96))
    >>> M.shape, L.shape, round(float(M.sum()), 1)
    ((64, 96), (64, 96, 1), 160.0)
    """
    H, W = shape
    M = np.zeros((H, W))
    L = np.zeros((H, W, logo.L.shape[2]))
    for p in placements:
        m, lc, (x0, y0, x1, y1) = render(logo, p, (H, W))
        if m.size == 0:
            continue
        sub = M[y0:y1, x0:x1]
        take = m > sub
        sub[take] = m[take]
        L[y0:y1, x0:x1][take] = lc[take]
    return M, L


def invert_logo(yc, Mc, Lc, alpha, colour, levels, inpaint_lost):
    """(restored crop, lost pixels, reported colour): the blend undone with the fitted colour, or with
    the logo's own colours ``Lc`` when ``colour`` is None (then the reported colour is their mean
    over the logo's solid pixels).

    Parameters
    ----------
    yc : np.ndarray
        (h, w, C) float crop in [0, 1].
    Mc : np.ndarray
        (h, w) coverage.
    Lc : np.ndarray
        (h, w, C) logo colours.
    alpha : float
        Opacity.
    colour : np.ndarray or None
        (C,) fitted colour, or None for the logo's own colours.
    levels : int
        Quantisation steps of the data.
    inpaint_lost : bool
        Inpaint the pixels whose data are gone.

    Returns
    -------
    out : np.ndarray
        (h, w, C) restored crop.
    lost : np.ndarray
        (h, w) bool.
    colour : np.ndarray
        (C,) reported colour.

    Examples
    --------
    >>> from odnn_sep.image.refmode import invert_logo
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((24, 24, 4), np.uint8); a[4:20, 4:9] = (255, 40, 40, 255); a[4:9, 4:20] = (40, 40, 255, 255)
    >>> logo = prepare_logo(a, (64, 96), 3)
    >>> M, L, _ = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> yy, xx = np.mgrid[0:M.shape[0], 0:M.shape[1]] / 40.0
    >>> I = np.stack([0.3 + 0.2 * xx, 0.4 + 0.1 * yy, 0.5 + 0.0 * xx], -1)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None] * L
    >>> out, lost, colour = invert_logo(y, M, L, 0.5, None, 255, True)
    >>> bool(np.allclose(out, I)), int(lost.sum()), np.round(colour, 2).tolist()
    (True, 0, [0.5, 0.16, 0.66])
    """
    from odnn_sep.image.estimate import invert

    if colour is not None:
        o, lost = invert(yc, Mc, alpha, colour, levels=levels, inpaint=inpaint_lost)
        return o, lost, colour
    # the logo's own colours: y' = y - alpha M (L - c0) is a one-colour blend with c0
    c0 = np.full(yc.shape[2], 0.5)
    o, lost = invert(yc - alpha * Mc[:, :, None] * (Lc - c0), Mc, alpha, c0, levels=levels, inpaint=inpaint_lost)
    w = (Mc > 0.5)[:, :, None]
    return o, lost, (Lc * w).sum(axis=(0, 1)) / max(1, int(w.sum()))


def reference_mode(image, reference, *, angle_range: float = 45.0, max_copies: int = 64,
                   min_score: float | None = None, inpaint_lost: bool = True, random_state=0):
    """Find the logo ``reference`` in ``image`` and remove it; see ``api.unwatermark``.

    Returns an ``api.UnwatermarkResult``; its report has ``residual_mark`` (``residual.residual_mark``).

    Parameters
    ----------
    image : np.ndarray
        (H, W[, C]) uint8, uint16 or float image.
    reference : np.ndarray
        The logo (grey, grey+alpha, RGB or RGBA), at most the photo's size.
    angle_range : float, default 45.0
        Largest rotation searched, degrees either way.
    max_copies : int, default 64
        Most copies removed.
    min_score : float, optional
        Detection threshold (default ``MIN_SCORE``).
    inpaint_lost : bool, default True
        Inpaint the pixels whose data are gone.
    random_state : int or Generator, default 0
        Seed of the fits.

    Returns
    -------
    UnwatermarkResult

    Raises
    ------
    InputError
        For an unusable reference image, or when the logo is not found.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.refmode import reference_mode
    >>> reference_mode(np.zeros((32, 48, 3), np.uint8), np.zeros((40, 40, 3), np.uint8))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: reference image 40x40 is larger than the photo 48x32; ...
    """
    from odnn_sep.image.api import UnwatermarkResult, color_report
    from odnn_sep.image.io import paste, split
    from odnn_sep.image.logo_residual import residual_mark

    t0 = time.perf_counter()
    min_score = MIN_SCORE if min_score is None else float(min_score)
    planes = split(image)
    y = planes.view
    H, W, C = y.shape
    logo = prepare_logo(reference, (H, W), C)
    fits: dict = {}

    def judge(p):
        from odnn_sep.image.detect import detection_score

        m, lc, (x0, y0, x1, y1) = render(logo, p, (H, W))
        if m.size == 0:
            fits[p] = 0.0
            return 0.0
        crop = y[y0:y1, x0:x1]
        fits[p] = (coloured_detection_score(crop, m, lc, random_state=random_state) if logo.coloured
                   else detection_score(crop, m, random_state=random_state))
        return fits[p]

    found = locate(y, logo, angle_range, max_copies, judge)
    best_score = found[0][1] if found else 0.0
    kept = [p for p, e in found if e >= min_score]
    if not kept:
        raise MarkNotFoundError(f"logo not found in the image (best match score {best_score:.3f}, needs >= {min_score:g}); "
                         f"check --reference or give --mask")
    M, L = place_all(logo, kept, (H, W))
    ys, xs = np.nonzero(M > 0)
    b = (max(0, xs.min() - 4), max(0, ys.min() - 4), min(W, xs.max() + 5), min(H, ys.max() + 5))
    yc, Mc, Lc = y[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]], L[b[1]:b[3], b[0]:b[2]]
    alpha, colour, explained = _fit(yc, Mc, Lc, logo.coloured, random_state)
    o, lost, colour = invert_logo(yc, Mc, Lc, alpha, colour, planes.levels, inpaint_lost)
    restored = paste(planes, o, b)
    lost_full = np.zeros((H, W), bool)
    lost_full[b[1]:b[3], b[0]:b[2]] = lost
    resid = residual_mark(yc, o, Mc, Lc)
    report = {"mode": "reference", "image_size": [W, H], "channels": C + (1 if planes.alpha is not None else 0),
              "bit_depth": int(planes.dtype.itemsize * 8), "bbox": [int(v) for v in b],
              "logo_colours": "own" if logo.coloured else "fitted", "logo_alpha_channel": logo.has_alpha,
              "score": round(float(best_score), 4), "explained": round(float(explained), 4),
              "marks": [{"center": [round(p.cx, 2), round(p.cy, 2)], "scale": round(p.scale, 4),
                         "angle_deg": round(p.angle, 2), "edge_ncc": round(p.score, 4),
                         "score": round(float(fits[p]), 4)} for p in kept],
              "alpha": round(float(alpha), 5), **color_report(colour, planes),
              "mark_pixels": int((M > 0.05).sum()), "lost_pixels": int(lost_full.sum()),
              "residual_mark": resid, "runtime_s": round(time.perf_counter() - t0, 3)}
    return UnwatermarkResult(restored, float(alpha), np.asarray(colour), M.astype(np.float32), lost_full, report)
