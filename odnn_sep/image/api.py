"""``unwatermark``: find a visible text watermark (or use the user's mask), estimate it, invert it."""
from __future__ import annotations

import dataclasses
import logging
import time

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.image.detect import CLIP as SCORE_MAX
from odnn_sep.image.detect import THRESHOLD as MIN_SCORE
from odnn_sep.image.textmode import WORK_MAX_PX, text_mode

log = logging.getLogger(__name__)

# A watermark line longer than this is not a watermark (and would render to an unbounded template).
MAX_TEXT_CHARS = 200
# Without --font, a mark found below this detection score gets a warning to check the output: on a
# development case (an Atkinson 800 mark found with DejaVu at 0.208) the opacity was underestimated
# and the letters stayed readable while every residual measure called the mark removed.
LOW_CONFIDENCE_SCORE = 0.3
# Mask mode: a removal that leaves this share of the mark's step along its edges, of either sign (a
# negative share: the letters removed too far, in the opposite colour), is not a removal.
STEP_LEFT = 0.15


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

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.api import UnwatermarkResult
    >>> r = UnwatermarkResult(np.zeros((32, 48, 3)), 0.3, np.ones(3), np.zeros((32, 48)),
    ...                       np.zeros((32, 48), bool), {})
    >>> r.alpha, r.image.shape, int(r.lost.sum())
    (0.3, (32, 48, 3), 0)
    """

    image: np.ndarray
    alpha: float
    color: np.ndarray
    mask: np.ndarray
    lost: np.ndarray
    report: dict


def _check_text_options(text, min_score) -> None:
    """One-line errors for a detection threshold or a text that cannot be meant."""
    try:
        ms = float(min_score)
    except (TypeError, ValueError):
        raise InputError(f"min_score/--min-score must be a number in (0, {SCORE_MAX:g}]; got {min_score!r}") from None
    # the detection score lies in [0, CLIP]: a threshold above CLIP could never be reached
    if not (np.isfinite(ms) and 0.0 < ms <= SCORE_MAX):
        raise InputError(f"min_score/--min-score must be finite and in (0, {SCORE_MAX:g}] (the detection score's range; "
                         f"default {MIN_SCORE}); got {min_score!r}")
    if text is None:
        return
    t = str(text)
    if len(t) > MAX_TEXT_CHARS:
        raise InputError(f"text/--text has {len(t)} characters, more than {MAX_TEXT_CHARS}; give the "
                         f"watermark's visible text (one line)")


def _residual(out, inp, M, prior, b, random_state) -> dict:
    """What is left of the mark in the restored box ``out`` (``residual.measure``): the detection
    statistic under the estimated coverage and under the registered rendering (text mode)."""
    from odnn_sep.image.residual import measure

    covs = [M[b[1]:b[3], b[0]:b[2]]]
    if prior is not None:
        covs.append(prior[b[1]:b[3], b[0]:b[2]])
    return measure(out, inp, *covs, random_state=random_state, rims=prior is not None)


def color_report(color, planes) -> dict:
    """The report's ``color`` (and ``color_hex`` for colour images) of a fitted mark colour in [0, 1].

    Parameters
    ----------
    color : array_like
        (C,) mark colour in [0, 1].
    planes : Planes
        The split input (:func:`odnn_sep.image.io.split`); only ``planes.grey`` is used.

    Returns
    -------
    dict
        ``{"color": [...]}`` rounded to 5 decimals, plus ``"color_hex"`` for colour images.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.api import color_report
    >>> from odnn_sep.image.io import split
    >>> color_report([1.0, 0.5, 0.0], split(np.zeros((32, 48, 3), np.uint8)))
    {'color': [1.0, 0.5, 0.0], 'color_hex': '#ff8000'}
    >>> color_report([0.25], split(np.zeros((32, 48), np.uint8)))
    {'color': [0.25]}
    """
    col = np.asarray(color, dtype=float)
    out = {"color": [round(float(v), 5) for v in col]}
    if not planes.grey:
        out["color_hex"] = "#" + "".join(f"{int(round(v * 255)):02x}" for v in col[:3])
    return out


def _estimate(y, text, font, mask, mask_invert, min_score, angle_range, max_marks, random_state, near=None):
    """(y, M, alpha, colour, report fields, registered rendering or None) of text or mask mode.

    Why long (10 parameters): it forwards ``unwatermark``'s options to the mode that uses them."""
    H, W = y.shape[:2]
    region = prepared = prior = None
    if mask is not None:
        from odnn_sep.image.maskprep import prepare_mask

        prepared = prepare_mask(mask, (H, W), invert=mask_invert)
        region = prepared.region
    if text:
        if max(H, W) <= WORK_MAX_PX:
            y = y.full()
        M, alpha, color, info, prior = text_mode(y, str(text), font, region, min_score, angle_range,
                                                  max_marks, random_state, near=near)
    else:
        from odnn_sep.image.maskmode import mask_mode

        M, alpha, color, info = mask_mode(y, prepared, random_state)
    return y, M, alpha, color, info, prior


