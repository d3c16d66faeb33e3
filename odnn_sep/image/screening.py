"""Judging the text search's hypotheses: a quick blend fit screens them, an order says which to
register, and the detection score of a registered placement decides (``textmode`` drives these)."""
from __future__ import annotations

from odnn_sep.errors import NotIdentifiableError


def screen_hypotheses(y, text, cands, off, random_state) -> list[tuple]:
    """(share of edge variance explained, match) of every search hypothesis, by a quick blend fit.

    Parameters
    ----------
    y : np.ndarray or FloatView
        The image, float (H, W, C) in [0, 1].
    text : str
        The mark's text.
    cands : list of Match
        Search hypotheses.
    off : tuple of float
        (dx, dy) added to every hypothesis' centre.
    random_state : int or Generator
        Seed of the fits' patch subsets.

    Returns
    -------
    list of tuple
        (explained, match) for the hypotheses that could be fitted.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.locate import Match
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.screening import screen_hypotheses
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.repeat(np.linspace(70, 110, 48)[:, None, None], 64, 1).repeat(3, 2).astype(np.uint8)
    >>> y = add_text_watermark(clean, "Hi", size=20, center=(32, 24), alpha=0.5)[0] / 255.0
    >>> F = resolve_font("DejaVuSans-Bold")
    >>> cands = [Match(F, 20.0, 0.0, (32.0, 24.0), 0.9), Match(F, 20.0, 0.0, (12.0, 10.0), 0.5)]
    >>> [round(v, 2) for v, _ in screen_hypotheses(y, "Hi", cands, (0, 0), 0)]
    [0.43, 0.01]
    """
    from odnn_sep.image.estimate import fit_blend
    from odnn_sep.image.register import render_at

    H, W = y.shape[:2]
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
    return screened


def refine_order(screened) -> tuple[list, list]:
    """(hypotheses to register in turn, the other fonts' rivals among them); sorts ``screened``.

    Screening ranks better than correlation alone (which ranks small spurious templates too high):
    the three that screen best, and the two that correlate best (the screening fit needs the
    placement to about a pixel, which the correlation grid does not always give: a faint mark then
    screens below a chance alignment while still leading the correlation); and the best of every
    other font at the place that screens best: the font is chosen by the likelihood of the
    registered renderings, which the quick screening fit cannot stand in for.

    Parameters
    ----------
    screened : list of tuple
        (explained, match) pairs from :func:`screen_hypotheses`; sorted in place, best first.

    Returns
    -------
    order : list of tuple
        The hypotheses to register, in turn.
    rivals : list of tuple
        The best hypothesis of every other font at the best place.

    Examples
    --------
    >>> from odnn_sep.image.locate import Match
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.screening import refine_order
    >>> a = Match(resolve_font("DejaVuSans-Bold"), 20.0, 0.0, (32.0, 24.0), 0.5)
    >>> b = Match(resolve_font("DejaVuSans"), 20.0, 0.0, (33.0, 24.0), 0.9)
    >>> order, rivals = refine_order([(0.2, b), (0.6, a)])
    >>> [t[0] for t in order], rivals[0][1] is b
    ([0.6, 0.2], True)
    """
    from odnn_sep.image.locate import same_place

    by_corr = sorted(screened, key=lambda t: -t[1].score)[:2]
    screened.sort(key=lambda t: -t[0])
    order = screened[:3] + [t for t in by_corr if all(t[1] is not u[1] for u in screened[:3])]
    rivals: list = []
    for t in screened[1:]:
        if screened and t[1].font != screened[0][1].font and same_place(t[1], screened[0][1]) and all(
                t[1].font != u[1].font for u in rivals):
            rivals.append(t)
    order += [t for t in rivals if all(t[1] is not u[1] for u in order)]
    return order, rivals


def placement_score(y, p, *, random_state=0) -> float:
    """Detection score (``detect.detection_score``) of a registered placement ``p`` on its crop.

    A score of the coverage the image itself shows around the rendering was tried for marks in
    fonts the tool does not have (a rendering in another font leaves the true glyph edges
    unexplained and scores near zero even on a plain mark): it found such marks, but it also turned
    2 of 16 clean-photo searches into false alarms (scores 0.64 and 0.67, a development seed and
    the evaluation seed), since that coverage is estimated from the very pixels it is scored on.

    Parameters
    ----------
    y : np.ndarray or FloatView
        The image, float (H, W, C) in [0, 1].
    p : Placed
        A registered placement (:func:`odnn_sep.image.register.refine`).
    random_state : int or Generator, default 0
        Seed of the statistic's patch subsets.

    Returns
    -------
    float
        The detection score, in [0, ``detect.CLIP``].

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.detect import THRESHOLD
    >>> from odnn_sep.image.register import refine
    >>> from odnn_sep.image.screening import placement_score
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.repeat(np.linspace(70, 110, 48)[:, None, None], 64, 1).repeat(3, 2).astype(np.uint8)
    >>> y = add_text_watermark(clean, "Hi", size=20, center=(32, 24), alpha=0.5)[0] / 255.0
    >>> p = refine(y, "Hi", "DejaVuSans-Bold", 19.5, 0.0, (31.5, 24.5))
    >>> placement_score(y, p) > THRESHOLD
    True
    """
    from odnn_sep.image.detect import detection_score

    x0, y0, x1, y1 = p.box
    return detection_score(y[y0:y1, x0:x1], p.coverage, random_state=random_state)


__all__ = ["screen_hypotheses", "refine_order", "placement_score"]
