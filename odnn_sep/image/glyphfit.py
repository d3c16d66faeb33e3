"""Move each glyph of a registered rendering onto the glyph the image shows (a mark in another font).

A placement registered with the tool's font is right about where the text is, its size and angle,
but another font's advance widths and letter spacing put the true glyphs up to an em or two away
from the rendered ones towards the ends of the string. Here the image is resampled upright along
the placement, every glyph is correlated with it over a window of shifts, and the layout is chosen
in two steps: one letter spacing and offset for the whole string (the sum of the glyphs'
correlations), then each glyph within a fifth of an em of that. The em size is tried at a few
factors as well, since fonts differ in x-height at the same em size.

The result is a font name with the glyph shifts in it (``layout.with_layout``), registered and
scored by the caller like any other font: the shifts add freedom, so a moved layout must pass the
same held-out detection score (``screening.placement_score``).
"""
from __future__ import annotations

import dataclasses

import numpy as np

SIZE_FACTORS = (0.84, 0.92, 1.0, 1.09, 1.18)
TRACKINGS_EM = np.arange(-0.2, 0.351, 0.02)   # extra advance per glyph tried for the whole string
OFFSETS_EM = np.arange(-0.5, 0.501, 0.05)     # shift of the whole string tried
LOCAL_EM = 0.2       # each glyph's own shift around the string's layout, either way
VERTICAL_EM = 0.12   # each glyph's vertical shift (baselines differ between fonts), either way


@dataclasses.dataclass
class Layout:
    """A moved layout: the font name with the shifts in it, the em size, the ink-box centre (x, y)
    it moves the placement to, and the mean correlation of its glyphs with the image.

    Examples
    --------
    >>> from odnn_sep.image.glyphfit import Layout
    >>> Layout("DejaVuSans@glyphs=0:0,0.1:0", 24.0, (50.0, 20.0), 0.8).size
    24.0
    """

    font: str
    size: float
    center: tuple[float, float]
    correlation: float


def _upright(y, center, angle, shape, ext, ext_y) -> np.ndarray:
    """The image sampled on the upright grid of a rendering of ``shape`` = (h, w) centred at
    ``center`` and turned by ``angle`` (as ``render.place`` puts it), with ``ext`` px more left and
    right and ``ext_y`` px more above and below."""
    import cv2

    h, w = shape
    th = np.deg2rad(angle)
    c, s = np.cos(th), np.sin(th)
    A = np.array([[c, s], [-s, c]])
    # only the image around the mark is read (y may be a view of a large photo)
    r = int(np.ceil(0.5 * np.hypot(w + 2 * ext, h + 2 * ext_y))) + 2
    H, W = y.shape[:2]
    x0, y0 = max(0, int(center[0]) - r), max(0, int(center[1]) - r)
    x1, y1 = min(W, int(center[0]) + r + 1), min(H, int(center[1]) + r + 1)
    crop = np.asarray(y[y0:y1, x0:x1], dtype=np.float32)
    if crop.ndim == 2:
        crop = crop[:, :, None]
    t = np.array([center[0] - x0, center[1] - y0]) - A @ np.array([(w - 1) / 2.0 + ext, (h - 1) / 2.0 + ext_y])
    out = cv2.warpAffine(crop, np.hstack([A, t[:, None]]), (w + 2 * ext, h + 2 * ext_y),
                         flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP, borderMode=cv2.BORDER_REFLECT)
    return out if out.ndim == 3 else out[:, :, None]


