"""Text rendering: the watermark's glyph coverage M for a pose (font, size, angle, centre).

Pose convention used everywhere in this package: ``size`` is the font size in output pixels
(the em height), ``angle`` is in degrees counter-clockwise as seen on screen, and ``(cx, cy)`` is
the centre of the text's ink box in image pixel coordinates (x right, y down).
"""
from __future__ import annotations

import functools
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from odnn_sep.errors import InputError


@dataclass(frozen=True)
class Pose:
    """Where one copy of the mark sits in the image."""

    font: str
    size: float
    angle: float
    cx: float
    cy: float

    def replace(self, **kw) -> "Pose":
        d = dict(self.__dict__)
        d.update(kw)
        return Pose(**d)


@functools.lru_cache(maxsize=512)
def reference(text: str, font: str, size_px: int) -> tuple[np.ndarray, float, float]:
    """Render ``text`` horizontally at an integer font size with FreeType (Pillow).

    Returns the coverage (float32 in [0, 1], padded by 2 px) and the ink-box centre (u0, v0).
    """
    from PIL import Image, ImageDraw, ImageFont

    if not text or not text.strip():
        raise InputError(f"text must contain at least one visible character; got {text!r}")
    try:
        f = ImageFont.truetype(str(font), int(size_px))
    except OSError as exc:
        raise InputError(f"font {str(font)!r} could not be loaded ({exc}); pass a .ttf/.otf file") from None
    x0, y0, x1, y1 = f.getbbox(text)
    pad = 2
    w, h = int(x1 - x0) + 2 * pad, int(y1 - y0) + 2 * pad
    img = Image.new("L", (max(w, 1), max(h, 1)), 0)
    ImageDraw.Draw(img).text((pad - x0, pad - y0), text, fill=255, font=f)
    cov = np.asarray(img, dtype=np.float32) / 255.0
    if cov.max() <= 0:
        raise InputError(f"text {text!r} renders to nothing with font {Path(font).name!r}; "
                         "check the characters are in the font")
    ys, xs = np.nonzero(cov > 0)
    u0 = 0.5 * (xs.min() + xs.max() + 1)
    v0 = 0.5 * (ys.min() + ys.max() + 1)
    cov.setflags(write=False)
    return cov, float(u0), float(v0)


def _affine(pose: Pose, n: int, u0: float, v0: float) -> np.ndarray:
    """2x3 matrix mapping template pixel (u, v) to image (x, y) for ``pose``."""
    s = pose.size / n
    t = np.deg2rad(pose.angle)
    c, sn = np.cos(t), np.sin(t)
    # Screen-CCW rotation in y-down coordinates.
    A = s * np.array([[c, sn], [-sn, c]])
    b = np.array([pose.cx, pose.cy]) - A @ np.array([u0, v0])
    return np.c_[A, b]


def render_size(size: float) -> int:
    """Integer size the glyphs are rasterised at before the (near-1) affine rescale."""
    return int(max(4, round(size)))


def mark_box(text: str, pose: Pose, shape: tuple[int, int], margin: int = 2):
    """Bounding box (y0, y1, x0, x1) of the mark clipped to ``shape``; None if it is outside."""
    n = render_size(pose.size)
    cov, u0, v0 = reference(text, pose.font, n)
    A = _affine(pose, n, u0, v0)
    h, w = cov.shape
    corners = np.array([[0, 0, 1], [w, 0, 1], [0, h, 1], [w, h, 1]], float) @ A.T
    x0 = int(np.floor(corners[:, 0].min())) - margin
    x1 = int(np.ceil(corners[:, 0].max())) + margin
    y0 = int(np.floor(corners[:, 1].min())) - margin
    y1 = int(np.ceil(corners[:, 1].max())) + margin
    H, W = shape
    x0, y0, x1, y1 = max(x0, 0), max(y0, 0), min(x1, W), min(y1, H)
    if x1 <= x0 or y1 <= y0:
        return None
    return y0, y1, x0, x1


def render_mark(text: str, pose: Pose, shape: tuple[int, int], box=None) -> np.ndarray:
    """Coverage M of the mark over ``box`` (y0, y1, x0, x1) of an image of ``shape`` (float32).

    Examples
    --------
    >>> from odnn_sep.image.fonts import default_fonts
    >>> p = Pose(str(default_fonts()[0]), 20.0, 30.0, 50.0, 40.0)
    >>> M = render_mark("Hi", p, (80, 100))
    >>> M.shape, 0.0 <= float(M.min()) and float(M.max()) <= 1.0
    ((80, 100), True)
    """
    import cv2

    if box is None:
        box = (0, shape[0], 0, shape[1])
    y0, y1, x0, x1 = box
    n = render_size(pose.size)
    cov, u0, v0 = reference(text, pose.font, n)
    A = _affine(pose, n, u0, v0)
    A[:, 2] -= (x0, y0)
    out = cv2.warpAffine(np.ascontiguousarray(cov), A, (x1 - x0, y1 - y0), flags=cv2.INTER_CUBIC,
                         borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return np.clip(out, 0.0, 1.0)


def combine(masks) -> np.ndarray:
    """Coverage of overlapping copies: two layers of α·M blend like 1 - Π(1 - M) to first order."""
    out = None
    for m in masks:
        out = m.copy() if out is None else 1.0 - (1.0 - out) * (1.0 - m)
    return out
