"""A second colour left beside the mark: an outline around its glyphs or a drop shadow off them.

A mark drawn in two colours (white letters with a dark outline, or over a dark copy shifted a few
pixels) is inverted by the tool as one colour over one shape. The part drawn in the other colour stays
in the output, outside (outline, shadow) or along the rim (an outline inside the estimated shape) of
the glyphs. It is a blend of a shape the mark itself gives: a ring around the glyphs, a rim inside
them, their core, or the glyphs shifted by a fraction of a stroke minus the glyphs. Each such shape is
scored with the detection statistic (``detect.detection_score``, out of sample and contrast-free) on
the output; a shape that passes the detection threshold with at least ``VISIBLE_LEVELS`` of contrast
is a second colour still visible.

Why a fixed family of shapes and not a free search: the statistic's null calibration holds for one
shape per mark; the family is small (about 30 shapes) and tied to the glyphs, and on clean photos
(perfect removals: 535 random placements of DejaVu renderings, 24-64 px, within 30 degrees, over the
four photos of ``../shared/data/photos_clean_skimage``) no shape of it was ever found.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.image.detect import THRESHOLD, detection_score

# Outline widths and shadow offsets, as fractions of the glyphs' stroke width: a 3-5 px outline or
# shadow on a 40-56 px bold face (stroke width 7-10 px), the common styles of stock marks.
SCALES = (0.35, 0.5, 0.65)
# Shapes with fewer pixels than this give the statistic too few edge patches to mean anything.
MIN_PIXELS = 30
# Marks with strokes wider than MAX_STROKE px are checked shrunk to strokes of WORK_STROKE px: the
# size of the marks the check was calibrated on (40-64 px bold text), at a fraction of the cost.
MAX_STROKE = 12.0
WORK_STROKE = 8.0
# A shape whose output steps by less than this (8-bit levels) from the photo around it is not
# scored: a step below what counts as visible (residual.VISIBLE_LEVELS). The second colours of
# development draws 0-1 stepped by 20-104 levels.
SCREEN_LEVELS = 4.0


def second_shapes(M: np.ndarray) -> dict[str, np.ndarray]:
    """The shapes a second colour of a mark with coverage ``M`` may take, by name.

    ``ring{r}``: the glyphs dilated by ``r`` px minus the glyphs (an outline); ``rim{r}``: the glyphs
    minus their erosion by ``r`` px (an outline inside the estimated shape); ``core{r}``: that erosion
    (the fill, where the estimated shape took the outline); ``shift{dx},{dy}``: the glyphs moved by
    (dx, dy) px minus the glyphs (a drop shadow), in the eight directions.

    Parameters
    ----------
    M : np.ndarray
        (h, w) coverage of the mark in [0, 1].

    Returns
    -------
    dict of str to np.ndarray
        (h, w) float shapes in {0, 1}.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_second import second_shapes
    >>> M = np.zeros((40, 60)); M[10:30, 20:28] = 1
    >>> S = second_shapes(M)
    >>> int(S["shift3,3"].sum()), bool((S["ring3"] * M).any())
    (75, False)
    """
    import cv2

    from odnn_sep.image.estimate import stroke_width

    on = (np.asarray(M) > 0.5).astype(np.uint8)
    steps = sorted({max(2, int(round(f * stroke_width(M)))) for f in SCALES})
    shapes: dict[str, np.ndarray] = {}
    for r in steps:
        disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
        shapes[f"ring{r}"] = (cv2.dilate(on, disk) - on).astype(float)
    for r in steps[:2]:
        disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r - 1, 2 * r - 1))
        core = cv2.erode(on, disk)
        shapes[f"rim{r - 1}"] = (on - core).astype(float)
        shapes[f"core{r - 1}"] = core.astype(float)
    h, w = on.shape
    for d in steps:
        for ux, uy in ((1, 0), (-1, 0), (0, 1), (0, -1), (1, 1), (-1, -1), (1, -1), (-1, 1)):
            dx, dy = ux * d, uy * d
            moved = np.zeros_like(on)
            if abs(dy) >= h or abs(dx) >= w:   # a crop smaller than the shift: nothing moves into it
                shapes[f"shift{dx},{dy}"] = moved.astype(float)
                continue
            moved[max(0, dy):h + min(0, dy), max(0, dx):w + min(0, dx)] = \
                on[max(0, -dy):h - max(0, dy), max(0, -dx):w - max(0, dx)]
            shapes[f"shift{dx},{dy}"] = np.clip(moved.astype(float) - on, 0.0, 1.0)
    return shapes


def second_colour(out: np.ndarray, M: np.ndarray, *, threshold: float = THRESHOLD, random_state=0) -> dict | None:
    """The strongest second colour left in the output crop ``out`` beside a mark of coverage ``M``.

    Parameters
    ----------
    out : np.ndarray
        (h, w, C) float output crop in [0, 1].
    M : np.ndarray
        (h, w) coverage of the mark.
    threshold : float
        Detection threshold (``detect.THRESHOLD``).
    random_state : int or Generator, default 0
        Seed of the statistic's patch subset.

    Returns
    -------
    dict or None
        ``{"shape", "score", "contrast_levels"}`` of the highest-contrast shape that passes the
        threshold with at least ``residual.VISIBLE_LEVELS`` of contrast; None when none does.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_second import second_colour
    >>> rng = np.random.default_rng(0)
    >>> I = 0.5 + 0.02 * rng.standard_normal((70, 100, 1))
    >>> M = np.zeros((70, 100)); M[15:50, 20:27] = 1; M[15:22, 10:85] = 1; M[43:50, 30:75] = 1
    >>> shadow = np.zeros_like(M); shadow[19:54, 24:31] = 1; shadow[19:26, 14:89] = 1
    >>> shadow[47:54, 34:79] = 1; shadow = shadow * (1 - M)
    >>> y = (1 - 0.5 * shadow[..., None]) * I       # the glyphs removed, their black shadow left
    >>> second_colour(y, M)["shape"], second_colour(I, M)
    ('shift4,4', None)
    """
    from odnn_sep.image.residual import VISIBLE_LEVELS, contrast_levels

    out = np.asarray(out, dtype=np.float64)
    out = out[:, :, None] if out.ndim == 2 else out
    out, M = _at_working_scale(out, np.asarray(M, dtype=np.float64))
    best = None
    shapes = second_shapes(M)
    step = _step_levels(out, M, shapes)
    for name, S in shapes.items():
        if np.count_nonzero(S > 0.5) < MIN_PIXELS or step[name] < SCREEN_LEVELS:
            continue
        score = detection_score(out, S, random_state=random_state)
        if score < threshold:
            continue
        levels = contrast_levels(out, S, random_state=random_state)
        if levels >= VISIBLE_LEVELS and (best is None or levels > best["contrast_levels"]):
            best = {"shape": name, "score": round(float(score), 4), "contrast_levels": round(float(levels), 2)}
    return best


def _step_levels(out: np.ndarray, M: np.ndarray, shapes: dict) -> dict:
    """Per shape, the mean step (8-bit levels, RMS over channels) between the output on the shape
    and the photo predicted there from around it (a Gaussian fill of the pixels off the shape and
    off the mark, about a stroke wide): a cheap screen before the detection statistic, which costs
    tens of milliseconds a shape. A second colour left steps by tens of levels; the screen only
    spares the statistic where there is next to no step."""
    import cv2

    from odnn_sep.image.estimate import stroke_width

    sigma = max(1.5, 0.5 * stroke_width(M))
    mark = np.asarray(M) > 0.5
    out32 = np.ascontiguousarray(out, dtype=np.float32)
    levels = {}
    for name, S in shapes.items():
        on = S > 0.5
        if not on.any():
            levels[name] = 0.0
            continue
        keep = (~on & ~mark).astype(np.float32)
        den = cv2.GaussianBlur(keep, (0, 0), sigma)
        d = []
        for ch in range(out.shape[2]):
            num = cv2.GaussianBlur(out32[:, :, ch] * keep, (0, 0), sigma)
            pred = num[on] / np.maximum(den[on], 1e-6)
            d.append(float(np.mean(out[:, :, ch][on] - pred)))
        levels[name] = 255.0 * float(np.sqrt(np.mean(np.square(d))))
    return levels


def _at_working_scale(out: np.ndarray, M: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``out`` and ``M`` shrunk (area averaging) so that the strokes are ``WORK_STROKE`` px wide
    when they are wider than ``MAX_STROKE``: the shapes scale with the strokes, and a mark on a
    12-megapixel photo would otherwise cost seconds per shape for the same answer."""
    import cv2

    from odnn_sep.image.estimate import stroke_width

    s = stroke_width(M)
    if not s > MAX_STROKE:
        return out, M
    f = WORK_STROKE / s
    size = (max(8, int(round(out.shape[1] * f))), max(8, int(round(out.shape[0] * f))))
    small = cv2.resize(np.ascontiguousarray(out, dtype=np.float32), size, interpolation=cv2.INTER_AREA)
    small = small[:, :, None] if small.ndim == 2 else small
    Ms = cv2.resize(np.ascontiguousarray(M, dtype=np.float32), size, interpolation=cv2.INTER_AREA)
    return small.astype(np.float64), Ms.astype(np.float64)


__all__ = ["second_shapes", "second_colour", "SCALES", "MIN_PIXELS", "MAX_STROKE", "WORK_STROKE", "SCREEN_LEVELS"]
