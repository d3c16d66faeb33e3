"""``--mask`` mode: the user marks the area; the mark's exact shape, opacity and colour are estimated.

A hard mask (a rough box, a filled rectangle, or the strokes) is a region where the coverage ``M``
is unknown in [0, 1], not ``M = 1``. Inside it, a blended pixel moves from the photo ``B`` straight
toward the mark colour: ``y - B = m (c - B)`` with ``m = alpha M`` in [0, 1]; photo pixels that are
not pulled keep ``m = 0``. The photo ``B`` under the candidate mark pixels is interpolated from the
pixels around them (OpenCV TELEA inpainting of the candidate set only), ``c`` and ``m`` are found on
that rank-one model, the candidate set is shrunk to where ``m`` is clearly non-zero, and the loop
repeats. It starts from the whole region (a stroke mask) and from the pixels pulled towards white or
towards black more than the photo around them (a rough box). Each estimate's coverage is set to 1
inside its strokes (only the one-pixel edges are read per pixel), the blend fit of ``estimate``
(locally smooth photo) gives ``alpha`` and the colour, and the detection statistic of ``detect``
decides which estimate stands and whether anything was found: a box whose content no blend of one
colour and one opacity explains is "not found" (``InputError``), not inpainted.

Filled translucent shapes (a banner, a badge, a logo's silhouette) are wider than a stroke: the
candidate search does not see them as dips, and inside an exact mask no pixel is unpulled. They are a
further hypothesis: the mask itself or shrunk by 1-3 px (exact and dilated masks), or the part of the
region pulled towards white, black or one colour by one factor, as one solid piece with its holes
filled (a rough box); ``M = 1`` inside, read per pixel on its edge only. The blend fit on its edge gives
opacity and colour, and the detection statistic on 12 px edge patches (``edge_score``) decides whether
it is there and whether it or the strokes stand.
"""
from __future__ import annotations

import logging

import numpy as np

from odnn_sep.core.linalg import solve_batched
from odnn_sep.errors import InputError
from odnn_sep.image.estimate import inpaint_telea

log = logging.getLogger(__name__)


def _colour(d: np.ndarray, B: np.ndarray, D: np.ndarray, prev) -> np.ndarray:
    """The mark colour as the least-squares meeting point of the lines from photo B through y.

    Every blended pixel lies on the segment from its photo colour to the mark colour, so with the
    deviation ``d = y - B`` the colour is where those lines (weighted by |d|^2) meet. A grey image
    has no direction to use: the colour is then white or black, from the sign of the deviation.
    """
    dd = d[D]
    n2 = np.sum(dd * dd, axis=1)
    sign = 1.0 if np.sum(dd) > 0 else 0.0
    if d.shape[2] == 1 or n2.size < 3:
        return np.full(d.shape[2], sign) if prev is None else prev
    sel = n2 > np.quantile(n2, 0.5)
    u = dd[sel] / np.sqrt(n2[sel])[:, None]
    w = n2[sel]
    Bs = B[D][sel]
    eye = np.eye(d.shape[2])
    P = eye[None] - u[:, :, None] * u[:, None, :]
    A = np.einsum("i,ijk->jk", w, P)
    b = np.einsum("i,ijk,ik->j", w, P, Bs)
    try:
        c = solve_batched(A + 1e-9 * eye, b)
    except np.linalg.LinAlgError:                                   # non-finite data
        c = np.full(d.shape[2], sign)
    return np.clip(c, 0.0, 1.0)


