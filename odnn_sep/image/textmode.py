"""Text mode of ``unwatermark``: search the rendered text, screen and register the hypotheses,
decide on detection, find repeated copies, and (for large images) do all that on a reduced copy with
only the found marks registered at full resolution."""
from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from odnn_sep.errors import MarkNotFoundError, NotIdentifiableError
from odnn_sep.image.screening import placement_score, refine_order, screen_hypotheses

log = logging.getLogger(__name__)

# Images larger than this (longest side, px) are searched on a reduced copy; only the found marks
# are refined at full resolution.
WORK_MAX_PX = 1024
# Without a pinned font, the other fonts at the best place are registered for the likelihood choice
# unless the mark is clearly detected and they screen below this share of the best screening score.
RIVAL_SCREEN_RATIO = 0.5
# When the first search finds nothing, more looks with other coarse grids (``find``); what they find
# counts only at this multiple of the detection threshold. On the development seeds (7, 11, 13, 17:
# 160 clean-photo searches) later looks scored up to 0.192 by chance, while the 16 marks they found
# (of 120 marks, besides the 96 the first look found) scored 0.40-1.18.
SECOND_LOOK_FACTOR = 1.3
# What the glyph-by-glyph look (``layoutlook``) finds counts only at this multiple of the detection
# threshold: moving each glyph is more freedom than a later look's search. Development seeds 501-502
# (34 clean-photo searches, random text and post-processing): the look scored up to 0.233 by chance
# (a 4-letter text), next 0.149; the marks it found on seeds 7 and 11 scored 0.26-0.67.
LAYOUT_LOOK_FACTOR = 1.6
# Glyph height (px) of the finer coarse grid of the last look (``find``); the first uses 10.
FINE_LOOK_HEIGHT = 14.0
# Letter spacing (em) of the spaced fonts of one more look (``find``): marks are often drawn spaced
# out, and a rendering without spacing then matches one letter at best (development seeds: marks
# spaced 0.1-0.25 em were found with this spacing and not without).
LOOK_TRACKING = 0.18
# Nelder-Mead iterations of the short registration that chooses among the hypotheses (the chosen one
# is then registered in full, 60 iterations and the whole font sizes).
QUICK_ITERATIONS = 30
# Another line of the same mark (``near_match``): its coarse grid within this many degrees of that
# line's angle (lines of one mark share it; the finer grids and the registration go on from there)
NEAR_ANGLE = 3.0


