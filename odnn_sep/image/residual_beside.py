"""Text of the mark's colour and opacity beside the line removed: another line of the mark, not given.

A mark of two lines ("Studio 2024" over "John Doe") run with the first line's text had that line
removed and reported "removed watermark" (exit 0), with the second line left in the photo. The
search renders only the text it is given, so nothing looked at the rest of the mark.

After removal, the input is read where another line would sit: bands one line height tall, 0.1 to 1.2
line heights above and below the removed line (in the line's own orientation), a quarter of its
width wider on each side.
Each pixel's share of the mark is estimated from the blend with the mark's colour and opacity over
the local median of the input (``(I - B) . (c - B) / (alpha |c - B|^2)``, where ``alpha |c - B|`` is at
least ``MIN_CONTRAST``); pixels whose share lies in ``[0.5, 1.5]`` look like the mark's glyph interior.
A band holding at least ``SHARE_OF_LINE`` of the removed line's own density of such pixels (on the
input), and ``OVER_PHOTO`` times that of bands 4-7 line heights away and beside the line (the photo's
own rate), and standing out of the rows beside it as a line of text does (``LINE_CONTRAST``), is
reported: a warning and ``residual_mark.text_beside``; the output is written as usual (the line asked
for was removed).
"""
from __future__ import annotations

import numpy as np

# A band of text stands out of the rows beside it (the gap between the lines, the rows beyond): its
# density must be this many times theirs. Chosen on development seed 0 (15 two-line marks given one
# line: 7 bands of text at 3.3-16, others at 1.0-3.0; 20 single-line marks: photo bands at 0.02-2.96,
# two at 3.9-4.5 with densities under a quarter of the line's).
LINE_CONTRAST = 3.0
# Window of the local median (the photo under the strokes), in line heights.
KERNEL_OF_LINE = 0.6
# Colour distance (fraction of full scale) between mark and photo under which a pixel says nothing.
MIN_CONTRAST = 0.08
# A band beside the line is text of the mark when it holds this share of the line's own density (a
# shorter second line fills less of the band, which is a quarter of the line's width wider each side) ...
SHARE_OF_LINE = 0.25
# ... and this many times the density of bands further away (the photo's own mark-coloured pixels).
OVER_PHOTO = 3.0
# A line taller than this (px, upright) is read on a copy reduced to this height: the bands span 15 line
# heights and the median window 0.6 of one, so a 160 px line on a 12-MP photo cost seconds at full size,
# while the strokes of a line this tall are still several pixels wide (their interiors hold share 1).
WORK_LINE_PX = 48


def _upright_height(M, angle_deg) -> float:
    """Height in px of the mark's line turned horizontal (the lower of the two turning senses)."""
    rr, cc = np.nonzero(M > 0.3)
    if not rr.size:
        return 0.0
    t = np.deg2rad(float(angle_deg))
    return float(min(np.ptp(np.cos(t) * rr + s * np.sin(t) * cc) for s in (-1.0, 1.0)))


def _crop(img, M, pad, shrink):
    """The crop around the mark (``pad`` px more on each side), as float32, reduced ``shrink`` times
    when that is over 1 (area averaging): (image crop, coverage crop)."""
    import cv2

    H, W = M.shape
    rr, cc = np.nonzero(M > 0.05)
    r0, r1 = max(0, rr.min() - pad), min(H, rr.max() + pad + 1)
    c0, c1 = max(0, cc.min() - pad), min(W, cc.max() + pad + 1)
    # a float view of a large image: its crop read as float32 straight from the input's values, and
    # scaled once reduced (the view's own crops are float64: a 12-MP crop cost a second)
    scale = getattr(img, "scale", None)
    sub = np.ascontiguousarray(img.raw[r0:r1, c0:c1] if scale is not None else img[r0:r1, c0:c1], dtype=np.float32)
    m = np.ascontiguousarray(M[r0:r1, c0:c1], dtype=np.float32)
    if shrink > 1:
        size = (max(1, round((c1 - c0) / shrink)), max(1, round((r1 - r0) / shrink)))
        sub, m = (cv2.resize(a, size, interpolation=cv2.INTER_AREA) for a in (sub, m))
    if scale is not None:
        sub *= np.float32(scale)
        np.clip(sub, 0.0, 1.0, out=sub)
    return sub, m


