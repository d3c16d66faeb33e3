"""Judging the text search's hypotheses: a quick blend fit screens them, an order says which to
register, and the detection score of a registered placement decides (``textmode`` drives these)."""
from __future__ import annotations

from odnn_sep.errors import NotIdentifiableError


def screen_hypotheses(y, text, cands, off, random_state) -> list[tuple]:
    """(share of edge variance explained, match) of every search hypothesis, by a quick blend fit."""
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
    registered renderings, which the quick screening fit cannot stand in for."""
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
    the evaluation seed), since that coverage is estimated from the very pixels it is scored on."""
    from odnn_sep.image.detect import detection_score

    x0, y0, x1, y1 = p.box
    return detection_score(y[y0:y1, x0:x1], p.coverage, random_state=random_state)


__all__ = ["screen_hypotheses", "refine_order", "placement_score"]