def text_mode(y, text, font, region, min_score, angle_range, max_marks, random_state, reduced=False, near=None):
    """(M (H, W), alpha, colour, report fields) of the text's mark(s) in ``y`` (float array or view).

    ``reduced``: ``y`` is a reduced copy of a large image (coarser registration, no whole sizes).
    Why long (9 parameters): ``unwatermark``'s text-mode options, passed on.

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    font : str or Path or None
        Pinned font; None tries the default fonts (and estimates the coverage from the data).
    region : np.ndarray or None
        (H, W) bool, where to search; None for everywhere.
    min_score : float
        Detection threshold.
    angle_range : float
        Largest rotation searched, degrees either way.
    max_marks : int
        Most copies of the mark.
    random_state : int or Generator
        Seed of the fits.
    reduced : bool, default False
        ``y`` is a reduced copy of a large image.
    near : float, optional
        Angle (degrees) of another line of the same mark, found already: searched first near it
        (:func:`find`).

    Returns
    -------
    M : np.ndarray
        (H, W) float32 coverage of all copies.
    alpha : float
        Opacity.
    color : np.ndarray
        (C,) mark colour.
    info : dict
        Report fields (font, size, angle, centre, match score, ...).
    prior : np.ndarray
        (H, W) registered rendering the coverage started from.

    Raises
    ------
    MarkNotFoundError
        When the text is not found (best score below ``min_score``); an ``InputError``.

    Examples
    --------
    >>> from odnn_sep.image.textmode import text_mode
    >>> import numpy as np
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> y, _ = add_text_watermark(np.full((40, 56, 3), 90, np.uint8), "Hi", size=18, center=(28, 20), alpha=0.5)
    >>> y = y / 255.0
    >>> M, alpha, color, info, prior = text_mode(y, "Hi", "DejaVuSans-Bold", None, 0.19, 0.0, 1, 0)
    >>> M.shape, round(alpha, 2), np.round(color, 2).tolist(), info["font_size_px"] > 17
    ((40, 56), 0.5, [1.0, 1.0, 1.0], True)
    """
    from odnn_sep.image.render import default_fonts, resolve_font

    H, W = y.shape[:2]
    if not reduced:
        _check_fits(y.shape, text, font)
    if max(H, W) > WORK_MAX_PX:
        return _text_mode_large(y, text, font, region, min_score, angle_range, max_marks, random_state)
    from odnn_sep.image.glyphs import fonts_for

    fonts = fonts_for(text, [resolve_font(font)] if font is not None else default_fonts(), given=font is not None)
    best, best_nc, score, off, ys = find(y, text, fonts, region, angle_range, random_state, min_score, reduced,
                                         near=near)
    if best is None or score < min_score:
        raise MarkNotFoundError(f"text {text!r} not found in the image (best match score {score:.3f}, needs >= "
                         f"{min_score:g}); check --text/--font or give --mask{_turn_hint(angle_range)}")
    placed = [best]
    if max_marks > 1:
        placed += _copies(y, ys, text, best, best_nc, off, max_marks, min_score,
                          dict(reduced=reduced, random_state=random_state))
        if region is None:  # copies of a tiled mark that the border cuts (the search places whole ones)
            from odnn_sep.image.border_copies import border_copies

            placed += border_copies(y, text, placed, max_marks - len(placed), min_score, random_state=random_state)
    return _assemble(y, text, placed, score, min_score, random_state, from_data=font is None and not reduced)


def _check_fits(shape, text, font) -> None:
    """Raise ``MarkNotFoundError`` when ``text`` is wider than the image at the smallest size searched
    in every font tried: the search would report "not found (score 0.000)" without saying why.

    Examples
    --------
    >>> from odnn_sep.image.textmode import _check_fits
    >>> _check_fits((64, 96, 3), "Hi", None) is None
    True
    >>> try:
    ...     _check_fits((40, 60, 3), "A LONG COPYRIGHT NOTICE", None)
    ... except Exception as exc:
    ...     print(type(exc).__name__, "px wide, more than the image (60 x 40 px" in str(exc))
    MarkNotFoundError True
    """
    from odnn_sep.image.glyphs import fonts_for
    from odnn_sep.image.locate import smallest_text
    from odnn_sep.image.render import default_fonts, resolve_font

    fonts = fonts_for(text, [resolve_font(font)] if font is not None else default_fonts(), given=font is not None)
    sizes = [smallest_text(text, f, shape) for f in fonts]
    if sizes and all(too_wide for _, _, too_wide in sizes):
        width, height, _ = min(sizes)
        H, W = shape[:2]
        raise MarkNotFoundError(
            f"text {text!r} cannot be found in this image: at the smallest size searched (text {height:.0f} px "
            f"tall) it is {width:.0f} px wide, more than the image ({W} x {H} px, diagonal "
            f"{np.hypot(H, W):.0f} px) can hold; give only the part of the text the image shows, or the "
            "full-size image")


def _turn_hint(angle_range) -> str:
    """The clause of a "not found" error on the angles searched: a vertical mark (text up the side of a
    photo) was "not found" with no word that the search never turns the text that far.

    Examples
    --------
    >>> _turn_hint(45.0)
    '; the search tries angles within +-45 degrees of level: for a mark turned further (vertical text), turn the image by 90 degrees first'
    >>> _turn_hint(0.0)
    ''
    """
    if not angle_range or float(angle_range) >= 90:
        return ""
    return (f"; the search tries angles within +-{float(angle_range):g} degrees of level: for a mark turned further "
            f"(vertical text), turn the image by 90 degrees first")


