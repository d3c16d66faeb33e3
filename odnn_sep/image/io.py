"""Image files in and out (OpenCV pixels, Pillow metadata): PNG, JPEG, TIFF, WebP; grey, grey+alpha, RGB,
RGBA; 8- and 16-bit.

Pixels are handled as floats in [0, 1] in RGB order; the alpha channel of an RGBA or grey+alpha image is
carried through untouched, and the output keeps the input's size, channels and bit depth. The EXIF
orientation is applied on read; EXIF (orientation reset to 1), the ICC profile and PNG text chunks are
written back (``io_meta``). Palette images are read as RGB (RGBA with transparency) and written so,
with a warning: the restored colours do not fit a palette. Animated images (several frames) are
refused.
"""
from __future__ import annotations

import dataclasses
import logging
import os
from pathlib import Path

import numpy as np

from odnn_sep.errors import FormatError, InputError

log = logging.getLogger(__name__)

EXTENSIONS = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp", ".bmp")
# How far a float image may stray outside [0, 1] unremarked (rounding of the caller's arithmetic), and
# with a warning (the overshoot of a cubic or Lanczos resampling at sharp edges, a few 8-bit levels)
# before it is refused: further out the scale is wrong (0-255 floats, an overexposed gain).
FLOAT_SLACK = 1e-6
FLOAT_OVERSHOOT = 0.02


class FloatView:
    """Read-only float view of the colour planes: crops are converted to float64 in [0, 1] on demand.

    A 12-megapixel photo as float64 is ~290 MB; converting (and later rounding back) all of it cost
    seconds while only the mark's neighbourhood is ever looked at in full resolution.

    Parameters
    ----------
    raw : np.ndarray
        (H, W, C) colour channels of the input, in the input's dtype.
    scale : float
        Factor that maps ``raw`` to [0, 1] (``1 / 255`` for uint8, 1 for float images).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.io import FloatView
    >>> v = FloatView(np.full((32, 48, 3), 51, np.uint8), 1 / 255)
    >>> v.shape, round(float(v[0, 0, 0]), 3)
    ((32, 48, 3), 0.2)
    >>> v.full().dtype, v.reduced(12, 8).shape
    (dtype('float64'), (8, 12, 3))
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
    what is needed to put it back together in the original format.

    Attributes
    ----------
    image : np.ndarray
        The input array, unchanged.
    view : FloatView
        Float view of the colour planes (one plane for grey images).
    alpha : np.ndarray or None
        The alpha channel (H, W), passed through untouched, or None.
    dtype : np.dtype
        The input's dtype.
    levels : int
        Quantisation levels of the output (255 for uint8, 65535 for uint16 and float).
    grey : bool
        True for grey and grey+alpha images.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.io import split
    >>> p = split(np.zeros((32, 48, 4), np.uint8))
    >>> p.grey, p.levels, p.view.shape, p.alpha.shape
    (False, 255, (32, 48, 3), (32, 48))
    """

    image: np.ndarray
    view: FloatView
    alpha: np.ndarray | None
    dtype: np.dtype
    levels: int
    grey: bool


