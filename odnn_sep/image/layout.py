"""A text drawn glyph by glyph, each glyph moved off its place in the font's own layout.

A mark set in a font the tool does not have has other advance widths, other letter spacing and
other baselines: the tool's rendering of the whole string then overlaps the true glyphs only near
its centre, and the blend model explains nearly nothing. Moving each glyph of the tool's rendering
onto the glyph the image shows (``glyphfit``) recovers most of that overlap. The moved layout is
written into the font's name, ``<font>@glyphs=<dx>:<dy>,...`` (shifts in em, one per inked glyph),
so that everything that renders through ``render.render_text`` (registration, copies, the full
resolution refit of a large photo) draws the same layout at any size and angle.
"""
from __future__ import annotations

import functools

import numpy as np

LAYOUT_TAG = "@glyphs="
MAX_SHIFT_EM = 4.0    # a glyph further than this from its place is not the same text any more


def with_layout(font, shifts) -> str:
    """The font name ``font`` drawn with each inked glyph moved by ``shifts`` = [(dx, dy), ...] em.

    Parameters
    ----------
    font : str or Path
        Font name or path (a layout already in it is replaced).
    shifts : sequence of (float, float)
        Shift of each inked glyph (spaces have none), in em, x right and y down.

    Returns
    -------
    str

    Examples
    --------
    >>> from odnn_sep.image.layout import split_layout, with_layout
    >>> split_layout(with_layout("DejaVuSans", [(0.1, 0.0), (-0.05, 0.02)]))
    ('DejaVuSans', ((0.1, 0.0), (-0.05, 0.02)))
    """
    base, _ = split_layout(font)
    body = ",".join(f"{float(dx):.4g}:{float(dy):.4g}" for dx, dy in shifts)
    return f"{base}{LAYOUT_TAG}{body}"


def split_layout(font) -> tuple[str, tuple | None]:
    """(font name or path, glyph shifts in em or None) of a font written by ``with_layout``.

    Parameters
    ----------
    font : str or Path

    Returns
    -------
    tuple of (str, tuple of (float, float) or None)

    Examples
    --------
    >>> from odnn_sep.image.layout import split_layout
    >>> split_layout("Arial")
    ('Arial', None)
    """
    s = str(font)
    if LAYOUT_TAG not in s:
        return s, None
    base, _, body = s.rpartition(LAYOUT_TAG)
    try:
        shifts = tuple((float(a), float(b)) for a, b in (item.split(":") for item in body.split(",") if item))
    except ValueError:
        return s, None
    if not all(np.isfinite(v) and abs(v) <= MAX_SHIFT_EM for sh in shifts for v in sh):
        return s, None
    return base, shifts


def glyphs(text: str, f, size: float):
    """The inked glyphs of ``text`` in the loaded font ``f`` at their places in the font's layout.

    Returns ``(patches, canvas)``: per inked glyph its coverage patch and the (x, y) of the patch's
    top-left corner on a canvas of shape ``canvas`` = (h, w) that holds the whole string with a
    margin of one em on every side.

    Examples
    --------
    >>> from odnn_sep.image.layout import glyphs
    >>> from odnn_sep.image.render import _load, resolve_font
    >>> pats, canvas = glyphs("a b", _load(str(resolve_font("DejaVuSans")), 20.0), 20.0)
    >>> len(pats), pats[1][1] > pats[0][1]
    (2, True)
    """
    from PIL import Image, ImageDraw

    margin = int(np.ceil(size)) + 4
    _, y0, _, y1 = f.getbbox(text)
    h = int(y1 - y0) + 2 * margin
    out = []
    x = float(margin)
    for ch in text:
        adv = f.getlength(ch)
        box = f.getbbox(ch)
        if ch.strip() and box[2] > box[0] and box[3] > box[1]:
            ix = int(np.floor(x))
            im = Image.new("L", (int(np.ceil(adv + size)) + 2 * margin, h), 0)
            ImageDraw.Draw(im).text((margin + x - ix, margin - y0), ch, fill=255, font=f)
            a = np.asarray(im, dtype=np.float32) / 255.0
            rr, cc = np.nonzero(a.max(axis=1) > 0)[0], np.nonzero(a.max(axis=0) > 0)[0]
            if rr.size:
                out.append((a[rr[0]:rr[-1] + 1, cc[0]:cc[-1] + 1], float(ix - margin + cc[0]), float(rr[0])))
        x += adv
    return out, (h, int(np.ceil(x)) + margin)