def _copies(y, ys, text, best, best_nc, off, max_marks, min_score, how) -> list:
    """Registered repeats of the found mark ``best`` (tiled or repeated watermarks).

    Repeats of a faint mark are as faint: they pass the bar the first copy had to pass. ``how``:
    ``reduced`` and ``random_state``.
    Why long (9 parameters): the search's view and offset travel with the mark found there."""
    from odnn_sep.image.detect import detection_score
    from odnn_sep.image.locate import Match, repeats
    from odnn_sep.image.register import refine, render_at

    H, W = y.shape[:2]
    ref = Match(best.font, best.size, best.angle, (best.center[0] - off[0], best.center[1] - off[1]), best_nc.score)
    out = []
    for r in repeats(ys, text, ref, max_marks=max_marks)[1:]:
        rc = (r.center[0] + off[0], r.center[1] + off[1])
        m, box = render_at(text, best.font, best.size, best.angle, rc, (H, W))
        if m.size == 0:
            continue
        try:
            if detection_score(y[box[1]:box[3], box[0]:box[2]], m) < min_score:
                continue
            p = refine(y, text, best.font, best.size, best.angle, rc, iterations=30, whole_sizes=not how["reduced"],
                       random_state=how["random_state"])
        except NotIdentifiableError:
            continue
        if placement_score(y, p, random_state=how["random_state"]) >= min_score:
            out.append(p)
    return out


def find(y, text, fonts, region, angle_range, random_state, min_score, reduced=False, near=None):
    """``best_match``, and more looks when the first finds nothing (a best score below ``min_score``).

    Without a pinned font, first the coarse grid with the templates of the font least like the
    first one: a monospaced text's letters sit where a proportional font's do not, so the first
    font's coarse templates missed monospaced marks that were found at once with the font given.
    Then a finer coarse grid (glyphs ``FINE_LOOK_HEIGHT`` px tall instead of 10): on a textured photo
    a faint mark ranks among hundreds of chance matches on the coarse grid, where its letters are a
    few pixels tall, while on the finer one it often ranks first. Each look costs a search (the
    finer one about three), but only when nothing was found.

    More looks give chance more tries, so a later look's mark must score ``SECOND_LOOK_FACTOR``
    times ``min_score``.

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    fonts : list of Path
        Fonts to try.
    region : np.ndarray or None
        (H, W) bool, where to search.
    angle_range : float
        Largest rotation searched, degrees either way.
    random_state : int or Generator
        Seed of the fits.
    min_score : float
        Detection threshold.
    reduced : bool, default False
        ``y`` is a reduced copy of a large image.
    near : float, optional
        Angle (degrees) of another line of the same mark: the lines of one mark share it, so the
        coarse grid is first searched within ``NEAR_ANGLE`` degrees of it (:func:`near_match`);
        only when nothing is found there, the whole search.

    Returns
    -------
    tuple
        As :func:`best_match`.

    Examples
    --------
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.textmode import find
    >>> import numpy as np
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> y, _ = add_text_watermark(np.full((40, 56, 3), 90, np.uint8), "Hi", size=18, center=(28, 20), alpha=0.5)
    >>> y = y / 255.0
    >>> best, match, score, off, ys = find(y, "Hi", [resolve_font("DejaVuSans-Bold")], None, 0.0, 0, 0.19)
    >>> round(best.size), score > 0.19
    (18, True)
    """
    from odnn_sep.image.layoutlook import layout_look
    from odnn_sep.image.locate import least_alike
    from odnn_sep.image.render import SLANTED_FONT_NAMES, default_fonts, spaced

    if near is not None and not reduced:
        hit = near_match(y, text, fonts, region, random_state, min_score, near)
        if hit is not None:
            return hit
    tried = [[]]  # the registered placements of every look, one list per look
    first = best_match(y, text, fonts, region, angle_range, random_state, reduced, tried=tried[0])
    if first[0] is not None and first[2] >= min_score:
        return first if reduced else _glyphs_checked(y, text, fonts, first, random_state)
    looks = [(fonts, {"coarse_font": least_alike(text, fonts)})] if len(fonts) > 1 else []
    if len(fonts) > 1:
        # letter-spaced marks: the first two fonts spaced out (the others only cost time here)
        wide = [Path(spaced(f, LOOK_TRACKING)) for f in fonts[:2]]
        looks.append((wide, {"coarse_font": wide[0]}))
    looks.append((fonts, {"coarse_height": FINE_LOOK_HEIGHT}))
    slanted = default_fonts(SLANTED_FONT_NAMES) if len(fonts) > 1 else []
    if slanted:
        looks.append((slanted, {}))
    for look_fonts, look in looks:
        tried.append([])
        again = best_match(y, text, look_fonts, region, angle_range, random_state, reduced, tried=tried[-1], **look)
        log.debug("another look for %r (%s): best score %.3f (first look %.3f)", text, look, again[2], first[2])
        if again[0] is not None and again[2] >= SECOND_LOOK_FACTOR * min_score:
            return again
    if len(fonts) > 1:  # a font the tool does not have: its glyphs elsewhere (``glyphfit``)
        best, score = layout_look(y, text, tried, random_state)
        log.debug("glyph-by-glyph look for %r: best score %.3f", text, score)
        if best is not None and score >= LAYOUT_LOOK_FACTOR * min_score:
            return (best, _as_match(best, score, first[3]), score) + first[3:]
    return first


