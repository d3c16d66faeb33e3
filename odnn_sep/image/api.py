"""``unwatermark``: find a visible text watermark (or use the user's mask), estimate it, invert it."""
from __future__ import annotations

import dataclasses
import logging
import time

import numpy as np

from odnn_sep.errors import InputError, NotIdentifiableError

log = logging.getLogger(__name__)

# Detection threshold on the share of the edge patches' photo-only residual that the mark explains
# (``estimate.detection_score``). The best placement the search finds for a random text on a clean
# photo (no mark; every default font, angles +-45 deg) scores below ~0.18 (BENCHMARKS.md reports the
# check); marks of opacity >= 0.3 usually score 0.3-0.99.
MIN_SCORE = 0.2

# Images larger than this (longest side, px) are searched on a reduced copy; only the found marks
# are refined at full resolution.
WORK_MAX_PX = 1024


@dataclasses.dataclass
class UnwatermarkResult:
    """Output of :func:`unwatermark`.

    Attributes
    ----------
    image : restored image, same shape and dtype as the input (alpha channel untouched)
    alpha : opacity of the mark
    color : mark colour, (C,) in [0, 1]
    mask : (H, W) coverage M of the mark (glyph coverage in [0, 1])
    lost : (H, W) bool, pixels whose data were gone and were inpainted
    report : JSON-ready dict
    """

    image: np.ndarray
    alpha: float
    color: np.ndarray
    mask: np.ndarray
    lost: np.ndarray
    report: dict


def _color_report(color, planes) -> dict:
    col = np.asarray(color, dtype=float)
    out = {"color": [round(float(v), 5) for v in col]}
    if not planes.grey:
        out["color_hex"] = "#" + "".join(f"{int(round(v * 255)):02x}" for v in col[:3])
    return out


def unwatermark(image, *, text: str | None = None, font=None, mask=None, min_score: float = MIN_SCORE,
                angle_range: float = 45.0, max_marks: int = 64, inpaint_lost: bool = True,
                random_state=0) -> UnwatermarkResult:
    """Remove a visible (alpha-blended) text watermark.

    Parameters
    ----------
    image : (H, W), (H, W, 3) or (H, W, 4) array, uint8, uint16 or float in [0, 1]
    text : the watermark's text; it is rendered and found in the image (position, size, angle, repeats)
    font : font file path or name (e.g. ``"DejaVuSans-Bold"``); default: try the common fonts found
    mask : (H, W) array, nonzero over the watermark's area; without ``text`` the mark's shape is
        estimated inside it, with ``text`` the search is restricted to it
    min_score : detection threshold (share of edge variance explained by the mark)

    Returns
    -------
    UnwatermarkResult

    Examples
    --------
    >>> from odnn_sep.image import make_watermark_demo, unwatermark
    >>> y, clean, truth = make_watermark_demo(random_state=2)
    >>> res = unwatermark(y, text=truth["text"], font="DejaVuSans-Bold")
    >>> abs(res.alpha - truth["alpha"]) < 0.02
    True
    """
    from odnn_sep.image.estimate import fit_blend, invert
    from odnn_sep.image.io import paste, split

    t0 = time.perf_counter()
    if (text is None or not str(text).strip()) and mask is None:
        raise InputError("give the watermark's text (text=/--text) or a mask of its area (mask=/--mask); got neither")
    planes = split(image)
    y = planes.view  # float crops on demand: large images are never converted whole
    H, W = y.shape[:2]
    region = None
    if mask is not None:
        mk = np.asarray(mask)
        if mk.ndim == 3:
            mk = mk[:, :, :3].max(axis=2) if mk.shape[2] >= 3 else mk[:, :, 0]
        if mk.shape[:2] != (H, W):
            raise InputError(f"mask size {mk.shape[1]}x{mk.shape[0]} differs from the image size {W}x{H}; "
                             f"pass a mask of the same size as the image")
        region = mk > 0
        if not region.any():
            raise InputError("mask has no nonzero pixels; mark the watermark's area with nonzero values")
    report: dict = {"mode": "text" if text else "mask", "image_size": [W, H], "channels": int(y.shape[2])
                    + (1 if planes.alpha is not None else 0), "bit_depth": int(planes.dtype.itemsize * 8)}
    if text:
        if max(H, W) <= WORK_MAX_PX:
            y = y.full()
        M, alpha, color, info = _text_mode(y, str(text), font, region, min_score, angle_range, max_marks,
                                           random_state)
        report.update(info)
    else:
        from odnn_sep.image.maskmode import estimate_shape

        ys, xs = np.nonzero(region)
        pad = 8
        x0, y0 = max(0, xs.min() - pad), max(0, ys.min() - pad)
        x1, y1 = min(W, xs.max() + pad + 1), min(H, ys.max() + pad + 1)
        crop = y[y0:y1, x0:x1]
        m, col0 = estimate_shape(crop, region[y0:y1, x0:x1])
        alpha = float(np.quantile(m[m > 0.05], 0.9)) if (m > 0.05).sum() >= 10 else float(m.max())
        Mc = np.clip(m / max(alpha, 1e-6), 0.0, 1.0)
        color = col0
        try:
            fit = fit_blend(crop, Mc, random_state=random_state)
            if 0.02 < fit.alpha <= 1.0 and fit.explained > min_score:
                alpha, color = fit.alpha, fit.color
                Mc = np.clip(m / alpha, 0.0, 1.0)
        except NotIdentifiableError:
            pass
        M = np.zeros((H, W), np.float32)
        M[y0:y1, x0:x1] = Mc
        report.update({"bbox": [int(x0), int(y0), int(x1), int(y1)], "marks": []})
    lost = np.zeros((H, W), bool)
    nz = np.nonzero(M > 0)
    restored = None
    if nz[0].size:  # only the mark's box is inverted and written back; the rest is copied unchanged
        b = (max(0, nz[1].min() - 4), max(0, nz[0].min() - 4), min(W, nz[1].max() + 5), min(H, nz[0].max() + 5))
        o, lo = invert(y[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]], alpha, color, levels=planes.levels,
                       inpaint=inpaint_lost)
        restored = paste(planes, o, b)
        lost[b[1]:b[3], b[0]:b[2]] = lo
    if restored is None:
        restored = paste(planes)
    report.update({"alpha": round(float(alpha), 5), **_color_report(color, planes),
                   "mark_pixels": int((M > 0.05).sum()), "lost_pixels": int(lost.sum()),
                   "runtime_s": round(time.perf_counter() - t0, 3)})
    return UnwatermarkResult(restored, float(alpha), np.asarray(color), M, lost, report)