def split(image) -> Planes:
    """Validate an image array and split it into a float view of its colour planes and a pass-through
    alpha (no full-image copy).

    Parameters
    ----------
    image : array_like
        (H, W) grey, (H, W, 2) grey+alpha, (H, W, 3) RGB or (H, W, 4) RGBA; uint8, uint16 or float
        in [0, 1].

    Returns
    -------
    Planes
        The float view, the alpha channel and what :func:`paste` needs to rebuild the format.

    Raises
    ------
    InputError
        For an empty image, an unsupported shape or dtype, or float values that are not finite or
        lie outside [0, 1].

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.io import split
    >>> p = split(np.full((32, 48), 1000, np.uint16))
    >>> p.grey, p.levels, p.alpha is None, round(float(p.view[0, 0, 0]), 4)
    (True, 65535, True, 0.0153)
    >>> split(np.full((32, 48, 3), 255.0))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: a float image must hold values in [0, 1]; got 255 to 255; for 0-255 values use 8-bit pixels (uint8) or divide by 255
    """
    a = np.asarray(image)
    if a.size == 0 or a.ndim < 2 or 0 in a.shape[:2]:
        raise InputError(f"image is empty (shape {a.shape}); pass an image with at least one pixel")
    if a.ndim == 3 and a.shape[2] == 1:
        a = a[:, :, 0]
    if a.ndim not in (2, 3) or (a.ndim == 3 and a.shape[2] not in (2, 3, 4)):
        raise InputError(f"image must be (H, W) grey, (H, W, 2) grey+alpha, (H, W, 3) RGB or (H, W, 4) RGBA; "
                         f"got shape {a.shape}")
    if a.dtype == np.uint8:
        levels = 255
    elif a.dtype == np.uint16:
        levels = 65535
    elif a.dtype.kind == "f":
        levels = 65535
        from odnn_sep.errors import check_finite

        check_finite("image", a)
        lo, hi = float(a.min()), float(a.max())
        if -FLOAT_OVERSHOOT <= lo < -FLOAT_SLACK or 1 + FLOAT_SLACK < hi <= 1 + FLOAT_OVERSHOOT:
            if -FLOAT_OVERSHOOT <= lo and hi <= 1 + FLOAT_OVERSHOOT:
                log.warning("the float image strays outside [0, 1] (%.4g to %.4g: resampling overshoot?); it is "
                            "read as it is and the output is clipped to [0, 1]", lo, hi)
                lo, hi = 0.0, 1.0
        if lo < -FLOAT_SLACK or hi > 1 + FLOAT_SLACK:
            # clipped silently, 0-255 floats read as white: the mark was "not found" or its opacity wrong
            hint = "; for 0-255 values use 8-bit pixels (uint8) or divide by 255" if hi > 2 else ""
            raise InputError(f"a float image must hold values in [0, 1]; got {lo:.6g} to {hi:.6g}{hint}")
    else:
        raise InputError(f"image dtype must be uint8, uint16 or float in [0, 1]; got {a.dtype}")
    grey = a.ndim == 2 or a.shape[2] == 2
    raw = a[:, :, None] if a.ndim == 2 else a[:, :, :1] if grey else a[:, :, :3]
    alpha = a[:, :, -1] if (a.ndim == 3 and a.shape[2] in (2, 4)) else None
    view = FloatView(raw, 1.0 / levels if a.dtype.kind == "u" else 1.0)
    return Planes(a, view, alpha, a.dtype, levels, grey)


def _to_dtype(planes: Planes, c: np.ndarray) -> np.ndarray:
    c = np.clip(c, 0.0, 1.0)
    if planes.dtype.kind == "u":
        return np.round(c * planes.levels).astype(planes.dtype)
    return c.astype(planes.dtype)


def paste(planes: Planes, crop: np.ndarray | None = None, box=None) -> np.ndarray:
    """A copy of the input (its format, alpha untouched) with the restored colour ``crop`` (float,
    (h, w, C)) written into ``box`` = (x0, y0, x1, y1); the rest stays bit-identical.

    Parameters
    ----------
    planes : Planes
        The split input (:func:`split`).
    crop : np.ndarray, optional
        Float colour values in [0, 1], (h, w, C); None returns a plain copy of the input.
    box : tuple of int, optional
        (x0, y0, x1, y1) where ``crop`` goes; required with ``crop``.

    Returns
    -------
    np.ndarray
        An array of the input's shape and dtype.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.io import paste, split
    >>> p = split(np.zeros((32, 48, 3), np.uint8))
    >>> out = paste(p, np.ones((2, 3, 3)), (10, 5, 13, 7))
    >>> out.dtype, int(out.sum()), int(out[5, 10, 0])
    (dtype('uint8'), 4590, 255)
    """
    out = np.array(planes.image, copy=True)
    if crop is None:
        return out
    x0, y0, x1, y1 = box
    c = _to_dtype(planes, crop)
    if planes.grey and out.ndim == 2:
        out[y0:y1, x0:x1] = c[:, :, 0]
    elif planes.grey:
        out[y0:y1, x0:x1, 0] = c[:, :, 0]
    else:
        out[y0:y1, x0:x1, :3] = c
    return out