def near_match(y, text, fonts, region, random_state, min_score, angle):
    """``best_match`` with the coarse grid only within ``NEAR_ANGLE`` degrees of ``angle`` (another
    line's of the same mark), or None when nothing there scores ``min_score``.

    Why long (7 parameters): ``find``'s options, passed on. Only the angle is carried over: the size
    and font are not, because a mark in a font the tool does not have is best fitted by different
    fonts and sizes on different lines (the real example: three fonts, 19.6-26.1 px over four lines;
    the sizes narrowed to a factor 1.35 moved its output 0.14 dB the wrong way). With several fonts
    the font is a guess, so the glyph-by-glyph look still runs (as in ``find``).

    Examples
    --------
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.textmode import near_match
    >>> import numpy as np
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> y, _ = add_text_watermark(np.full((48, 72, 3), 90, np.uint8), "Hi", size=18, center=(36, 24), alpha=0.5,
    ...                           angle=20)
    >>> f = [resolve_font("DejaVuSans-Bold")]
    >>> hit = near_match(y / 255.0, "Hi", f, None, 0, 0.19, 19.0)
    >>> round(hit[0].angle), hit[2] > 0.19
    (20, True)
    >>> near_match(y / 255.0, "Hi", f, None, 0, 0.19, -20.0) is None
    True
    """
    got = best_match(y, text, fonts, region, NEAR_ANGLE, random_state, angle_center=float(angle))
    if got[0] is None or got[2] < min_score:
        return None
    return _glyphs_checked(y, text, fonts, got, random_state)


def _glyphs_checked(y, text, fonts, got, random_state):
    """``got`` (a found :func:`best_match`), with its glyphs moved where that explains the mark clearly
    better (``layoutlook.keep_better``) when several fonts were tried: the font is then a guess, and
    its glyphs may sit elsewhere."""
    if len(fonts) <= 1:
        return got
    from odnn_sep.image.layoutlook import keep_better

    best, score = keep_better(y, text, got[0], got[2], random_state)
    return (best, _as_match(best, score, got[3]), score) + got[3:]


def _as_match(p, score, off):
    """The search hypothesis of a registered placement ``p`` (in the searched view's coordinates)."""
    from odnn_sep.image.locate import Match

    return Match(p.font, p.size, p.angle, (p.center[0] - off[0], p.center[1] - off[1]), score)