def _fit_one(y, text, font, size, angle, center, direction, f_font):
    """The best moved layout at one em size, or None when fewer than two glyphs can be correlated."""
    import cv2

    from odnn_sep.image.layout import compose, glyphs, with_layout

    pats, canvas = glyphs(text, f_font, size)
    n = len(pats)
    if n < 2:
        return None
    full, (ox, oy) = compose(pats, [(0.0, 0.0)] * n, canvas)
    idx = np.arange(n) - (n - 1) / 2.0
    track = max(abs(TRACKINGS_EM[0]), TRACKINGS_EM[-1]) * size
    # how far each glyph can move: the string's spacing grows towards its ends
    reach = [int(np.ceil(abs(i) * track + (OFFSETS_EM[-1] + LOCAL_EM) * size)) + 2 for i in idx]
    ext = max(reach) + 2
    ry = int(np.ceil(VERTICAL_EM * size))
    strip = _upright(y, center, angle, full.shape, ext, ry + 2)
    g = np.ascontiguousarray(strip @ direction, dtype=np.float32)
    cols, dys, base = [], [], []
    for (gl, gx, gy), rx in zip(pats, reach):
        bx, by = int(round(gx - ox)) + ext, int(round(gy - oy)) + ry + 2
        ya, xa = max(0, by - ry), max(0, bx - rx)
        reg = g[ya:min(g.shape[0], by + gl.shape[0] + ry), xa:min(g.shape[1], bx + gl.shape[1] + rx)]
        if reg.shape[0] < gl.shape[0] or reg.shape[1] < gl.shape[1] or float(gl.std()) == 0.0:
            cols.append(None)
            dys.append(None)
            base.append(0)
            continue
        sc = cv2.matchTemplate(reg, np.ascontiguousarray(gl), cv2.TM_CCOEFF_NORMED)
        sc = np.nan_to_num(sc, nan=0.0)
        k = np.argmax(sc, axis=0)              # best vertical shift at each horizontal shift
        cols.append(sc[k, np.arange(sc.shape[1])])
        dys.append(k + ya - by)
        base.append(bx - xa)
    if sum(c is not None for c in cols) < 2:
        return None
    # the whole string: one extra advance per glyph and one offset, by the sum of correlations
    T, D = np.meshgrid(TRACKINGS_EM * size, OFFSETS_EM * size, indexing="ij")
    total = np.zeros_like(T)
    for i, c in enumerate(cols):
        if c is None:
            continue
        X = np.rint(base[i] + D + idx[i] * T).astype(int)
        ok = (X >= 0) & (X < c.size)
        total += np.where(ok, c[np.clip(X, 0, c.size - 1)], -1.0)
    ti, di = np.unravel_index(int(np.argmax(total)), total.shape)
    shifts, corr = [], []
    for i, c in enumerate(cols):
        s0 = D[ti, di] + idx[i] * T[ti, di]
        if c is None:
            shifts.append((s0, 0.0))
            continue
        lo = max(0, int(np.floor(base[i] + s0 - LOCAL_EM * size)))
        hi = min(c.size, int(np.ceil(base[i] + s0 + LOCAL_EM * size)) + 1)
        if hi <= lo:
            shifts.append((s0, 0.0))
            continue
        X = lo + int(np.argmax(c[lo:hi]))
        shifts.append((float(X - base[i]), float(dys[i][X])))
        corr.append(float(c[X]))
    cut, (nx, ny) = compose(pats, shifts, canvas)
    # the moved ink box's centre against the old one, turned onto the image
    old = np.array([ox + (full.shape[1] - 1) / 2.0, oy + (full.shape[0] - 1) / 2.0])
    new = np.array([nx + (cut.shape[1] - 1) / 2.0, ny + (cut.shape[0] - 1) / 2.0])
    th = np.deg2rad(angle)
    A = np.array([[np.cos(th), np.sin(th)], [-np.sin(th), np.cos(th)]])
    moved = np.asarray(center, float) + A @ (new - old)
    spec = with_layout(font, [(dx / size, dy / size) for dx, dy in shifts])
    return Layout(spec, float(size), (float(moved[0]), float(moved[1])), float(np.mean(corr)))


def fit_layout(y, text: str, font, size: float, angle: float, center, color) -> Layout | None:
    """The moved layout of ``text`` that best matches the image around a placement.

    Parameters
    ----------
    y : np.ndarray or FloatView
        The whole image, float (H, W, C) in [0, 1].
    text : str
        The mark's text.
    font : str or Path
        The placement's font (a tracking or an earlier layout in its name is dropped).
    size, angle : float
        The placement's em size (px) and angle (degrees, counter-clockwise as displayed).
    center : tuple of float
        The placement's ink-box centre (x, y).
    color : array_like
        (C,) the mark colour fitted there: the image is read along the colour's contrast with the photo.

    Returns
    -------
    Layout or None
        The best layout over ``SIZE_FACTORS``, or None when the text has fewer than two inked glyphs.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.glyphfit import fit_layout
    >>> from odnn_sep.image.layout import split_layout
    >>> from odnn_sep.image.render import place, render_text, spaced
    >>> M, _ = place(render_text("ABCDEF", spaced("DejaVuSans", 0.2), 24), (60, 260), (130, 30), 0)
    >>> y = np.full((60, 260, 3), 0.3); y[:M.shape[0], :M.shape[1]] += 0.5 * M[..., None]
    >>> lay = fit_layout(y, "ABCDEF", "DejaVuSans", 24, 0, ((M.shape[1] - 1) / 2, (M.shape[0] - 1) / 2), [0.8] * 3)
    >>> steps = np.diff([dx for dx, _ in split_layout(lay.font)[1]])
    >>> bool(np.all(np.abs(steps - 0.2) < 0.05)), lay.correlation > 0.9
    (True, True)
    """
    from odnn_sep.image.layout import split_layout
    from odnn_sep.image.render import _load, resolve_font, split_tracking

    base = split_tracking(split_layout(font)[0])[0]
    path = str(resolve_font(base))
    # the photo's colour: the mean within an em of the centre (the mark pulls it only part way)
    r = int(np.ceil(size))
    near = np.asarray(y[max(0, int(center[1]) - r):int(center[1]) + r + 1,
                        max(0, int(center[0]) - r):int(center[0]) + r + 1], dtype=np.float64)
    photo = near.reshape(-1, near.shape[-1] if near.ndim == 3 else 1).mean(axis=0)
    d = np.asarray(color, dtype=np.float64).ravel() - photo
    if d.size != photo.size or not np.all(np.isfinite(d)) or np.linalg.norm(d) < 1e-6:
        d = np.ones(photo.size)
    d = d / np.linalg.norm(d)
    best = None
    for f in SIZE_FACTORS:
        s = float(size) * f
        lay = _fit_one(y, text, base, s, angle, center, d, _load(path, round(s, 3)))
        if lay is not None and (best is None or lay.correlation > best.correlation):
            best = lay
    return best


__all__ = ["Layout", "fit_layout", "SIZE_FACTORS"]
