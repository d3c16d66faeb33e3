"""Image files in and out (OpenCV): PNG, JPEG, TIFF, WebP; grey, RGB, RGBA; 8- and 16-bit.

Pixels are handled as floats in [0, 1] in RGB order; the alpha channel of an RGBA image is carried
through untouched, and the output keeps the input's size, channels and bit depth.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError

EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".bmp")


class FloatView:
    """Read-only float view of the colour planes: crops are converted to float64 in [0, 1] on demand.

    A 12-megapixel photo as float64 is ~290 MB; converting (and later rounding back) all of it cost
    seconds while only the mark's neighbourhood is ever looked at in full resolution.
    """

    def __init__(self, raw: np.ndarray, scale: float):
        self.raw = raw                  # (H, W, C) view of the input's colour channels, input dtype
        self.scale = scale
        self.shape = raw.shape
        self.ndim = 3

    def __getitem__(self, key) -> np.ndarray:
        c = np.asarray(self.raw[key], dtype=np.float64)
        if self.scale != 1.0:
            c *= self.scale
        return np.clip(c, 0.0, 1.0, out=c)

    def full(self) -> np.ndarray:
        return self[:, :]

    def reduced(self, w: int, h: int) -> np.ndarray:
        """The whole image resampled (area average) to w x h, float64 (H, W, C)."""
        import cv2

        a = self.raw
        if a.dtype.kind == "f":
            a = np.asarray(a, dtype=np.float32)
        r = cv2.resize(np.ascontiguousarray(a), (w, h), interpolation=cv2.INTER_AREA)
        if r.ndim == 2:
            r = r[:, :, None]
        return np.clip(r.astype(np.float64) * self.scale, 0.0, 1.0)


@dataclasses.dataclass
class Planes:
    """An image split for processing: a float view of the colour planes (H, W, C) in [0, 1], plus
    what is needed to put it back together in the original format."""

    image: np.ndarray
    view: FloatView
    alpha: np.ndarray | None
    dtype: np.dtype
    levels: int
    grey: bool


def split(image) -> Planes:
    """Validate an image array and split it into a float view of its colour planes and a pass-through
    alpha (no full-image copy)."""
    a = np.asarray(image)
    if a.size == 0 or a.ndim < 2 or 0 in a.shape[:2]:
        raise InputError(f"image is empty (shape {a.shape}); pass an image with at least one pixel")
    if a.ndim == 3 and a.shape[2] == 1:
        a = a[:, :, 0]
    if a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] not in (3, 4)):
        raise InputError(f"image must be (H, W) grey, (H, W, 3) RGB or (H, W, 4) RGBA; got shape {a.shape}")
    if a.dtype == np.uint8:
        levels = 255
    elif a.dtype == np.uint16:
        levels = 65535
    elif a.dtype.kind == "f":
        levels = 65535
        from odnn_sep.errors import check_finite

        check_finite("image", a)
    else:
        raise InputError(f"image dtype must be uint8, uint16 or float in [0, 1]; got {a.dtype}")
    grey = a.ndim == 2
    raw = a[:, :, None] if grey else a[:, :, :3]
    alpha = a[:, :, 3] if (a.ndim == 3 and a.shape[2] == 4) else None
    view = FloatView(raw, 1.0 / levels if a.dtype.kind == "u" else 1.0)
    return Planes(a, view, alpha, a.dtype, levels, grey)


def _to_dtype(planes: Planes, c: np.ndarray) -> np.ndarray:
    c = np.clip(c, 0.0, 1.0)
    if planes.dtype.kind == "u":
        return np.round(c * planes.levels).astype(planes.dtype)
    return c.astype(planes.dtype)


def paste(planes: Planes, crop: np.ndarray | None = None, box=None) -> np.ndarray:
    """A copy of the input (its format, alpha untouched) with the restored colour ``crop`` (float,
    (h, w, C)) written into ``box`` = (x0, y0, x1, y1); the rest stays bit-identical."""
    out = np.array(planes.image, copy=True)
    if crop is None:
        return out
    x0, y0, x1, y1 = box
    c = _to_dtype(planes, crop)
    if planes.grey:
        out[y0:y1, x0:x1] = c[:, :, 0]
    else:
        out[y0:y1, x0:x1, :3] = c
    return out


def read_image(path) -> np.ndarray:
    """Read an image file as an RGB/RGBA/grey array of its own dtype (uint8 or uint16)."""
    import cv2

    from odnn_sep.io_utils import check_input_path

    p = check_input_path(path, what="input image")

    def _read(q):
        data = np.fromfile(str(q), dtype=np.uint8)
        img = cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
        if img is None:
            raise ValueError("not a readable PNG/JPEG/TIFF/WebP/BMP image")
        return img

    from odnn_sep.io_utils import ensure_readable

    img = ensure_readable(p, _read, what="input image")
    if img.size == 0:
        raise FormatError(f"input image {str(p)!r} is empty (no pixels)")
    if img.ndim == 3 and img.shape[2] == 3:
        img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
    elif img.ndim == 3 and img.shape[2] == 4:
        img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA)
    return img


def write_image(path, image: np.ndarray, *inputs, jpeg_quality: int = 95) -> None:
    """Write an RGB/RGBA/grey array atomically; the format follows the extension; never an input."""
    import cv2

    from odnn_sep.io_utils import atomic_output, check_output_path

    out = Path(path)
    if out.suffix.lower() not in EXTENSIONS:
        raise InputError(f"output {str(out)!r} must end in one of {', '.join(EXTENSIONS)}")
    check_output_path(out, *inputs)
    a = np.asarray(image)
    if a.ndim == 3 and a.shape[2] == 3:
        a = cv2.cvtColor(a, cv2.COLOR_RGB2BGR)
    elif a.ndim == 3 and a.shape[2] == 4:
        a = cv2.cvtColor(a, cv2.COLOR_RGBA2BGRA)
    if a.dtype == np.uint16 and out.suffix.lower() in (".jpg", ".jpeg", ".webp", ".bmp"):
        a = np.round(a / 257.0).astype(np.uint8)  # these formats hold 8 bits only
    params = [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)] if out.suffix.lower() in (".jpg", ".jpeg") else []
    if out.suffix.lower() == ".webp":
        params = [cv2.IMWRITE_WEBP_QUALITY, 101]  # lossless
    with atomic_output(out) as tmp:
        ok, buf = cv2.imencode(out.suffix.lower(), a, params)
        if not ok:
            raise FormatError(f"could not encode the output image as {out.suffix}")
        buf.tofile(str(tmp))