def _upright(sub, m, angle_deg):
    """The crop turned so that the line is horizontal: (image crop, coverage crop); of the two
    turning senses, the one whose coverage is lowest."""
    import cv2

    h, w = m.shape
    best = None
    for a in {float(angle_deg), -float(angle_deg)}:
        rot = cv2.getRotationMatrix2D((w / 2.0, h / 2.0), a, 1.0)
        mr = cv2.warpAffine(m, rot, (w, h), flags=cv2.INTER_LINEAR)
        rows = np.nonzero(mr.max(axis=1) > 0.3)[0]
        height = np.ptp(rows) if rows.size else np.inf
        if best is None or height < best[0]:
            best = (height, rot, mr)
    _, rot, mr = best
    ir = cv2.warpAffine(sub, rot, (w, h), flags=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
    return (ir if ir.ndim == 3 else ir[..., None]), mr


def _mark_like(img, color, alpha, k):
    """(share of the mark per pixel, reliable pixels) from the blend over the local median."""
    import cv2

    k = min(int(k) | 1, 255)
    # the median of 8-bit levels (OpenCV's large-window median takes 8 bits): the photo under the
    # strokes, which cover under half of any window about a line's height wide
    B = np.stack([cv2.medianBlur(np.clip(np.round(img[..., c] * 255), 0, 255).astype(np.uint8), k) / 255.0
                  for c in range(img.shape[2])], axis=2)
    col = np.asarray(color, float)[: img.shape[2]].reshape(1, 1, -1)
    d = col - B
    n2 = (d * d).sum(axis=2)
    share = ((img - B) * d).sum(axis=2) / np.maximum(alpha * n2, 1e-12)
    return share, alpha * np.sqrt(n2 / img.shape[2]) >= MIN_CONTRAST


def text_beside(y, M, alpha, color, angle_deg) -> dict | None:
    """Where text of the mark's colour and opacity sits beside the removed line, or None.

    Parameters
    ----------
    y : (H, W, C) float array in [0, 1]
        The input image (or a view whose slices are arrays: only the crop around the mark is read).
    M : (H, W) array
        Coverage of the mark that was removed.
    alpha : float
        The mark's opacity.
    color : array_like
        The mark's colour (C,) in [0, 1].
    angle_deg : float
        The line's angle.

    Returns
    -------
    dict or None
        ``side`` ("above" or "below"), ``density`` of mark-like pixels there, ``line_density`` (the
        removed line's, on the input) and ``photo_density`` (bands further away).

    Examples
    --------
    >>> from odnn_sep.image.render import render_text
    >>> from odnn_sep.image.synth import photo_like
    >>> photo = photo_like((200, 320), random_state=3) / 255.0
    >>> g1, g2 = render_text("Studio 2024", "DejaVuSans-Bold", 28), render_text("John Doe", "DejaVuSans-Bold", 28)
    >>> M1 = np.zeros(photo.shape[:2]); M1[50:50 + g1.shape[0], 40:40 + g1.shape[1]] = g1
    >>> M2 = np.zeros(photo.shape[:2]); M2[92:92 + g2.shape[0], 60:60 + g2.shape[1]] = g2
    >>> aM = 0.5 * np.maximum(M1, M2)[..., None]
    >>> y = (1 - aM) * photo + aM
    >>> text_beside(y, M1, 0.5, [1.0, 1.0, 1.0], 0.0)["side"]
    'below'
    >>> text_beside((1 - 0.5 * M1[..., None]) * photo + 0.5 * M1[..., None], M1, 0.5, [1.0, 1.0, 1.0], 0.0) is None
    True
    """
    M = np.asarray(M, float)
    if not (M > 0.05).any() or not alpha > 0:
        return None
    rows = np.nonzero((M > 0.05).any(axis=1))[0]
    h0 = max(int(np.ptp(rows)) + 1, 4)
    shrink = _upright_height(M, angle_deg) / WORK_LINE_PX
    img, m = _upright(*_crop(y, M, 7 * h0, shrink), angle_deg)
    on = m > 0.05
    rr = np.nonzero(on.any(axis=1))[0]
    cc = np.nonzero(on.any(axis=0))[0]
    if not rr.size:
        return None
    r0, r1, c0, c1 = rr.min(), rr.max() + 1, cc.min(), cc.max() + 1
    h, w = r1 - r0, c1 - c0
    share, ok = _mark_like(img, color, alpha, k=max(5, int(KERNEL_OF_LINE * h)))
    hit = ok & (share >= 0.5) & (share <= 1.5)
    import cv2
    near_mark = cv2.dilate(on.astype(np.uint8), np.ones((3, 3), np.uint8)).astype(bool)

    def density(a, b, cols=(c0, c1), exclude=True):
        a, b = max(0, int(a)), min(img.shape[0], int(b))
        x0, x1 = max(0, int(cols[0])), min(img.shape[1], int(cols[1]))
        if b - a < 2 or x1 - x0 < 2:
            return None
        sel = ok[a:b, x0:x1] & ~near_mark[a:b, x0:x1] if exclude else ok[a:b, x0:x1]
        n = int(sel.sum())
        return None if n < 0.2 * (b - a) * (x1 - x0) else float(hit[a:b, x0:x1][sel].sum()) / n


    line = density(r0, r1, exclude=False)
    if line is None or line <= 0:
        return None
    wide = (c0 - 0.25 * w, c1 + 0.25 * w)
    # the photo's own rate: bands 4-7 line heights away, and beside the line (a median, so that
    # other lines of a long mark among them do not decide it)
    far = [density(r1 + k * h, r1 + (k + 1) * h, wide) for k in (4, 5, 6)] + \
          [density(r0 - (k + 1) * h, r0 - k * h, wide) for k in (4, 5, 6)] + \
          [density(r0, r1, (c0 - 1.5 * w, c0 - 0.25 * w)), density(r0, r1, (c1 + 0.25 * w, c1 + 1.5 * w))]
    far = [d for d in far if d is not None]
    base = float(np.median(far)) if far else 0.0
    best = None
    for off in np.linspace(0.1, 1.2, 12):      # line spacings of 1.1 to 2.2 line heights
        for side, sign in (("above", -1), ("below", 1)):
            edge = r1 if sign > 0 else r0

            def band(lo, hi, edge=edge, sign=sign):
                # rows lo..hi line heights from the removed line's edge, on this side
                a, b = (edge + lo * h, edge + hi * h) if sign > 0 else (edge - hi * h, edge - lo * h)
                return density(a, b, wide)
            d = band(off, off + 1)
            if d is None or d < SHARE_OF_LINE * line or d < OVER_PHOTO * base + 0.01:
                continue
            # a line of text stands out of the rows beside it: the gap between the lines, and the rows
            # just beyond; a photo's texture fills them alike
            around = [v for v in (band(0.02, off) if off >= 0.3 else None, band(off + 1, off + 1.5)) if v is not None]
            contrast = d / max(max(around, default=0.0), 0.01)
            if contrast >= LINE_CONTRAST and (best is None or d > best["density"]):
                best = {"side": side, "density": round(d, 4), "line_density": round(line, 4),
                        "photo_density": round(base, 4), "contrast": round(contrast, 2)}
    return best