def estimate_shape(y: np.ndarray, region: np.ndarray, *, iterations: int = 3, details: dict | None = None,
                   start: np.ndarray | None = None, color=None) -> tuple[np.ndarray, np.ndarray]:
    """Coverage ``m = alpha M`` (h, w) and colour (C,) of a mark inside ``region`` of crop ``y``.

    ``details`` (a dict, filled in): ``background`` (the interpolated photo B), ``explained`` (share of
    the deviation ``y - B`` inside the region that the one-colour blend explains), ``residual_sd``.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    region : np.ndarray
        (h, w) bool, where the mark is.
    iterations : int, default 3
        Rounds of photo interpolation and shape estimation.
    details : dict, optional
        Filled in with the fields above.
    start : np.ndarray, optional
        (h, w) bool, the first set of candidate mark pixels (default: all of ``region``).
    color : array_like, optional
        (C,) the mark colour, when known (default: estimated from the lines from photo to pixel).

    Returns
    -------
    m : np.ndarray
        (h, w) coverage times opacity, 0 outside the region.
    color : np.ndarray
        (C,) mark colour.

    Raises
    ------
    InputError
        When ``region`` is empty.

    Examples
    --------
    >>> from odnn_sep.image.maskmode import estimate_shape
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.3 * xx, 0.3 + 0.2 * yy, 0.5 + 0.1 * xx], -1)
    >>> M = np.zeros((32, 48)); M[10:22, 12:16] = 1; M[10:14, 12:36] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None]
    >>> region = np.zeros((32, 48), bool); region[6:26, 8:40] = True
    >>> m, color = estimate_shape(y, region)
    >>> round(float(m.max()), 2), bool(color.min() > 0.9)
    (0.46, True)
    """
    import cv2

    R = region.astype(bool)
    if not R.any():
        raise InputError("mask has no nonzero pixels inside the image; mark the watermark's area")
    D = R.copy() if start is None else (np.asarray(start, bool) & R)
    c = None
    m = np.zeros(R.shape)
    for _ in range(iterations):
        B = inpaint_telea(y, D, 5)
        d = y - B
        c = _colour(d, B, D, c) if color is None else np.asarray(color, dtype=np.float64)
        v = c[None, None, :] - B
        m = np.clip(np.sum(d * v, axis=2) / np.maximum(np.sum(v * v, axis=2), 1e-6), 0.0, 1.0)
        m[~D] = 0.0
        noise = 1.4826 * np.median(np.abs(m[D] - np.median(m[D]))) + 1e-3
        keep = (m > max(0.03, 3 * noise)).astype(np.uint8)
        keep = cv2.dilate(keep, np.ones((3, 3), np.uint8)).astype(bool) & R
        if details is not None:
            r = d - m[:, :, None] * v
            details["background"] = B
            details["explained"] = 1.0 - float(np.sum(r[R] ** 2)) / max(float(np.sum(d[R] ** 2)), 1e-12)
            details["residual_sd"] = 1.4826 * float(np.median(np.abs(r[R]))) + 1.0 / 255
        if keep.sum() < 3:
            break
        D = keep
    m[~D] = 0.0
    return m, np.asarray(c)


# A mark fitted with at least this opacity is opaque: the photo under it is gone and the masked area
# is inpainted (only when its shape's edges reach MASK_MIN_SCORE and the blend explains
# MASK_FOUND_EXPLAINED of them; an opaque logo, not photo detail).
OPAQUE_ALPHA = 0.9
# Mask mode: the blend fit replaces the shape estimate's opacity and colour only when the mark
# explains at least this share of the edge patches' photo-only residual (also what a stroke mask's
# mark must explain to be found).
MASK_MIN_EXPLAINED = 0.28
# A mark inside a rough box is found only when the detection statistic of the estimated shape
# reaches this and the blend explains this share of its edge patches. The shape is read from the
# data, so chance scores run higher than text mode's THRESHOLD for a rendered template: on 32 boxes
# over the clean skimage photos (astronaut, coffee, chelsea, rocket) the best hypothesis scored up
# to 1.1; most chance fits that pass are then called still visible by the residual check (no output).
MASK_MIN_SCORE = 0.5
MASK_FOUND_EXPLAINED = 0.5
# A mask whose estimated strokes fill this share of it (of its part above 0.5 for a soft mask) is a
# stroke mask: text mode's threshold applies.
STROKE_SHARE = 0.5
# A mark found inside a rough box covers at least this share of it (a text mark in a box of a few
# pixels' margin covers 10-40 %; a few photo details that one colour explains, less).
MIN_MARK_SHARE = 0.05
# Parts of a mark whose opacity departs from the common one by more than this share are photo detail.
LEVEL_TOLERANCE = 0.3
# A start from the candidate pixels replaces the one from the whole region when its score is higher by this.
PREFER_REGION = 0.1
# Filled shapes: parts of the shape smaller than this share of its largest part are dropped.
FILL_PART = 0.2
# Holes in a filled shape smaller than this share of it are the photo's texture and are filled.
FILL_HOLE = 0.02
# Filled shapes are scored on a crop this much larger than the mask: their edge patches are wide.
FILL_PAD = 24
# Side of the edge patches that score a filled shape (``edge_score``).
FILL_PATCH = 12
# A filled shape is found when its edge score reaches this and it covers this share of the mask.
FILL_MIN_SCORE = 0.6
FILL_MIN_SHARE = 0.2
# A filled shape is at least this wide (px, ``estimate.stroke_width``) and covers at least this share of
# its convex hull (text in 28-49 px bold and serif fonts: 2-8 px, 0.25-0.57; filled badges, banners and
# a logo silhouette: 9.6-50 px, 0.6-1.0).
FILL_MIN_WIDTH = 9.0
# Colours of the stroke estimates a filled shape in a box is also looked for with (at most this many).
FILL_COLOURS = 3
FILL_MIN_SOLIDITY = 0.5
# A filled shape this solid (a rectangle, an ellipse) cannot be text: it replaces the strokes when it
# scores higher; a less solid one (a silhouette, or bold text in its own mask) by PREFER_REGION more.
FILL_SOLID = 0.8


