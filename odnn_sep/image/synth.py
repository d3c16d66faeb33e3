"""Synthetic watermarked images with known truth (procedural photos, no third-party media).

The watermark is made the way common scripts make one: Pillow draws the text at an integer font
size on a coverage layer, ``Image.rotate(..., BICUBIC, expand=True)`` turns it, and the layer is
pasted at an integer offset and alpha-blended. The detector renders through a different path
(OpenCV affine warp at a continuous pose), so the benchmark does not grade the renderer against
itself.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.image.fonts import default_fonts, resolve_font


def procedural_photo(shape=(384, 512), random_state=0) -> np.ndarray:
    """A photo-like RGB float image in [0, 1]: sky gradient, hills, blurred objects, fine texture.

    Examples
    --------
    >>> procedural_photo((32, 48)).shape
    (32, 48, 3)
    """
    import cv2

    rng = np.random.default_rng(random_state)
    H, W = shape
    yy, xx = np.mgrid[0:H, 0:W].astype(np.float64)
    sky_top, sky_bot = rng.uniform(0.3, 0.6, 3), rng.uniform(0.6, 0.95, 3)
    t = yy / H
    img = sky_top * (1 - t[..., None]) + sky_bot * t[..., None]
    # Two rolling hill lines with their own colours and a brightness ramp.
    for _k in range(2):
        base = H * rng.uniform(0.45, 0.75)
        amp = H * rng.uniform(0.03, 0.1)
        line = base + amp * np.sin(2 * np.pi * xx / W * rng.uniform(0.7, 2.5) + rng.uniform(0, 6.3))
        col = rng.uniform(0.05, 0.6, 3)
        shade = 0.7 + 0.3 * (xx / W)
        inside = (yy > line)[..., None]
        img = np.where(inside, col * shade[..., None] * (1 + 0.2 * (yy - line)[..., None] / H), img)
    # Objects: soft discs and rectangles.
    for _ in range(int(rng.integers(4, 9))):
        cx, cy, r = rng.uniform(0, W), rng.uniform(0, H), rng.uniform(0.03, 0.15) * min(H, W)
        col = rng.uniform(0, 1, 3)
        if rng.random() < 0.5:
            m = ((xx - cx) ** 2 + (yy - cy) ** 2 < r * r).astype(np.float64)
        else:
            m = ((abs(xx - cx) < r) & (abs(yy - cy) < 0.6 * r)).astype(np.float64)
        m = cv2.GaussianBlur(m, (0, 0), rng.uniform(0.7, 3.0))[..., None]
        img = img * (1 - m) + col * m
    # Fine texture (sensor grain + foliage-like band-pass noise).
    tex = cv2.GaussianBlur(rng.standard_normal((H, W)), (0, 0), 1.2) * 0.05
    img = img + tex[..., None] + rng.standard_normal((H, W, 3)) * 0.004
    return np.clip(img, 0.0, 1.0)


def render_layer(shape, text, font, size_px, angle, center):
    """Pillow-rendered coverage layer (float in [0, 1]) and the true ink-box centre after pasting."""
    from PIL import Image, ImageDraw, ImageFont

    f = ImageFont.truetype(str(font), int(size_px))
    x0, y0, x1, y1 = f.getbbox(text)
    pad = 4
    layer = Image.new("L", (x1 - x0 + 2 * pad, y1 - y0 + 2 * pad), 0)
    ImageDraw.Draw(layer).text((pad - x0, pad - y0), text, fill=255, font=f)
    a = np.asarray(layer)
    ys, xs = np.nonzero(a)
    u0, v0 = 0.5 * (xs.min() + xs.max() + 1), 0.5 * (ys.min() + ys.max() + 1)
    w0, h0 = layer.size
    rot = layer.rotate(angle, resample=Image.BICUBIC, expand=True)
    w1, h1 = rot.size
    t = np.deg2rad(angle)
    du, dv = u0 - w0 / 2, v0 - h0 / 2
    # Where the ink centre lands inside the rotated canvas (screen-CCW, y down).
    cu = w1 / 2 + np.cos(t) * du + np.sin(t) * dv
    cv = h1 / 2 - np.sin(t) * du + np.cos(t) * dv
    ox, oy = int(round(center[0] - cu)), int(round(center[1] - cv))
    H, W = shape
    full = np.zeros((H, W), np.float64)
    r = np.asarray(rot, np.float64) / 255.0
    ya, yb = max(oy, 0), min(oy + h1, H)
    xa, xb = max(ox, 0), min(ox + w1, W)
    if yb > ya and xb > xa:
        full[ya:yb, xa:xb] = r[ya - oy:yb - oy, xa - ox:xb - ox]
    return full, (ox + cu, oy + cv)


def add_watermark(clean, text, *, font=None, size_px=32, angle=0.0, centers=None, alpha=0.5,
                  color=(1.0, 1.0, 1.0)):
    """Blend a text mark into ``clean`` (float in [0, 1], HxW or HxWxC): y = (1 - αM)·I + αM·c.

    Returns the watermarked float image and the coverage M (HxW). Several ``centers`` tile the mark.
    """
    clean = np.asarray(clean, dtype=np.float64)
    H, W = clean.shape[:2]
    font = resolve_font(font) if font is not None else default_fonts()[0]
    if centers is None:
        centers = [(W / 2, H / 2)]
    M = np.zeros((H, W))
    true_centers = []
    for c in centers:
        m, tc = render_layer((H, W), text, font, size_px, angle, c)
        M = 1 - (1 - M) * (1 - m)
        true_centers.append(tc)
    col = np.asarray(color, dtype=np.float64)
    if clean.ndim == 2:
        col = col.mean() if col.size > 1 else col.item()
        y = (1 - alpha * M) * clean + alpha * M * col
    else:
        y = (1 - alpha * M[..., None]) * clean + (alpha * M)[..., None] * col[: clean.shape[2]]
    return y, M, true_centers


def make_watermark_demo(random_state=0):
    """A procedural photo with a rotated text watermark, and the truth.

    Returns
    -------
    watermarked : (H, W, 3) uint8 RGB
    clean : (H, W, 3) uint8 RGB
    truth : dict with text, font, size_px, angle, alpha, color (0-255), centers, mask (H, W float)

    Examples
    --------
    >>> y, clean, truth = make_watermark_demo()
    >>> y.shape == clean.shape and y.dtype.name == "uint8", truth["text"]
    (True, '© odnn-sep 2025')
    """
    rng = np.random.default_rng(random_state)
    clean = procedural_photo((384, 512), random_state=random_state)
    clean8 = np.round(clean * 255).astype(np.uint8)
    text = "© odnn-sep 2025"
    font = default_fonts()[0]
    size = 44
    angle = float(np.round(rng.uniform(15, 35), 1))
    alpha = 0.45
    color = (1.0, 1.0, 1.0)
    y, M, centers = add_watermark(clean8 / 255.0, text, font=font, size_px=size, angle=angle,
                                  centers=[(256 + rng.uniform(-20, 20), 192 + rng.uniform(-20, 20))],
                                  alpha=alpha, color=color)
    y8 = np.round(np.clip(y, 0, 1) * 255).astype(np.uint8)
    truth = {"text": text, "font": str(font), "size_px": size, "angle": angle, "alpha": alpha,
             "color": [255.0 * c for c in color], "centers": centers, "mask": M}
    return y8, clean8, truth