def best_match(y, text, fonts, region, angle_range, random_state, reduced=False, tried=None, **coarse):
    """(best registered placement or None, its search match, its detection score, offset, searched view).

    ``coarse``: ``coarse_font`` and ``coarse_height`` of the search's coarse grid (``locate.search``).

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    fonts : list of Path
        Fonts to try.
    region : np.ndarray or None
        (H, W) bool, where to search.
    angle_range : float
        Largest rotation searched, degrees either way.
    random_state : int or Generator
        Seed of the fits.
    reduced : bool, default False
        ``y`` is a reduced copy of a large image.
    **coarse
        Options of the coarse grid.

    Returns
    -------
    best : Placed or None
        The best registered placement.
    match : Match or None
        Its search hypothesis.
    score : float
        Its detection score (0 when nothing was registered).
    off : tuple of int
        (x, y) offset of the searched view in ``y``.
    ys : np.ndarray or FloatView
        The searched view (``y``, or its crop around ``region``).

    Examples
    --------
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.textmode import best_match
    >>> import numpy as np
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> y, _ = add_text_watermark(np.full((40, 56, 3), 90, np.uint8), "Hi", size=18, center=(28, 20), alpha=0.5)
    >>> y = y / 255.0
    >>> best, match, score, off, ys = best_match(y, "Hi", [resolve_font("DejaVuSans-Bold")], None, 0.0, 0)
    >>> round(best.size), [round(c) for c in best.center], score > 0.19, off
    (18, [28, 20], True, (0, 0))
    """
    from odnn_sep.image.choose import most_likely
    from odnn_sep.image.locate import search
    from odnn_sep.image.register import refine

    H, W = y.shape[:2]
    off = (0, 0)
    ys = y
    if region is not None:  # search only where the user says the mark is
        rr, cc = np.nonzero(region)
        pad = 16
        off = (max(0, cc.min() - pad), max(0, rr.min() - pad))
        ys = y[off[1]:min(H, rr.max() + pad + 1), off[0]:min(W, cc.max() + pad + 1)]
    cands = search(ys, text, fonts, angle_range=angle_range, max_hypotheses=20, per_size_bin=2, **coarse)
    screened = screen_hypotheses(y, text, cands, off, random_state)
    order, rivals = refine_order(screened)
    best, best_nc = None, None
    refined = []
    for sc0, c in order:
        if best is not None and best.fit.explained >= 0.5 and sc0 < (
                0.8 if all(c is not u[1] for u in rivals) else RIVAL_SCREEN_RATIO) * screened[0][0]:
            # a clear detection: no need to refine clearly weaker hypotheses, nor fonts that
            # explain less than half as much at the same place (their likelihood cannot win)
            continue
        try:
            # a short registration of every hypothesis to choose among them; only the chosen one is
            # registered in full below (on a reduced copy that is done at full resolution instead)
            p = refine(y, text, c.font, c.size, c.angle, (c.center[0] + off[0], c.center[1] + off[1]),
                       iterations=QUICK_ITERATIONS, whole_sizes=False, random_state=random_state)
        except NotIdentifiableError:
            continue
        refined.append((p, c))
        if best is None or p.fit.explained > best.fit.explained:
            best, best_nc = p, c
    score = 0.0
    if best is not None:
        # The place: the registered hypothesis with the best detection score. The in-sample share of
        # variance that ranked them so far is dominated by textured patches, where a chance
        # alignment can beat a faint real mark; the out-of-sample score is what decides detection.
        scores = {id(p): placement_score(y, p, random_state=random_state)
                  for p, _ in refined}
        if tried is not None:  # best held-out score first (``layoutlook`` moves the first few)
            tried.extend(sorted((p for p, _ in refined), key=lambda p: -scores[id(p)]))
        best, best_nc = max(refined, key=lambda t: scores[id(t[0])])
        # the font (and size) at the chosen place: by the likelihood on the same pixels
        rivals = [(p, c) for p, c in refined if _overlap(p.box, best.box) > 0.5]
        best, best_nc = rivals[most_likely(y, [p for p, _ in rivals], random_state=random_state)]
        score = scores[id(best)]
        if not reduced:
            best, score = _polish(y, text, best, score, random_state)
    return best, best_nc, score, off, ys