def compose(patches, shifts_px, canvas) -> tuple[np.ndarray, tuple[float, float]]:
    """The glyph patches moved by ``shifts_px`` (px), drawn together and cut to their ink box plus a
    2-px border; also the (x, y) of that cut's top-left corner on the canvas of ``glyphs``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.layout import compose
    >>> pats = [(np.ones((4, 3), np.float32), 10.0, 5.0), (np.ones((4, 3), np.float32), 20.0, 5.0)]
    >>> a, corner = compose(pats, [(0.0, 0.0), (2.0, 0.0)], (20, 40))
    >>> a.shape, corner
    ((8, 19), (8.0, 3.0))
    """
    import cv2

    xs = [gx + dx for (_, gx, _), (dx, _) in zip(patches, shifts_px)]
    ys = [gy + dy for (_, _, gy), (_, dy) in zip(patches, shifts_px)]
    x0 = int(np.floor(min(xs))) - 3
    y0 = int(np.floor(min(ys))) - 3
    x1 = int(np.ceil(max(x + g.shape[1] for x, (g, _, _) in zip(xs, patches)))) + 3
    y1 = int(np.ceil(max(y + g.shape[0] for y, (g, _, _) in zip(ys, patches)))) + 3
    can = np.zeros((y1 - y0, x1 - x0), np.float32)
    for (g, _, _), x, y in zip(patches, xs, ys):
        A = np.float32([[1, 0, x - x0], [0, 1, y - y0]])
        can = np.maximum(can, cv2.warpAffine(g, A, (can.shape[1], can.shape[0]), flags=cv2.INTER_LINEAR))
    rr, cc = np.nonzero(can.max(axis=1) > 0)[0], np.nonzero(can.max(axis=0) > 0)[0]
    if rr.size == 0:
        return np.zeros((5, 5), np.float32), (float(x0), float(y0))
    cut = np.pad(can[rr[0]:rr[-1] + 1, cc[0]:cc[-1] + 1], 2)
    return cut, (float(x0 + cc[0] - 2), float(y0 + rr[0] - 2))


@functools.lru_cache(maxsize=256)
def render_layout(text: str, font: str, size: float, shifts: tuple) -> np.ndarray:
    """Upright coverage of ``text`` with each inked glyph moved by ``shifts`` em (``render_text``'s
    contract: the ink box plus a 2-px border). Shifts beyond the glyph count are ignored, missing
    ones are zero.

    Examples
    --------
    >>> from odnn_sep.image.layout import render_layout
    >>> from odnn_sep.image.render import resolve_font
    >>> f = str(resolve_font("DejaVuSans"))
    >>> wide = render_layout("AB", f, 20.0, ((0.0, 0.0), (0.5, 0.0)))
    >>> wide.shape[1] - render_layout("AB", f, 20.0, ()).shape[1]
    10
    """
    from odnn_sep.image.render import _load

    pats, canvas = glyphs(text, _load(font, float(size)), float(size))
    if not pats:
        return np.zeros((5, 5), np.float32)
    sh = [(dx * size, dy * size) for dx, dy in shifts[:len(pats)]]
    sh += [(0.0, 0.0)] * (len(pats) - len(sh))
    a, _ = compose(pats, sh, canvas)
    a.setflags(write=False)
    return a


__all__ = ["LAYOUT_TAG", "with_layout", "split_layout", "glyphs", "compose", "render_layout"]