def _restore(planes, y, M, alpha, color, prior, inpaint_lost, random_state, step=False, copy_box=None):
    """(restored image, lost pixels (H, W), residual-mark report) of the blend inverted in the mark's box
    only (the rest is copied unchanged). ``step``: also the signed step left along the mark's edges
    (``residual.step_left``; mask mode, whose shape and opacity come from the data alone): a mark
    removed too far, or not far enough, by more than ``STEP_LEFT`` of its step and ``VISIBLE_LEVELS``
    is visible. ``copy_box``: one copy's box (text mode), the template of the copies still looked for
    in the rest of the output (``residual_copies.copies_left``)."""
    from odnn_sep.image.estimate import invert
    from odnn_sep.image.io import paste

    H, W = y.shape[:2]
    lost = np.zeros((H, W), bool)
    nz = np.nonzero(M > 0)
    if not nz[0].size:
        return paste(planes), lost, {"score": 0.0, "contrast_levels": 0.0, "edge_left": 0.0,
                                     "threshold": MIN_SCORE, "visible": False, "second_colour": None}
    b = (max(0, nz[1].min() - 4), max(0, nz[0].min() - 4), min(W, nz[1].max() + 5), min(H, nz[0].max() + 5))
    o, lo = invert(y[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]], alpha, color, levels=planes.levels,
                   inpaint=inpaint_lost)
    lost[b[1]:b[3], b[0]:b[2]] = lo
    inp = y[b[1]:b[3], b[0]:b[2]]
    if prior is None:
        res = _residual(o, inp, M, prior, b, random_state)
    else:
        # text mode: copies of the mark outside the removed box (tiled marks cut by the border),
        # looked for on a second thread while the box's residual is measured (both read only, and
        # mostly in OpenCV and NumPy, which let go of the interpreter: 0.3 s less on 12 megapixels)
        from concurrent.futures import ThreadPoolExecutor

        from odnn_sep.image.residual_copies import copies_left

        with ThreadPoolExecutor(1) as ex:
            job = ex.submit(copies_left, y, o, M, b, copy_box=copy_box, random_state=random_state)
            res = _residual(o, inp, M, prior, b, random_state)
            left = job.result()
        res["copies_left"] = left
        if left is not None:
            res["visible"] = True
        # letters of the text the input does not show, drawn in the opposite colour by the inversion
        from odnn_sep.image.residual_drawn import drawn_parts

        drawn = drawn_parts(o, np.asarray(inp, dtype=np.float64), M[b[1]:b[3], b[0]:b[2]], alpha, color)
        for part in drawn:
            part["at"] = (round(part["at"][0] + b[0], 1), round(part["at"][1] + b[1], 1))
        res["drawn"] = drawn or None
        if drawn:
            res["visible"] = True
    if step:
        from odnn_sep.image.residual import VISIBLE_LEVELS, step_left

        share, levels = step_left(o, np.asarray(inp, dtype=np.float64), M[b[1]:b[3], b[0]:b[2]],
                                  random_state=random_state)
        res["step_left"] = round(share, 3)
        res["step_levels"] = round(levels, 2)
        if abs(share) >= STEP_LEFT and levels >= VISIBLE_LEVELS:
            res["visible"] = True
    return paste(planes, o, b), lost, res


