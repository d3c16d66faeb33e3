"""Synthetic watermark data with known truth: a procedural photo-like image and a blended text mark.

The mark is made the way image editors make one (Pillow draws the text at an integer font size,
rotates it with bicubic resampling, pastes it at a pixel position, alpha-blends it), which is a
different pipeline from the one the estimator renders with, so tests do not reward a shared
implementation detail.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import InputError


def photo_like(shape=(320, 480), *, random_state=0) -> np.ndarray:
    """A procedurally generated, photo-like RGB uint8 image (smooth shading, blurred-edge shapes,
    fine texture and sensor noise); no third-party media.

    Examples
    --------
    >>> photo_like((64, 96), random_state=1).shape
    (64, 96, 3)
    """
    import cv2

    rng = np.random.default_rng(random_state)
    H, W = shape
    yy, xx = np.mgrid[0:H, 0:W] / max(H, W)
    img = np.zeros((H, W, 3))
    base = rng.uniform(0.2, 0.8, 3)
    for c in range(3):  # smooth illumination
        g = rng.normal(0, 0.25, 3)
        img[..., c] = base[c] + g[0] * (xx - 0.5) + g[1] * (yy - 0.5) + g[2] * (xx - 0.5) * (yy - 0.5)
    for _ in range(14):  # objects: ellipses and boxes with soft edges
        col = rng.uniform(0.05, 0.95, 3)
        m = np.zeros((H, W), np.float32)
        cx, cy = rng.uniform(0, W), rng.uniform(0, H)
        if rng.random() < 0.6:
            cv2.ellipse(m, (int(cx), int(cy)), (int(rng.uniform(10, W / 4)), int(rng.uniform(10, H / 4))),
                        float(rng.uniform(0, 180)), 0, 360, 1.0, -1)
        else:
            w2, h2 = rng.uniform(10, W / 4), rng.uniform(10, H / 4)
            cv2.rectangle(m, (int(cx - w2), int(cy - h2)), (int(cx + w2), int(cy + h2)), 1.0, -1)
        m = cv2.GaussianBlur(m, (0, 0), float(rng.uniform(0.7, 3.0)))
        shade = 1 + 0.3 * (rng.normal() * (xx - cx / max(H, W)) + rng.normal() * (yy - cy / max(H, W)))
        img = img * (1 - m[..., None]) + (col * shade[..., None]) * m[..., None]
    tex = cv2.GaussianBlur(rng.normal(0, 1, (H, W)).astype(np.float32), (0, 0), 1.2)
    img += 0.03 * tex[..., None] * rng.uniform(0.5, 1.5, 3)
    img += rng.normal(0, 0.004, img.shape)
    return np.clip(np.round(img * 255), 0, 255).astype(np.uint8)


def text_coverage(text: str, font, size: int, angle: float) -> np.ndarray:
    """Coverage of ``text`` drawn by Pillow at integer ``size`` and rotated by Pillow (bicubic, expand).

    Parameters
    ----------
    text : str
        The text to draw.
    font : str or Path
        Font file or name (see :func:`odnn_sep.image.render.resolve_font`).
    size : int
        Font size in pixels.
    angle : float
        Rotation in degrees, counter-clockwise; the canvas grows to hold the rotated text.

    Returns
    -------
    np.ndarray
        (h, w) float coverage in [0, 1]: the ink box plus a 2-px border.

    Examples
    --------
    >>> from odnn_sep.image.synth import text_coverage
    >>> c = text_coverage("Hi", "DejaVuSans-Bold", 16, 0)
    >>> c.shape, float(c.max())
    ((16, 23), 1.0)
    >>> text_coverage("Hi", "DejaVuSans-Bold", 16, 30).shape
    (26, 29)
    """
    from PIL import Image, ImageDraw, ImageFont

    from odnn_sep.image.render import resolve_font

    f = ImageFont.truetype(str(resolve_font(font)), int(size))
    x0, y0, x1, y1 = f.getbbox(text)
    im = Image.new("L", (x1 - x0 + 4, y1 - y0 + 4), 0)
    ImageDraw.Draw(im).text((2 - x0, 2 - y0), text, fill=255, font=f)
    if angle:
        im = im.rotate(angle, resample=Image.BICUBIC, expand=True)
    return np.asarray(im, dtype=np.float64) / 255.0


def add_text_watermark(clean, text: str, *, font="DejaVuSans-Bold", size: int = 40, angle: float = 0.0,
                       center=None, alpha: float = 0.5, color=(255, 255, 255), tile: tuple[int, int] | None = None,
                       random_state=0):
    """Blend a text watermark into ``clean`` (uint8/uint16, grey or RGB): ``y = (1 - a M) I + a M c``.

    Why long (10 parameters): a test-data generator, every property of the mark a keyword with a default.

    ``center`` (x, y) defaults to a random point that keeps the mark inside; ``tile=(dx, dy)`` repeats
    it on a grid with that spacing. Returns ``(watermarked, M)`` with ``M`` the full-size coverage.

    Parameters
    ----------
    clean : array_like
        (H, W) grey, (H, W, 3) RGB or (H, W, 4) RGBA image, uint8/uint16 (or float in [0, 1]).
    text : str
        The watermark's text.
    font : str or Path, default "DejaVuSans-Bold"
        Font file or name.
    size : int, default 40
        Font size in pixels.
    angle : float, default 0.0
        Rotation in degrees, counter-clockwise.
    center : tuple of float, optional
        (x, y) of the mark's centre; random (mark inside the image) when None.
    alpha : float, default 0.5
        Opacity in (0, 1].
    color : tuple of int, default (255, 255, 255)
        Mark colour, 0-255 (its mean for grey images).
    tile : tuple of int, optional
        (dx, dy) spacing of a repeated mark.
    random_state : int or Generator, default 0
        Seed for the random centre.

    Returns
    -------
    watermarked : np.ndarray
        The blended image, same shape and dtype as ``clean``.
    M : np.ndarray
        (H, W) float coverage of the mark.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.full((32, 48, 3), 100, np.uint8)
    >>> y, M = add_text_watermark(clean, "Hi", size=16, center=(24, 16), alpha=0.5)
    >>> y.shape, y.dtype, int(y.max()), float(M.max())
    ((32, 48, 3), dtype('uint8'), 178, 1.0)
    """
    clean = np.asarray(clean)
    if not 0 < alpha <= 1:
        raise InputError(f"alpha must be in (0, 1]; got {alpha}")
    H, W = clean.shape[:2]
    cov = text_coverage(text, font, size, angle)
    h, w = cov.shape
    rng = np.random.default_rng(random_state)
    M = np.zeros((H, W))
    if center is None:
        center = (rng.uniform(w / 2, max(w / 2 + 1, W - w / 2)), rng.uniform(h / 2, max(h / 2 + 1, H - h / 2)))
    centers = [center]
    if tile:
        dx, dy = tile
        centers = [(center[0] + i * dx, center[1] + j * dy) for i in range(-20, 21) for j in range(-20, 21)]
    for cx, cy in centers:
        x0, y0 = int(round(cx - w / 2)), int(round(cy - h / 2))
        xa, ya, xb, yb = max(0, x0), max(0, y0), min(W, x0 + w), min(H, y0 + h)
        if xb <= xa or yb <= ya:
            continue
        M[ya:yb, xa:xb] = np.maximum(M[ya:yb, xa:xb], cov[ya - y0:yb - y0, xa - x0:xb - x0])
    top = float(np.iinfo(clean.dtype).max) if clean.dtype.kind in "ui" else 1.0
    col = np.asarray(color, dtype=float).ravel() / 255.0
    img = clean.astype(np.float64) / top
    if img.ndim == 2:
        col = np.array([col.mean()])
        y = (1 - alpha * M) * img + alpha * M * col[0]
    else:
        y = (1 - alpha * M[..., None]) * img[..., :3] + alpha * M[..., None] * col[None, None, :3]
        if img.shape[2] == 4:
            y = np.concatenate([y, img[..., 3:]], axis=2)
    out = np.clip(np.round(y * top), 0, top).astype(clean.dtype) if clean.dtype.kind in "ui" else y
    return out, M


def make_watermark_demo(random_state=0, shape=(320, 480)):
    """A watermarked photo-like RGB uint8 image, its clean original and the truth.

    The mark is ``"(c) odnn-sep 2026"`` in DejaVu Sans Bold (shipped with matplotlib), at a random
    size, angle, position, opacity and colour drawn from ``random_state``.

    Returns
    -------
    watermarked, clean : (H, W, 3) uint8 arrays
    truth : dict with text, font, size, angle, center, alpha, color (0-255) and mask (M, float)

    Examples
    --------
    >>> y, clean, truth = make_watermark_demo(random_state=0)
    >>> y.shape == clean.shape and 0.2 <= truth["alpha"] <= 0.8
    True
    """
    from pathlib import Path

    import matplotlib

    rng = np.random.default_rng(random_state)
    clean = photo_like(shape, random_state=rng.integers(1 << 31))
    font = Path(matplotlib.get_data_path()) / "fonts" / "ttf" / "DejaVuSans-Bold.ttf"
    text = "(c) odnn-sep 2026"
    size = int(rng.integers(28, 44))
    angle = float(rng.uniform(-30, 30))
    alpha = float(rng.uniform(0.3, 0.7))
    color = tuple(int(v) for v in (rng.choice([0, 255]) * np.ones(3) if rng.random() < 0.7
                                    else rng.integers(0, 256, 3)))
    cov = text_coverage(text, font, size, angle)
    H, W = shape
    center = (float(rng.uniform(cov.shape[1] / 2 + 2, W - cov.shape[1] / 2 - 2)),
              float(rng.uniform(cov.shape[0] / 2 + 2, H - cov.shape[0] / 2 - 2)))
    y, M = add_text_watermark(clean, text, font=font, size=size, angle=angle, center=center, alpha=alpha,
                              color=color)
    truth = {"text": text, "font": str(font), "size": size, "angle": angle, "center": center, "alpha": alpha,
             "color": color, "mask": M}
    return y, clean, truth


def moved_layout_demo(text: str = "ABCDE"):
    """A mark whose glyphs sit off the font's own layout (as another font's would), and the placement
    registered there with the font's own layout: ``(y, placement)``, ``y`` float (56, 200, 3) in [0, 1].

    Examples
    --------
    >>> from odnn_sep.image.screening import placement_score
    >>> from odnn_sep.image.synth import moved_layout_demo
    >>> y, p = moved_layout_demo()
    >>> bool(placement_score(y, p) < 0.1)   # the font's own layout explains almost nothing
    True
    """
    from odnn_sep.image.layout import with_layout
    from odnn_sep.image.register import refine
    from odnn_sep.image.render import place, render_text

    rng = np.random.default_rng(0)
    y = 0.3 + 0.2 * np.linspace(0, 1, 200)[None, :, None] + 0.01 * rng.standard_normal((56, 200, 3))
    steps = [(0.3 * (k // 2 + k % 2), 0.0) for k in range(len(text))]   # 0, .3, .3, .6, .6, ...
    M, box = place(render_text(text, with_layout("DejaVuSans", steps), 28), (56, 200), (100, 28), 0)
    y[box[1]:box[3], box[0]:box[2]] += 0.4 * M[..., None]
    return y, refine(y, text, "DejaVuSans", 28, 0, (100, 28))