def _candidates(y: np.ndarray, region: np.ndarray, color) -> np.ndarray:
    """Pixels of ``region`` pulled towards ``color`` more than the photo around them: where a mark's
    strokes may be inside a rough box.

    A blend towards ``c`` multiplies the distance of the photo from ``c`` by ``1 - a M``: in
    ``log |y - c|`` the mark is a dip of one depth, ``log(1 - a)``, over the photo. The photo's level
    is the upper envelope of that log image (a morphological closing wider than a stroke); what
    dips below it by a share of at least Otsu's split (and 0.1) is a candidate. The photo's own
    detail that is closer to ``c`` than its surroundings dips too; the blend fit that follows keeps
    only what one opacity explains."""
    import cv2

    h = int(region.any(axis=1).sum())
    d = int(np.clip(round(0.35 * h), 7, 31)) | 1
    dist = np.sqrt(np.sum((y - np.asarray(color, dtype=np.float64)[None, None, :]) ** 2, axis=2))
    L = np.log(dist + 2.0 / 255).astype(np.float32)
    se = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (d, d))
    env = cv2.morphologyEx(L, cv2.MORPH_CLOSE, se, borderType=cv2.BORDER_REPLICATE)
    m = 1.0 - np.exp(np.minimum(L - env, 0.0))
    v = m[region]
    if v.size < 10 or float(v.max()) <= 0:
        return np.zeros_like(region)
    u8 = np.round(np.clip(v / v.max(), 0, 1) * 255).astype(np.uint8).reshape(-1, 1)
    t, _ = cv2.threshold(u8, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
    thr = max(0.1, float(t) / 255 * float(v.max()))
    return (m > thr) & region


def clean_coverage(m: np.ndarray, alpha: float) -> tuple[np.ndarray, np.ndarray]:
    """(coverage M, glyph core) of a per-pixel ``a M`` map ``m``: 1 inside the strokes, ``m / alpha`` on
    their edges, 0 elsewhere.

    The per-pixel ``a M`` carries the error of the photo interpolated under the mark (on a face, a
    share of 0.3-0.5 where the truth was 0.45); inverting with it would replace the photo's texture
    under the strokes by the interpolation. A mark's coverage is 1 inside its strokes: only the
    one-pixel edges are read per pixel. Components of fewer than 6 pixels are dropped.

    Parameters
    ----------
    m : np.ndarray
        (h, w) per-pixel ``a M``.
    alpha : float
        Opacity (the interior level of ``m``).

    Returns
    -------
    M : np.ndarray
        (h, w) coverage in [0, 1].
    core : np.ndarray
        (h, w) bool, stroke interiors (M = 1).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.maskmode import clean_coverage
    >>> m = np.zeros((20, 30)); m[5:15, 5:25] = 0.4; m[8, 8] = 0.3; m[4, 5:25] = 0.2
    >>> M, core = clean_coverage(m, 0.4)
    >>> float(M[8, 8]), float(M[4, 10]), int(core.sum())
    (1.0, 0.5, 144)
    """
    import cv2

    a = max(float(alpha), 1e-6)
    S = (m > 0.5 * a).astype(np.uint8)
    n, lab, stats, _ = cv2.connectedComponentsWithStats(S, connectivity=8)
    small = np.nonzero(stats[:, cv2.CC_STAT_AREA] < 6)[0]
    S[np.isin(lab, small[small > 0])] = 0
    core = cv2.erode(S, np.ones((3, 3), np.uint8)).astype(bool)
    near = cv2.dilate(S, np.ones((3, 3), np.uint8)).astype(bool)
    M = np.where(core, 1.0, np.where(near, np.clip(m / a, 0.0, 1.0), 0.0))
    return M, core


def _one_opacity(M: np.ndarray, m: np.ndarray) -> np.ndarray:
    """``M`` without the connected parts whose per-pixel ``a M`` (``m``) sits off the common level.

    A mark has one opacity: every letter is pulled towards its colour by the same factor. Photo
    detail that the candidate set took in (a highlight, a dark fold) is pulled by its own. Parts of
    ``M > 0.5`` whose median ``m`` departs from the pixel-weighted median over all parts by more than
    ``LEVEL_TOLERANCE`` of it are dropped (with their edge pixels)."""
    import cv2

    S = (M > 0.5).astype(np.uint8)
    n, lab = cv2.connectedComponents(S, connectivity=8)
    if n <= 2:
        return M
    levels = np.array([np.median(m[lab == k]) for k in range(1, n)])
    sizes = np.bincount(lab.ravel(), minlength=n)[1:]
    order = np.argsort(levels)
    cum = np.cumsum(sizes[order])
    common = float(levels[order][np.searchsorted(cum, 0.5 * cum[-1])])
    bad = 1 + np.nonzero(np.abs(levels - common) > LEVEL_TOLERANCE * common)[0]
    if not bad.size:
        return M
    drop = cv2.dilate(np.isin(lab, bad).astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool) & ~(
        np.isin(lab, np.setdiff1d(np.arange(1, n), bad)))
    return np.where(drop, 0.0, M)


def _interior_level(m: np.ndarray) -> float | None:
    """Opacity as the median per-pixel ``a M`` over the stroke interiors, or None with too few."""
    import cv2

    on = m[m > 0.03]
    if on.size < 20:
        return None
    a0 = float(np.median(on[on > 0.5 * np.quantile(on, 0.95)]))
    core = cv2.erode((m > 0.5 * a0).astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)
    vals = m[core] if core.sum() >= 20 else m[m > 0.5 * a0]
    return float(np.median(vals)) if vals.size else None


def _hypothesis(crop, R, start, random_state, color=None):
    """One estimate of a translucent mark inside region ``R`` from the starting set ``start``:
    dict with ``M``, ``alpha``, ``color``, ``score`` (detection statistic), ``explained``, or None."""
    import cv2

    from odnn_sep.errors import NotIdentifiableError
    from odnn_sep.image.detect import detection_score
    from odnn_sep.image.estimate import fit_blend

    if start.sum() < 10:
        return None
    det: dict = {}
    m, color = estimate_shape(crop, R, start=start, details=det, color=color)
    a = _interior_level(m)
    if a is None or a <= 0.02:
        return None
    M, _ = clean_coverage(m, a)
    if (M > 0.5).sum() < 10:
        return None
    alpha, explained = a, 0.0
    B = det["background"]
    for rnd in range(2):
        try:
            fit = fit_blend(crop, M, random_state=random_state)
        except NotIdentifiableError:
            break
        explained = fit.explained
        if not (0.02 < fit.alpha <= 1.0 and fit.explained > MASK_MIN_EXPLAINED):
            break
        alpha, color = fit.alpha, fit.color
        if rnd:
            break
        # the per-pixel a M again with the fitted colour (the colour where the lines from the photo
        # through the pixels meet is poorly placed along them: a M read against it ran to 1), its
        # strokes scaled by the fitted opacity; then the opacity once more with that coverage
        v = color[None, None, :] - B
        m2 = np.clip(np.sum((crop - B) * v, axis=2) / np.maximum(np.sum(v * v, axis=2), 1e-6), 0.0, 1.0)
        near = cv2.dilate((M > 0).astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool) & R
        M2, _ = clean_coverage(np.where(near, m2, 0.0), alpha)
        M2 = _one_opacity(M2, m2)
        if (M2 > 0.5).sum() < 10:
            break
        m, a, M = m2, alpha, M2
    score = detection_score(crop, M, random_state=random_state)
    # an opaque mark: the edges of the region-interpolated shape itself (whatever one colour explains)
    opaque_score = detection_score(crop, (m > 0.5 * a).astype(float), random_state=random_state) \
        if a >= OPAQUE_ALPHA else 0.0
    return {"M": M, "alpha": float(alpha), "color": np.asarray(color), "score": float(score),
            "opaque_score": float(opaque_score), "n_on": int((M > 0.5).sum()), "explained": float(explained),
            "blend_explained": float(det.get("explained", 0.0))}


def _pull(y: np.ndarray, B: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Per-pixel ``a M`` of ``y`` over photo ``B`` towards colour ``c``: the share of the way from B to c."""
    v = np.asarray(c, dtype=np.float64)[None, None, :] - B
    return np.clip(np.sum((y - B) * v, axis=2) / np.maximum(np.sum(v * v, axis=2), 1e-6), 0.0, 1.0)


def _blob(m: np.ndarray, region: np.ndarray, level: float | None = None) -> tuple[np.ndarray, float]:
    """(filled shape, its level) of a per-pixel ``a M`` map: where the median-smoothed ``m`` is above half
    the level (Otsu's upper class when not given), its large connected parts with their small holes
    (under ``FILL_HOLE`` of the shape) filled."""
    import cv2
    from scipy.ndimage import binary_fill_holes

    ms = cv2.medianBlur(m.astype(np.float32), 5)
    v = ms[region]
    if level is None:
        if v.size < 20 or float(v.max()) <= 0.02:
            return np.zeros_like(region), 0.0
        u8 = np.round(np.clip(v / v.max(), 0, 1) * 255).astype(np.uint8).reshape(-1, 1)
        t, _ = cv2.threshold(u8, 0, 255, cv2.THRESH_BINARY + cv2.THRESH_OTSU)
        hi = v[v > float(t) / 255 * float(v.max())]
        level = float(np.median(hi)) if hi.size else 0.0
    S = ((ms > 0.5 * level) & region).astype(np.uint8)
    S = cv2.morphologyEx(S, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    n, lab, stats, _ = cv2.connectedComponentsWithStats(S, connectivity=8)
    if n <= 1:
        return np.zeros_like(region), float(level)
    area = stats[1:, cv2.CC_STAT_AREA]
    keep = 1 + np.nonzero((area >= FILL_PART * area.max()) & (area >= 20))[0]
    S = np.isin(lab, keep)
    # holes the photo's texture left are filled; a letter's counter or a ring's middle stays open
    holes = binary_fill_holes(S) & ~S
    n, lab, stats, _ = cv2.connectedComponentsWithStats(holes.astype(np.uint8), connectivity=4)
    small = 1 + np.nonzero(stats[1:, cv2.CC_STAT_AREA] < FILL_HOLE * S.sum())[0]
    return (S | np.isin(lab, small)) & region, float(level)


def _solidity(S: np.ndarray) -> float:
    """Share of its convex hull that a shape covers, 0 for a shape narrower than ``FILL_MIN_WIDTH``
    (``estimate.stroke_width``): a filled shape (a banner, a badge, a silhouette) has at least
    ``FILL_MIN_SOLIDITY``, text in 28-49 px bold and serif fonts 0.25-0.57 (strokes of 2-8 px)."""
    import cv2

    from odnn_sep.image.estimate import stroke_width

    if S.sum() < 20 or stroke_width(S.astype(np.float64)) < FILL_MIN_WIDTH:
        return 0.0
    hull = cv2.convexHull(cv2.findNonZero(S.astype(np.uint8)))
    return min(1.0, float(S.sum()) / max(float(cv2.contourArea(hull)), 1.0))


def _filled_coverage(S: np.ndarray, m: np.ndarray, alpha: float) -> np.ndarray:
    """Coverage of a filled shape ``S``: 1 inside, ``m / alpha`` on its one-pixel edges inside and out."""
    import cv2

    k = np.ones((3, 3), np.uint8)
    core = cv2.erode(S.astype(np.uint8), k).astype(bool)
    band = cv2.dilate(S.astype(np.uint8), k).astype(bool) & ~core
    return np.where(core, 1.0, np.where(band, np.clip(m / max(alpha, 1e-6), 0.0, 1.0), 0.0))


def edge_score(y: np.ndarray, M: np.ndarray, *, patch: int = FILL_PATCH, random_state=0) -> float:
    """The detection statistic of ``detect.detection_score`` on edge patches of a fixed side ``patch``.

    ``detection_score`` scales its patches to the strokes (up to 32 px); the edge of a filled shape is
    one long step, and in 32 px patches of a textured photo the photo's own detail drowns it. With
    small patches along the edge, the opacity and colour fitted on one half of the edge predict the
    other half patch by patch, as for strokes.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) coverage.
    patch : int, default FILL_PATCH
        Patch side in px.
    random_state : int or Generator, default 0
        Draws the patch subset when there are many.

    Returns
    -------
    float
        Mean clipped log-ratio over the edge patches (0 for no evidence or fewer than four patches).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.maskmode import edge_score
    >>> rng = np.random.default_rng(0)
    >>> I = 0.5 + 0.02 * rng.standard_normal((60, 90, 1))
    >>> M = np.zeros((60, 90)); M[15:45, 20:70] = 1
    >>> y = (1 - 0.3 * M[..., None]) * I + 0.3 * M[..., None]
    >>> edge_score(y, M) > 1.0, edge_score(I, M) < 0.1
    (True, True)
    """
    from odnn_sep.image.detect import patch_score

    # detection_score's statistic on fixed small patches (at most 600 of them)
    return patch_score(y, M, patch, 600, random_state=random_state)


def _fit_filled(crop, S, c, a, random_state):
    """(M, alpha, colour, explained, photo) of the filled shape ``S`` with the blend fit on its edges, the
    edge pixels read against the photo interpolated from around the shape; None when it fails."""
    import cv2

    from odnn_sep.errors import NotIdentifiableError
    from odnn_sep.image.estimate import fit_blend

    hole = cv2.dilate(S.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    B = inpaint_telea(crop, hole, 5)
    M = S.astype(np.float64) if c is None else _filled_coverage(S, _pull(crop, B, c), a)
    for _ in range(2):
        try:
            fit = fit_blend(crop, M, random_state=random_state)
        except NotIdentifiableError:
            return None
        if not 0.02 < fit.alpha <= 1.0:
            return None
        M2 = _filled_coverage(S, _pull(crop, B, fit.color), fit.alpha)
        if c is not None and abs(fit.alpha - a) < 0.01:
            break
        M, a, c = M2, fit.alpha, fit.color
    return M, float(fit.alpha), np.asarray(fit.color), float(fit.explained), B


def _filled_hypotheses(crop, R, random_state, colors=()):
    """Filled translucent shapes (a banner, a badge, a logo's silhouette) inside region ``R``: the
    region itself and the region shrunk by 1-3 px (an exact or a dilated mask), and the part of ``R``
    whose pixels are pulled towards white, black or one colour (estimated from the lines from the photo
    through the pixels, or one of ``colors``: those fitted to the stroke estimates) by one factor, as
    one piece with its small holes filled, and once more with all of them filled (a rough box). Each shape's coverage is 1 inside and read per pixel on its edge;
    opacity and colour come from the blend fit, the score from ``edge_score``. List of dicts as
    ``_hypothesis`` gives."""
    import cv2
    from scipy.ndimage import binary_fill_holes

    k3 = np.ones((3, 3), np.uint8)
    shapes = []
    S = R.astype(np.uint8)
    for _ in range(4):
        if S.sum() >= 20:
            shapes.append((S.astype(bool), None, None))
        S = cv2.erode(S, k3)
    hole = cv2.dilate(R.astype(np.uint8), k3).astype(bool)
    B = inpaint_telea(crop, hole, 5)
    tried: list = []
    for col in [np.full(crop.shape[2], 1.0), np.full(crop.shape[2], 0.0), None] + list(colors):
        c = np.asarray(col, dtype=np.float64) if col is not None else _colour(crop - B, B, R, None)
        if any(float(np.abs(c - t).max()) < 0.1 for t in tried):
            continue
        tried.append(c)
        S, a = _blob(np.where(R, _pull(crop, B, c), 0.0), R)
        if S.sum() < 20 or a <= 0.02 or S.sum() > 0.9 * R.sum():
            continue
        # read the shape once more against the photo interpolated from around it (not from around R)
        Bs = inpaint_telea(crop, cv2.dilate(S.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool), 5)
        S2, _ = _blob(np.where(R, _pull(crop, Bs, c), 0.0), R, a)
        S = S2 if S2.sum() >= 20 else S
        shapes.append((S, c, a))
        # its larger holes may be a letter's counter or texture the pull missed: both are tried
        full = binary_fill_holes(S) & R
        if full.sum() > S.sum():
            shapes.append((full, c, a))
    out = []
    for S, c, a in shapes:
        solid = _solidity(S)
        if solid < FILL_MIN_SOLIDITY:
            continue
        f = _fit_filled(crop, S, c, a, random_state)
        if f is None:
            continue
        M, alpha, color, explained, _ = f
        score = edge_score(crop, M, random_state=random_state)
        out.append({"M": M, "alpha": alpha, "color": color, "score": float(score), "opaque_score": 0.0,
                    "n_on": int((M > 0.5).sum()), "explained": explained, "blend_explained": explained,
                    "solidity": solid})
    return out


def mask_mode(y, prepared, random_state=0):
    """(M (H, W) float32, alpha, colour, report fields) of the mark inside a prepared mask.

    ``y``: (H, W, C) float array or ``io.FloatView``; ``prepared``: ``maskprep.PreparedMask``. A hard
    mask (a rough box or the strokes) is a region where the coverage M is unknown in [0, 1], not
    M = 1: the strokes, the opacity and the colour are estimated from the data (pixels pulled
    towards one colour by one factor), starting once from the whole region (a stroke mask) and once
    from the pixels that stand out from the photo around them (a rough box); the estimate the
    detection statistic (``detect.detection_score``) supports better is kept. A filled translucent
    shape (a banner, a badge: solid and wider than a stroke) is a further hypothesis, scored by
    ``edge_score``; it stands when it reaches ``FILL_MIN_SCORE`` and scores above the strokes. An opaque mark (or one
    the one-colour blend does not explain) comes back as ``M = 1`` over the region with
    ``alpha = 1``: the blend inversion then inpaints all of it, and the report says so.

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    prepared : PreparedMask
        The user's mask (:func:`odnn_sep.image.maskprep.prepare_mask`).
    random_state : int or Generator, default 0
        Seed of the blend fit.

    Returns
    -------
    M : np.ndarray
        (H, W) float32 coverage.
    alpha : float
        Opacity.
    color : np.ndarray
        (C,) mark colour.
    info : dict
        Report fields (``bbox``, ``mask_soft``, ``blend_explained``, ``match_score``, ...).

    Raises
    ------
    InputError
        When nothing inside the mask is a blend of one colour and one opacity (not found).

    Examples
    --------
    >>> from odnn_sep.image.maskmode import mask_mode
    >>> from odnn_sep.image.maskprep import prepare_mask
    >>> from odnn_sep.image.synth import add_text_watermark, photo_like
    >>> import numpy as np
    >>> clean = photo_like((100, 200), random_state=1)
    >>> y, M = add_text_watermark(clean, "MARK", size=40, center=(100, 50), alpha=0.4)
    >>> ys, xs = np.nonzero(M > 0.02)
    >>> box = np.zeros((100, 200), np.uint8); box[ys.min() - 6:ys.max() + 7, xs.min() - 6:xs.max() + 7] = 255
    >>> M_est, alpha, color, info = mask_mode(y / 255.0, prepare_mask(box, (100, 200)))
    >>> round(alpha, 1), bool(color.min() > 0.9), info["opaque"]
    (0.4, True, False)
    """
    from odnn_sep.image.detect import THRESHOLD

    H, W = y.shape[:2]
    region = prepared.region
    ys, xs = np.nonzero(region)
    pad = 8
    x0, y0 = max(0, xs.min() - pad), max(0, ys.min() - pad)
    x1, y1 = min(W, xs.max() + pad + 1), min(H, ys.max() + pad + 1)
    crop = np.asarray(y[y0:y1, x0:x1], dtype=np.float64)
    Rc = region[y0:y1, x0:x1]
    info = {"bbox": [int(x0), int(y0), int(x1), int(y1)], "marks": [], "mask_soft": prepared.soft,
            "mask_inverted": prepared.inverted}
    if prepared.note:
        info["mask_note"] = prepared.note
    best = None
    hyps = []
    filled: list = []
    if crop.shape[0] >= 8 and crop.shape[1] >= 8:
        C = crop.shape[2]
        starts = [(Rc, None)]
        for v in (1.0, 0.0):
            cand = _candidates(crop, Rc, np.full(C, v))
            starts += [(cand, np.full(C, v)), (cand, None)]
        for k, (start, col) in enumerate(starts):
            h = _hypothesis(crop, Rc, start, random_state, col)
            hyps += [h] if h is not None else []
            # the whole region first (a stroke mask): another start must do clearly better
            if h is not None and (best is None or h["score"] > best["score"] + (PREFER_REGION if k else 0.0)):
                best = h
        # a filled shape (a banner, a badge): scored on a wider crop, its edge patches are wide
        bx0, by0 = max(0, xs.min() - FILL_PAD), max(0, ys.min() - FILL_PAD)
        bx1, by1 = min(W, xs.max() + FILL_PAD + 1), min(H, ys.max() + FILL_PAD + 1)
        big = np.asarray(y[by0:by1, bx0:bx1], dtype=np.float64)
        colors = [h["color"] for h in hyps if h["alpha"] < OPAQUE_ALPHA][:FILL_COLOURS]
        filled = [h for h in _filled_hypotheses(big, region[by0:by1, bx0:bx1], random_state, colors)
                  if h["alpha"] < OPAQUE_ALPHA]
    # a stroke mask leaves the shape little freedom: text mode's threshold; a rough box needs more
    hard = (prepared.prior[y0:y1, x0:x1] > 0.5) if prepared.soft else Rc
    stroke_like = best is not None and best["n_on"] >= STROKE_SHARE * int(hard.sum())
    need = THRESHOLD if stroke_like else MASK_MIN_SCORE
    found = best is not None and best["score"] >= need and \
        best["explained"] >= (MASK_MIN_EXPLAINED if stroke_like else MASK_FOUND_EXPLAINED) and \
        best["n_on"] >= MIN_MARK_SHARE * int(Rc.sum())
    filled = [h for h in filled if h["score"] >= FILL_MIN_SCORE and h["n_on"] >= FILL_MIN_SHARE * int(hard.sum())]
    if filled:
        top = max(filled, key=lambda h: h["score"])
        # the filled shape against the strokes on the same statistic: the one whose edges the blend
        # predicts better stands (a shape that could be bold text must do clearly better)
        rival = 0.0
        if found and best["alpha"] < OPAQUE_ALPHA:
            Mb = np.zeros(big.shape[:2])
            Mb[y0 - by0:y1 - by0, x0 - bx0:x1 - bx0] = best["M"]
            rival = edge_score(big, Mb, random_state=random_state)
        if top["score"] > rival + (0.0 if top["solidity"] >= FILL_SOLID else PREFER_REGION):
            best = dict(top, M=top["M"][y0 - by0:y1 - by0, x0 - bx0:x1 - bx0])
            found, need = True, FILL_MIN_SCORE
    info["match_score"] = round(best["score"], 4) if best is not None else 0.0
    opaque = [h for h in hyps if h["alpha"] >= OPAQUE_ALPHA and h["explained"] >= MASK_FOUND_EXPLAINED
              and h["opaque_score"] >= MASK_MIN_SCORE]
    if found and best["alpha"] < OPAQUE_ALPHA:
        Mc, alpha, color = best["M"], best["alpha"], best["color"]
        info["blend_explained"] = round(best["blend_explained"], 4)
        info["opaque"] = False
    elif opaque:
        # a nearly opaque shape with sharp edges: the photo under it is gone
        top = max(opaque, key=lambda h: h["opaque_score"])
        info["blend_explained"] = round(top["blend_explained"], 4)
        info["opaque"] = True
        info["mask_note"] = (info.get("mask_note", "") + "; " if "mask_note" in info else "") + \
            f"mark is opaque (opacity {top['alpha']:.2f}): the masked area is inpainted"
        log.warning(info["mask_note"].split("; ")[-1])
        Mc = Rc.astype(np.float64) if not prepared.soft else (prepared.prior[y0:y1, x0:x1] > 0.5).astype(float)
        if not Mc.any():
            Mc = Rc.astype(np.float64)
        alpha, color = 1.0, np.asarray(top["color"])
    else:
        score = best["score"] if best is not None else 0.0
        raise InputError(f"no watermark found inside the mask: nothing there is a blend of one colour and one "
                         f"opacity (match score {score:.3f}, needs >= {need:g}); check the mask")
    M = np.zeros((H, W), np.float32)
    M[y0:y1, x0:x1] = Mc
    return M, float(alpha), np.asarray(color), info