def unwatermark(image: np.ndarray, *, text: str | None = None, font: str | None = None,
                mask: np.ndarray | None = None, min_score: float | None = None, angle_range: float = 45.0,
                max_marks: int = 64, inpaint_lost: bool = True, random_state: int | None = 0,
                mask_invert: bool | None = None, reference: np.ndarray | None = None,
                check_beside: bool = True, near: float | None = None) -> UnwatermarkResult:
    """Remove a visible (alpha-blended) text watermark.

    Why long (13 parameters): the public keyword API, one option per command-line flag (and ``near``).

    Parameters
    ----------
    image : (H, W), (H, W, 3) or (H, W, 4) array, uint8, uint16 or float in [0, 1]
    text : the watermark's text; it is rendered and found in the image (position, size, angle, repeats).
        Several lines (separated by line breaks) are found and removed one after the other
        (:mod:`~odnn_sep.image.textlines`)
    font : font file path or name (e.g. ``"DejaVuSans-Bold"``); default: try the common fonts found
    mask : (H, W) array, nonzero over the watermark's area; without ``text`` the mark's shape is
        estimated inside it (the coverage M is unknown in [0, 1] there: a rough box is fine; nothing
        found raises ``InputError``), with ``text`` the search is restricted to it. A greyscale mask
        with many intermediate values counts over its support; see ``maskprep`` and ``maskmode``
    mask_invert : the mask is black on white (True), white on black (False); None: read as inverted
        when it marks most of the image (with a warning)
    reference : a logo image (array, with or without alpha channel) to find (position, scale 0.25-4x,
        rotation within ``angle_range``, tiled copies) and remove; see ``refmode``. The report's
        ``residual_mark`` says whether the mark is still visible in the output
    check_beside : text mode: look for text of the mark's colour and opacity beside the line removed
        (another line of the mark, not given: a warning and ``residual_mark.text_beside``)
    near : text mode: the angle (degrees) of another line of the same mark, found already; the text
        is searched near that angle first (``textmode.near_match``), and at every angle only when
        nothing is found there. Given by ``textlines`` for a mark's later lines.
    min_score : detection threshold of text mode (``detect.detection_score``: mean log-ratio of the
        edge patches' photo-only residual to their residual under the mark, predicted out of
        sample); default ``MIN_SCORE``, just above the best chance score on clean photos

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
    from odnn_sep.image.io import split

    if reference is not None:
        from odnn_sep.image.refmode import reference_mode

        return reference_mode(image, reference, angle_range=angle_range, max_copies=max_marks, min_score=min_score,
                              inpaint_lost=inpaint_lost, random_state=random_state)
    t0 = time.perf_counter()
    if min_score is None:
        min_score = MIN_SCORE
    _check_text_options(text, min_score)
    if text is not None and ("\n" in str(text) or "\r" in str(text)):
        from odnn_sep.image.textlines import split_lines, unwatermark_lines

        lines = split_lines(text)
        if len(lines) > 1:   # several lines: each found and removed in turn (textlines.py)
            return unwatermark_lines(image, lines, font=font, mask=mask, min_score=min_score, angle_range=angle_range,
                                     max_marks=max_marks, inpaint_lost=inpaint_lost, random_state=random_state,
                                     mask_invert=mask_invert)
        text = lines[0] if lines else ""
    if (text is None or not str(text).strip()) and mask is None:
        raise InputError("give the watermark's text (text=/--text) or a mask of its area (mask=/--mask); got neither")
    planes = split(image)
    y = planes.view  # float crops on demand: large images are never converted whole
    H, W = y.shape[:2]
    report: dict = {"mode": "text" if text else "mask", "image_size": [W, H], "channels": int(y.shape[2])
                    + (1 if planes.alpha is not None else 0), "bit_depth": int(planes.dtype.itemsize * 8)}
    y, M, alpha, color, info, prior = _estimate(y, text, font, mask, mask_invert, min_score, angle_range,
                                                max_marks, random_state, near=near)
    copy_box = info.pop("_copy_box", None)  # one copy's box (text mode), not a report field
    report.update(info)
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(1) as pool:
        # the line-beside check reads the input only: on a second thread while the blend is inverted
        # and its residual measured (mostly NumPy and OpenCV, which let go of the interpreter)
        beside = pool.submit(_text_beside, y, M, alpha, color, report.get("angle_deg")) \
            if text and check_beside else None
        restored, lost, report["residual_mark"] = _restore(planes, y, M, alpha, color, prior, inpaint_lost,
                                                           random_state, step=not text and not info.get("opaque"),
                                                           copy_box=copy_box)
        found = beside.result() if beside is not None else None
    report.update({"alpha": round(float(alpha), 5), **color_report(color, planes),
                   "mark_pixels": int((M > 0.05).sum()), "lost_pixels": int(lost.sum()),
                   "runtime_s": round(time.perf_counter() - t0, 3)})
    if beside is not None and not report["residual_mark"].get("visible"):
        report["residual_mark"]["text_beside"] = found
        if found is not None:
            log.warning("text of the mark's colour and opacity remains %s the line removed (another line of the "
                        "mark?): give every line of the mark, separated by line breaks (--text $'line 1\\nline 2')",
                        found["side"])
    score = report.get("match_score")
    if text and font is None and score is not None and score < LOW_CONFIDENCE_SCORE \
            and not report["residual_mark"].get("visible"):
        log.warning("the mark was found only just over the detection threshold (score %.3f < %g) with a font "
                    "the tool guessed: a fainter copy of its letters may remain; check the output, or give "
                    "--font with the mark's font file", score, LOW_CONFIDENCE_SCORE)
    return UnwatermarkResult(restored, float(alpha), np.asarray(color), M, lost, report)


def _text_beside(y, M, alpha, color, angle_deg):
    """Where text of the mark's colour and opacity sits beside the line removed (``residual_beside``)."""
    from odnn_sep.image.residual_beside import text_beside

    return text_beside(y, M, alpha, color, float(angle_deg or 0.0))


__all__ = ["unwatermark", "UnwatermarkResult", "color_report", "MIN_SCORE", "WORK_MAX_PX"]
