"""A text watermark of several lines: each line is found and removed in turn.

A mark such as "Studio 2024" over "John Doe" is several lines of one colour and opacity; the
search renders and registers one line at a time (their spacing and alignment are the mark's own).
Each line is searched in the output of the lines before it, so a removed line cannot be taken for
the next. The outcome is honest per line: a line that is not found, or still visible after its
removal, makes the whole mark "still visible" (``residual_mark.visible``), and the report lists
every line with what happened to it.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import InputError, MarkNotFoundError

# More lines than this is not a watermark (a limit on the work: each line is a whole search).
MAX_LINES = 8


def split_lines(text: str) -> list[str]:
    """The non-empty lines of ``text`` (``\\n``, ``\\r\\n`` or ``\\r`` between them), stripped.

    Examples
    --------
    >>> split_lines("Studio 2024\\n  John Doe \\n")
    ['Studio 2024', 'John Doe']
    """
    return [ln.strip() for ln in str(text).replace("\r\n", "\n").replace("\r", "\n").split("\n") if ln.strip()]


def unwatermark_lines(image, lines, **options):
    """:func:`~odnn_sep.image.api.unwatermark` of every line of a multi-line text mark, in turn.

    Parameters
    ----------
    image : array
        As for ``unwatermark``.
    lines : list of str
        The mark's lines, top to bottom (:func:`split_lines`).
    **options
        ``unwatermark``'s other options (font, min_score, ...).

    Returns
    -------
    UnwatermarkResult
        The image with every line found removed; ``mask`` and ``lost`` over all lines; ``alpha``,
        ``color`` and the report's placement fields are the first found line's; ``report["lines"]``
        lists every line (text, outcome, match score, alpha, residual mark) and ``residual_mark``
        is visible when any line was not found or is still visible.

    Raises
    ------
    MarkNotFoundError
        When no line is found.

    Examples
    --------
    >>> from odnn_sep.image import make_watermark_demo
    >>> y, clean, truth = make_watermark_demo(random_state=2)
    >>> r = unwatermark_lines(y, [truth["text"], "NOT THERE"], font="DejaVuSans-Bold")
    >>> [ln["outcome"] for ln in r.report["lines"]], r.report["residual_mark"]["visible"]
    (['removed', 'not found'], True)
    """
    from odnn_sep.image.api import UnwatermarkResult, unwatermark

    if len(lines) > MAX_LINES:
        raise InputError(f"text/--text has {len(lines)} lines, more than {MAX_LINES}; give the watermark's "
                         f"visible lines only")
    current, first, masks, lost, per_line = image, None, [], [], []
    for line in lines:
        try:
            r = unwatermark(current, text=line, check_beside=False, near=_near(first), **options)
        except MarkNotFoundError as exc:
            per_line.append({"text": line, "outcome": "not found", "why": str(exc)})
            continue
        current = r.image
        first = first or r
        masks.append(r.mask)
        lost.append(r.lost)
        res = r.report.get("residual_mark") or {}
        per_line.append({"text": line, "outcome": "still visible" if res.get("visible") else "removed",
                         "match_score": r.report.get("match_score"), "alpha": r.report.get("alpha"),
                         "color_hex": r.report.get("color_hex"), "font": r.report.get("font"),
                         "residual_mark": res})
    if first is None:
        raise MarkNotFoundError(f"none of the {len(lines)} lines of the text was found in the image "
                                f"({'; '.join(ln['why'] for ln in per_line)})")
    report = dict(first.report)
    report["text"] = "\n".join(lines)
    report["lines"] = per_line
    report["residual_mark"] = _combined_residual(per_line)
    report["mark_pixels"] = int(sum(int((m > 0.05).sum()) for m in masks))
    report["lost_pixels"] = int(np.logical_or.reduce(lost).sum())
    return UnwatermarkResult(current, first.alpha, first.color, np.maximum.reduce(masks),
                             np.logical_or.reduce(lost), report)


def _near(first) -> float | None:
    """The angle of the first found line, for the later lines' search (the lines of one mark share
    it); None before a line is found, so a line not found constrains nothing.

    Examples
    --------
    >>> _near(None) is None
    True
    """
    return None if first is None else float(first.report["angle_deg"])


def _combined_residual(per_line) -> dict:
    """The residual mark of the whole text: the worst found line's fields, visible when any line is
    still visible or was not found, with the lines in question named."""
    found = [ln for ln in per_line if ln["outcome"] != "not found"]
    worst = next((ln for ln in found if ln["outcome"] == "still visible"), found[0])
    out = dict(worst["residual_mark"])
    missing = [ln["text"] for ln in per_line if ln["outcome"] == "not found"]
    visible = [ln["text"] for ln in found if ln["outcome"] == "still visible"]
    out["visible"] = bool(missing or visible)
    out["lines_not_found"] = missing
    out["lines_still_visible"] = visible
    return out