def read_image(path: str | os.PathLike, *, what: str = "input image") -> np.ndarray:
    """Read an image file as an upright RGB/RGBA/grey/grey+alpha array of its own dtype (uint8 or uint16).

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF, WebP or BMP file.
    what : str, optional
        What the file is, for the messages (``--mask image``, ``--reference image``).

    Returns
    -------
    np.ndarray
        (H, W), (H, W, 2), (H, W, 3) or (H, W, 4) pixels, RGB order, EXIF orientation applied.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from odnn_sep.image.io import read_image, write_image
    >>> a = np.zeros((32, 48, 3), np.uint8); a[..., 0] = 200
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_image(os.path.join(d, "x.png"), a)
    ...     b = read_image(os.path.join(d, "x.png"))
    >>> b.shape, b.dtype, bool(np.array_equal(a, b))
    ((32, 48, 3), dtype('uint8'), True)
    """
    return read_image_meta(path, what=what)[0]


def read_image_meta(path, *, what: str = "input image"):
    """(pixels, :class:`io_meta.ImageMeta`) of an image file; the EXIF orientation is applied.

    Parameters
    ----------
    path : str or Path
        A PNG, JPEG, TIFF, WebP or BMP file (one frame).

    Returns
    -------
    img : np.ndarray
        Upright pixels as :func:`read_image` returns them.
    meta : ImageMeta
        EXIF, ICC profile, PNG text, applied orientation and Pillow mode of the file.

    Raises
    ------
    FormatError
        For an animated, empty or unreadable file.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from odnn_sep.image.io import read_image_meta, write_image
    >>> with tempfile.TemporaryDirectory() as d:
    ...     write_image(os.path.join(d, "x.png"), np.zeros((32, 48), np.uint8))
    ...     img, meta = read_image_meta(os.path.join(d, "x.png"))
    >>> img.shape, meta.mode, meta.orientation
    ((32, 48), 'L', 1)
    """
    import cv2

    from odnn_sep.image.io_meta import apply_orientation, read_meta
    from odnn_sep.io_paths import check_input_path
    from odnn_sep.io_utils import ensure_readable

    p = check_input_path(path, what=what)
    meta = read_meta(p)
    if meta.frames > 1:
        raise FormatError(f"{what} {str(p)!r} is animated ({meta.frames} frames); extract the one frame "
                          f"to process (e.g. as PNG) and pass that")

    def _read(q):
        data = np.fromfile(str(q), dtype=np.uint8)
        if meta.orientation != 1:
            # OpenCV turns a TIFF upright itself; the stored pixels are turned below, as for every format
            from odnn_sep.image.io_tiff import orientation_cleared

            cleared = orientation_cleared(data.tobytes())
            data = data if cleared is None else np.frombuffer(cleared, np.uint8)
        img = cv2.imdecode(data, cv2.IMREAD_UNCHANGED)
        if img is None:
            raise FormatError("not a readable PNG/JPEG/TIFF/WebP/BMP image")
        return img

    img = ensure_readable(p, _read, what=what)
    if img.size == 0:
        raise FormatError(f"{what} {str(p)!r} is empty (no pixels)")
    if img.ndim == 3 and img.shape[2] == 3:
        img = cv2.cvtColor(img, cv2.COLOR_BGR2RGB)
    elif img.ndim == 3 and img.shape[2] == 4:
        img = cv2.cvtColor(img, cv2.COLOR_BGRA2RGBA)
        if meta.mode in ("LA", "La") and np.array_equal(img[:, :, 0], img[:, :, 1]) \
                and np.array_equal(img[:, :, 0], img[:, :, 2]):
            img = np.ascontiguousarray(img[:, :, [0, 3]])  # grey+alpha stays grey+alpha
    if meta.mode in ("P", "PA") and what == "input image":
        # (a mask or a reference logo is only read: its palette needs no word)
        log.warning("%s is a palette image: read as %s and written so (restored colours do not fit a palette)",
                    p.name, "RGBA" if img.ndim == 3 and img.shape[2] == 4 else "RGB")
    if meta.orientation != 1:
        img = apply_orientation(img, meta.orientation)
    return img, meta


def _encode_grey_alpha(a: np.ndarray, suffix: str):
    """Encoded bytes of a (H, W, 2) grey+alpha array: 8-bit PNG through Pillow; otherwise the array
    expanded to RGBA (the OpenCV encoders have no two-channel mode), with a warning."""
    if a.dtype == np.uint8 and suffix == ".png":
        import io as _io

        from PIL import Image

        b = _io.BytesIO()
        Image.fromarray(np.ascontiguousarray(a), "LA").save(b, format="PNG")
        return b.getvalue(), None
    log.warning("grey+alpha written as RGBA: the %s %d-bit encoder has no grey+alpha mode", suffix,
                a.dtype.itemsize * 8)
    return None, np.ascontiguousarray(a[:, :, [0, 0, 0, 1]])