def _text_mode(y, text, font, region, min_score, angle_range, max_marks, random_state, reduced=False):
    from odnn_sep.image.estimate import detection_score, fit_blend
    from odnn_sep.image.locate import Match, repeats, search
    from odnn_sep.image.register import refine, render_at
    from odnn_sep.image.render import default_fonts, resolve_font

    H, W = y.shape[:2]
    if max(H, W) > WORK_MAX_PX:
        return _text_mode_large(y, text, font, region, min_score, angle_range, max_marks, random_state)
    fonts = [resolve_font(font)] if font is not None else default_fonts()
    off = (0, 0)
    ys = y
    if region is not None:  # search only where the user says the mark is
        rr, cc = np.nonzero(region)
        pad = 16
        off = (max(0, cc.min() - pad), max(0, rr.min() - pad))
        ys = y[off[1]:min(H, rr.max() + pad + 1), off[0]:min(W, cc.max() + pad + 1)]
    cands = search(ys, text, fonts, angle_range=angle_range, max_hypotheses=20, per_size_bin=2)
    # screen every hypothesis with a quick blend fit (share of edge variance the mark explains),
    # then refine the best three: correlation alone ranks small spurious templates too high
    screened = []
    for c in cands:
        m, box = render_at(text, c.font, c.size, c.angle, (c.center[0] + off[0], c.center[1] + off[1]), (H, W))
        if m.size == 0:
            continue
        try:
            f = fit_blend(y[box[1]:box[3], box[0]:box[2]], m, max_patches=300, irls=0, xatol=2e-3,
                          random_state=random_state)
        except NotIdentifiableError:
            continue
        screened.append((f.explained, c))
    screened.sort(key=lambda t: -t[0])
    best, best_nc = None, None
    for sc0, c in screened[:3]:
        if best is not None and best.fit.explained >= 0.5 and sc0 < 0.8 * screened[0][0]:
            break  # a clear detection: no need to refine clearly weaker hypotheses (another font at
            # the same place screens about as well, and is refined)
        try:
            # on a reduced copy the placement is only a start for the full-resolution registration
            p = refine(y, text, c.font, c.size, c.angle, (c.center[0] + off[0], c.center[1] + off[1]),
                       iterations=30 if reduced else 60, whole_sizes=not reduced, random_state=random_state)
        except NotIdentifiableError:
            continue
        if best is None or p.fit.explained > best.fit.explained:
            best, best_nc = p, c
    score = 0.0
    if best is not None:
        x0, y0, x1, y1 = best.box
        score = detection_score(y[y0:y1, x0:x1], best.coverage, random_state=random_state)
    if best is None or score < min_score:
        raise InputError(f"text {text!r} not found in the image (best match score {score:.3f}, needs >= "
                         f"{min_score:g}); check --text/--font or give --mask")
    placed = [best]
    if max_marks > 1:
        ref = Match(best.font, best.size, best.angle, (best.center[0] - off[0], best.center[1] - off[1]),
                    best_nc.score)
        for r in repeats(ys, text, ref, max_marks=max_marks)[1:]:
            rc = (r.center[0] + off[0], r.center[1] + off[1])
            m, box = render_at(text, best.font, best.size, best.angle, rc, (H, W))
            if m.size == 0:
                continue
            try:
                if detection_score(y[box[1]:box[3], box[0]:box[2]], m) < min_score:
                    continue
                p = refine(y, text, best.font, best.size, best.angle, (r.center[0] + off[0], r.center[1] + off[1]),
                           iterations=30, whole_sizes=not reduced, random_state=random_state)
            except NotIdentifiableError:
                continue
            x0, y0, x1, y1 = p.box
            if detection_score(y[y0:y1, x0:x1], p.coverage) >= min_score:
                placed.append(p)
    return _assemble(y, text, placed, score, min_score, random_state)