def _polish(y, text, p, score, random_state):
    """(placement, detection score) of the full registration (``refine``: more iterations and the
    whole font sizes) started at the chosen placement ``p``; ``p`` stands if it fits no better."""
    from odnn_sep.image.register import refine

    try:
        q = refine(y, text, p.font, p.size, p.angle, p.center, iterations=60, whole_sizes=True,
                   random_state=random_state)
    except NotIdentifiableError:
        return p, score
    if q.fit.explained < p.fit.explained:
        return p, score
    return q, placement_score(y, q, random_state=random_state)


def _overlap(a, b) -> float:
    """Intersection over the smaller of two boxes (x0, y0, x1, y1)."""
    w = min(a[2], b[2]) - max(a[0], b[0])
    h = min(a[3], b[3]) - max(a[1], b[1])
    if w <= 0 or h <= 0:
        return 0.0
    return w * h / min((a[2] - a[0]) * (a[3] - a[1]), (b[2] - b[0]) * (b[3] - b[1]))


def _assemble(y, text, placed, score, min_score, random_state, from_data=True):
    """Coverage of all placed copies, one opacity and colour for them, and the report fields.

    ``from_data``: estimate the coverage from the image around the rendering (``coverage``); off when
    the user pinned the font, whose rendering is then the coverage."""
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
    prior = M
    if from_data:
        M, fit = _coverage_from_data(y, M, fit, random_state)
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
    info["_copy_box"] = tuple(int(v) for v in best.box)  # the template of the copies looked for after removal
    return M, fit.alpha, fit.color, info, prior


def _coverage_from_data(y, M, fit, random_state):
    """The coverage estimated from the image around the registered rendering ``M`` (``coverage``), on
    the crop holding the mark(s) with a margin; the rendering's fit stands if the new one fails."""
    from odnn_sep.image.coverage import refine_coverage
    from odnn_sep.image.estimate import stroke_width

    H, W = M.shape
    nz = np.nonzero(M > 0.02)
    pad = int(np.ceil(2 * stroke_width(M))) + 8
    b = (max(0, nz[1].min() - pad), max(0, nz[0].min() - pad), min(W, nz[1].max() + pad + 1),
         min(H, nz[0].max() + pad + 1))
    Mc, f = refine_coverage(y[b[1]:b[3], b[0]:b[2]], M[b[1]:b[3], b[0]:b[2]], fit.alpha, fit.color,
                            random_state=random_state)
    if f is None:
        return M, fit
    out = np.zeros_like(M)
    out[b[1]:b[3], b[0]:b[2]] = Mc
    return out, f


def _text_mode_large(y, text, font, region, min_score, angle_range, max_marks, random_state):
    """Large images: find the mark(s) on a copy reduced to ``WORK_MAX_PX``, then refine each placement
    on the full-resolution crop around it only.

    The correlation search works on a pyramid capped at 768 px anyway, so the reduced copy loses no
    detections; what it saves is the full-resolution patch fits and registrations of every
    hypothesis (a 12-megapixel photo spent most of its time there).
    """
    import cv2

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
    _, _, _, info, _ = text_mode(small, text, font, reg, min_score, angle_range, max_marks, random_state,
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
        sc = placement_score(y, p, random_state=random_state)
        if sc >= min_score:  # the bar the reduced copy's score had to pass
            placed.append(p)
            scores.append(sc)
    if not placed:
        raise MarkNotFoundError(f"text {text!r} not found in the image (best match score {info['match_score']:.3f} on a "
                         f"reduced copy, not confirmed at full resolution, needs >= {min_score:g}); check "
                         f"--text/--font or give --mask{_turn_hint(angle_range)}")
    order = np.argsort(-np.asarray(scores), kind="stable")
    placed = [placed[i] for i in order]
    return _assemble(y, text, placed, float(scores[order[0]]), min_score, random_state, from_data=font is None)