def write_image(path: str | os.PathLike, image: np.ndarray, *inputs, jpeg_quality: int = 95,
                meta: dict | None = None) -> None:
    """Write an RGB/RGBA/grey/grey+alpha array atomically; the format follows the extension; never an
    input. ``meta`` (from :func:`read_image_meta`): EXIF, ICC and PNG text written back where the format
    holds them.

    Parameters
    ----------
    path : str or Path
        Output file; its extension (one of ``EXTENSIONS``) picks the format.
    image : np.ndarray
        (H, W), (H, W, 2), (H, W, 3) or (H, W, 4), uint8 or uint16 (16-bit is reduced to 8 bits for
        JPEG, WebP and BMP).
    *inputs : str or Path
        Input files the output must not overwrite.
    jpeg_quality : int, default 95
        JPEG quality (WebP is written lossless).
    meta : ImageMeta, optional
        Metadata to write back.

    Raises
    ------
    InputError
        For an unknown extension or an output that is one of ``inputs``.

    Examples
    --------
    >>> import os, tempfile
    >>> import numpy as np
    >>> from odnn_sep.image.io import write_image
    >>> from odnn_sep.image.io_meta import ImageMeta, read_meta
    >>> with tempfile.TemporaryDirectory() as d:
    ...     f = os.path.join(d, "x.png")
    ...     write_image(f, np.zeros((32, 48, 3), np.uint8), meta=ImageMeta(text={"Author": "me"}))
    ...     read_meta(f).text
    {'Author': 'me'}
    """
    import cv2

    from odnn_sep.image.io_meta import add_metadata, for_pixels
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output

    out = Path(path)
    suffix = out.suffix.lower()
    if suffix not in EXTENSIONS:
        raise InputError(f"output {str(out)!r} must end in one of {', '.join(EXTENSIONS)}")
    check_output_path(out, *inputs)
    a = np.asarray(image)
    encoded = None
    if a.ndim == 3 and a.shape[2] == 2:
        encoded, a = _encode_grey_alpha(a, suffix)
    grey_out = a is None or a.ndim == 2   # one grey channel written (with its alpha through Pillow)
    if encoded is None:
        if a.ndim == 3 and a.shape[2] == 4 and suffix in (".jpg", ".jpeg"):
            log.warning("JPEG holds no alpha channel: the alpha channel is dropped from %s", out.name)
            a = a[:, :, :3]
        if a.ndim == 3 and a.shape[2] == 3:
            a = cv2.cvtColor(a, cv2.COLOR_RGB2BGR)
        elif a.ndim == 3 and a.shape[2] == 4:
            a = cv2.cvtColor(a, cv2.COLOR_RGBA2BGRA)
        if a.dtype == np.uint16 and suffix in (".jpg", ".jpeg", ".webp", ".bmp"):
            log.warning("%s holds 8 bits per channel: the 16-bit image is written at 8 bits to %s; use .png or "
                        ".tiff to keep 16 bits", {".jpg": "JPEG", ".jpeg": "JPEG"}.get(suffix, suffix[1:].upper()),
                        out.name)
            a = np.round(a / 257.0).astype(np.uint8)  # these formats hold 8 bits only
        params = [cv2.IMWRITE_JPEG_QUALITY, int(jpeg_quality)] if suffix in (".jpg", ".jpeg") else []
        if suffix == ".webp":
            params = [cv2.IMWRITE_WEBP_QUALITY, 101]  # lossless
        ok, buf = cv2.imencode(suffix, a, params)
        if not ok:
            raise FormatError(f"could not encode the output image as {out.suffix}")
        encoded = buf.tobytes()
    # a profile of another colour space than the pixels written (a CMYK photo's, on its RGB pixels) is left out
    encoded = add_metadata(encoded, suffix, for_pixels(meta, grey_out))
    with atomic_output(out) as tmp:
        Path(tmp).write_bytes(encoded)