def _assemble(y, text, placed, score, min_score, random_state):
    """Coverage of all placed copies, one opacity and colour for them, and the report fields."""
    from odnn_sep.image.estimate import fit_blend

    H, W = y.shape[:2]
    best = placed[0]
    M = np.zeros((H, W), np.float32)
    for p in placed:
        x0, y0, x1, y1 = p.box
        M[y0:y1, x0:x1] = np.maximum(M[y0:y1, x0:x1], p.coverage)
    if len(placed) > 1:  # one opacity and colour for all copies
        nz = np.nonzero(M > 0)
        b = (nz[1].min(), nz[0].min(), nz[1].max() + 1, nz[0].max() + 1)
        fit = fit_blend(y[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]], random_state=random_state)
    else:
        fit = best.fit
    nz = np.nonzero(M > 0.05)
    info = {
        "text": text, "font": str(best.font), "font_size_px": round(best.size, 3), "angle_deg": round(best.angle, 3),
        "center": [round(best.center[0], 2), round(best.center[1], 2)],
        "bbox": [int(nz[1].min()), int(nz[0].min()), int(nz[1].max()) + 1, int(nz[0].max()) + 1],
        "match_score": round(float(score), 4), "match_score_threshold": min_score,
        "alpha_stderr": round(float(fit.alpha_stderr), 6), "patches": int(fit.n_patches),
        "marks": [{"center": [round(p.center[0], 2), round(p.center[1], 2)], "angle_deg": round(p.angle, 3),
                   "font_size_px": round(p.size, 3), "score": round(float(p.fit.explained), 4)} for p in placed],
    }
    return M, fit.alpha, fit.color, info


def _text_mode_large(y, text, font, region, min_score, angle_range, max_marks, random_state):
    """Large images: find the mark(s) on a copy reduced to ``WORK_MAX_PX``, then refine each placement
    on the full-resolution crop around it only.

    The correlation search works on a pyramid capped at 768 px anyway, so the reduced copy loses no
    detections; what it saves is the full-resolution patch fits and registrations of every
    hypothesis (a 12-megapixel photo spent most of its time there).
    """
    import cv2

    from odnn_sep.image.estimate import detection_score
    from odnn_sep.image.register import refine

    H, W = y.shape[:2]
    f = WORK_MAX_PX / max(H, W)
    w, h = max(1, round(W * f)), max(1, round(H * f))
    if hasattr(y, "reduced"):
        small = y.reduced(w, h)
    else:
        small = cv2.resize(np.asarray(y, dtype=np.float32), (w, h), interpolation=cv2.INTER_AREA)
        small = (small if small.ndim == 3 else small[:, :, None]).astype(np.float64)
    reg = None
    if region is not None:
        reg = cv2.resize(region.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
        if not reg.any():
            reg = cv2.resize(region.astype(np.uint8), (w, h), interpolation=cv2.INTER_AREA) > 0
    _, _, _, info = _text_mode(small, text, font, reg, min_score, angle_range, max_marks, random_state,
                               reduced=True)
    fx, fy = W / w, H / h
    placed, scores = [], []
    for k, mk in enumerate(info["marks"]):
        # pixel centres: x_full = (x_small + 0.5) * W / w - 0.5
        c = ((mk["center"][0] + 0.5) * fx - 0.5, (mk["center"][1] + 0.5) * fy - 0.5)
        try:
            p = refine(y, text, info["font"], mk["font_size_px"] / f, mk["angle_deg"], c,
                       iterations=40 if k == 0 else 20, random_state=random_state)
        except NotIdentifiableError:
            continue
        x0, y0, x1, y1 = p.box
        sc = detection_score(y[y0:y1, x0:x1], p.coverage, random_state=random_state)
        if sc >= min_score:
            placed.append(p)
            scores.append(sc)
    if not placed:
        raise InputError(f"text {text!r} not found in the image (best match score {info['match_score']:.3f} on a "
                         f"reduced copy, not confirmed at full resolution, needs >= {min_score:g}); check "
                         f"--text/--font or give --mask")
    order = np.argsort(-np.asarray(scores), kind="stable")
    placed = [placed[i] for i in order]
    return _assemble(y, text, placed, float(scores[order[0]]), min_score, random_state)
