"""What a photo file carries besides its pixels: EXIF (orientation), ICC profile, PNG text chunks,
the resolution (dots per inch) and a PNG's own colour chunks (gamma, chromaticities, sRGB intent).

OpenCV decodes and encodes the pixels (fast, 16-bit) but ignores the EXIF orientation and drops
the metadata. Pillow reads the metadata without decoding the pixels; on write the metadata are
put back into OpenCV's encoded bytes (PNG chunks after IHDR, JPEG APP segments after SOI), so the
pixel path stays the same for 8- and 16-bit images. EXIF is kept with its orientation reset to 1,
because the pixels are written upright. An ICC profile is written only onto pixels of the colour
space it describes: a CMYK photo is read as RGB, and its CMYK profile on RGB pixels would tell a
viewer to read them as ink amounts.
"""
from __future__ import annotations

import dataclasses
import logging
import struct
import zlib

import numpy as np

from odnn_sep.errors import FormatError

log = logging.getLogger(__name__)

ORIENTATION_TAG = 0x0112
ICC_CHUNK = 65519  # ICC bytes per JPEG APP2 segment (64 KiB less the headers)


@dataclasses.dataclass
class ImageMeta:
    """Metadata of a read image. ``exif``: TIFF-structure EXIF bytes with orientation reset to 1 (no
    ``Exif\\0\\0`` header); ``icc``: ICC profile bytes; ``text``: PNG text chunks; ``orientation``:
    the EXIF orientation that was applied on read (1 = none); ``mode``: Pillow's mode of the file;
    ``frames``: number of frames (more than 1 for an animation); ``dpi``: (x, y) resolution in dots
    per inch, or None; ``png_colour``: a PNG's gAMA, cHRM and sRGB chunks (type, data), written back
    to PNG only.

    Examples
    --------
    >>> from odnn_sep.image.io_meta import ImageMeta
    >>> m = ImageMeta(text={"Title": "x"})
    >>> m.orientation, m.frames, m.exif is None
    (1, 1, True)
    """

    exif: bytes | None = None
    icc: bytes | None = None
    text: dict = dataclasses.field(default_factory=dict)
    orientation: int = 1
    mode: str = ""
    frames: int = 1
    dpi: tuple | None = None
    png_colour: list = dataclasses.field(default_factory=list)


def read_meta(path) -> ImageMeta:
    """The metadata of an image file (Pillow, pixels not decoded); an empty ``ImageMeta`` when
    Pillow cannot open the file (OpenCV may still read its pixels).

    Parameters
    ----------
    path : str or Path
        An image file.

    Returns
    -------
    ImageMeta
        EXIF (orientation reset to 1), ICC profile, PNG text, orientation, mode and frame count.

    Examples
    --------
    >>> import os, tempfile
    >>> from PIL import Image
    >>> from odnn_sep.image.io_meta import read_meta
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.new("RGB", (48, 32)).save(os.path.join(d, "x.png"))
    ...     m = read_meta(os.path.join(d, "x.png"))
    ...     empty = read_meta(os.path.join(d, "missing.png"))
    >>> m.mode, m.orientation, m.frames, empty.mode
    ('RGB', 1, 1, '')
    """
    try:
        from PIL import Image, UnidentifiedImageError
    except ImportError:  # pragma: no cover - Pillow ships with the image extra
        return ImageMeta()
    try:
        with Image.open(path) as im:
            meta = ImageMeta(mode=im.mode, frames=int(getattr(im, "n_frames", 1) or 1))
            meta.icc = im.info.get("icc_profile") or None
            meta.dpi = _dpi(_jfif_dpi(im.info) if im.format == "JPEG" else im.info.get("dpi"))
            if im.format == "PNG":
                meta.png_colour = _png_colour_chunks(im.info)
            # Pillow decodes a whole PNG to reach text or EXIF chunks that may follow the pixel data;
            # when none does (the usual case), what it read before the pixels is all there is
            header_only = im.format == "PNG" and meta.frames == 1 and not png_has_late_metadata(path)
            text = getattr(getattr(im, "png", None), "im_text", None) if header_only else None
            if text is None:
                header_only = False
                text = getattr(im, "text", {}) if im.format == "PNG" else {}
            meta.text = {str(k): str(v) for k, v in text.items()}
            exif = im.getexif() if not header_only or "exif" in im.info else {}
            if len(exif):
                meta.orientation = int(exif.get(ORIENTATION_TAG, 1) or 1)
                if meta.orientation not in range(1, 9):
                    meta.orientation = 1
                exif[ORIENTATION_TAG] = 1
                b = exif.tobytes()
                meta.exif = b[6:] if b.startswith(b"Exif\x00\x00") else b
    except (UnidentifiedImageError, OSError, ValueError, SyntaxError) as exc:
        log.debug("no metadata read from %s: %s", path, exc)
        return ImageMeta()
    return meta


def _dpi(value) -> tuple | None:
    """(x, y) dots per inch from Pillow's ``info["dpi"]``; None when absent or not positive."""
    try:
        x, y = (float(v) for v in value)
    except (TypeError, ValueError):
        return None
    return (x, y) if x > 0 and y > 0 and np.isfinite(x) and np.isfinite(y) else None


def _jfif_dpi(info: dict):
    """A JPEG's dots per inch from its JFIF density (Pillow's ``info["dpi"]`` falls back to 72 when
    the EXIF holds no resolution: a value the file does not hold); None for an aspect ratio only."""
    unit, density = info.get("jfif_unit"), info.get("jfif_density")
    if unit not in (1, 2) or not density:
        return None
    return tuple(float(v) * (2.54 if unit == 2 else 1.0) for v in density)


def _png_colour_chunks(info: dict) -> list:
    """The gAMA, cHRM and sRGB chunks (type, data) of a PNG, from what Pillow read of them."""
    out = []
    try:
        if info.get("gamma"):
            out.append((b"gAMA", struct.pack(">I", round(float(info["gamma"]) * 100000))))
        if info.get("chromaticity") and len(info["chromaticity"]) == 8:
            out.append((b"cHRM", struct.pack(">8I", *(round(float(v) * 100000) for v in info["chromaticity"]))))
        if info.get("srgb") is not None:
            out.append((b"sRGB", bytes([int(info["srgb"]) & 0xFF])))
    except (TypeError, ValueError, struct.error):
        return []
    return out


def icc_space(icc: bytes | None) -> str | None:
    """The colour space an ICC profile describes (``"RGB"``, ``"GRAY"``, ``"CMYK"``, ...), from its header.

    Examples
    --------
    >>> from PIL import ImageCms
    >>> from odnn_sep.image.io_meta import icc_space
    >>> icc_space(ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes())
    'RGB'
    >>> icc_space(b"short") is None
    True
    """
    if not icc or len(icc) < 20:
        return None
    return icc[16:20].decode("latin-1").strip() or None


def for_pixels(meta: ImageMeta | None, grey: bool) -> ImageMeta | None:
    """``meta`` without an ICC profile of another colour space than the pixels written (``grey``: one
    grey channel; otherwise RGB), with a warning; unchanged otherwise.

    A CMYK JPEG is decoded to RGB: its CMYK profile, written onto the RGB output, is a profile the
    pixels do not follow (PNG forbids it; viewers ignore it or read the pixels as ink).

    Examples
    --------
    >>> from PIL import ImageCms
    >>> from odnn_sep.image.io_meta import ImageMeta, for_pixels
    >>> srgb = ImageCms.ImageCmsProfile(ImageCms.createProfile("sRGB")).tobytes()
    >>> cmyk = srgb[:16] + b"CMYK" + srgb[20:]
    >>> for_pixels(ImageMeta(icc=srgb), grey=False).icc == srgb
    True
    >>> for_pixels(ImageMeta(icc=cmyk, text={"a": "b"}), grey=False).icc is None
    True
    """
    space = icc_space(meta.icc) if meta is not None else None
    want = "GRAY" if grey else "RGB"
    if space is None or space == want:
        return meta
    log.warning("the input's colour profile is for %s pixels and the output holds %s ones: the profile is not "
                "written (the %s pixels were converted without it)", space, want,
                "CMYK" if space == "CMYK" else "input's")
    return dataclasses.replace(meta, icc=None)


# PNG chunks of metadata that may come after the pixel data (IDAT)
LATE_PNG_CHUNKS = (b"tEXt", b"zTXt", b"iTXt", b"eXIf")


def png_has_late_metadata(path) -> bool:
    """Whether a PNG file has text or EXIF chunks after its first pixel-data chunk (chunk headers
    only are read; the pixel data are skipped). True when the file cannot be walked.

    Parameters
    ----------
    path : str or Path
        A PNG file.

    Returns
    -------
    bool

    Examples
    --------
    >>> import os, tempfile
    >>> from PIL import Image, PngImagePlugin
    >>> from odnn_sep.image.io_meta import png_has_late_metadata
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.new("RGB", (48, 32)).save(os.path.join(d, "x.png"))
    ...     info = PngImagePlugin.PngInfo(); info.add_text("Title", "t")
    ...     Image.new("RGB", (48, 32)).save(os.path.join(d, "t.png"), pnginfo=info)
    ...     png_has_late_metadata(os.path.join(d, "x.png")), png_has_late_metadata(os.path.join(d, "t.png"))
    (False, False)
    """
    try:
        with open(path, "rb") as fh:
            if fh.read(8) != b"\x89PNG\r\n\x1a\n":
                return True
            seen_idat = False
            while True:
                head = fh.read(8)
                if len(head) < 8:
                    return True  # truncated: let Pillow decide
                n, kind = struct.unpack(">I4s", head)
                if kind == b"IEND":
                    return False
                seen_idat = seen_idat or kind == b"IDAT"
                if seen_idat and kind in LATE_PNG_CHUNKS:
                    return True
                fh.seek(n + 4, 1)  # the chunk's data and CRC
    except OSError:
        return True


def apply_orientation(a: np.ndarray, orientation: int) -> np.ndarray:
    """The pixels ``a`` (H, W[, C]) turned upright as EXIF ``orientation`` (1-8) says.

    Parameters
    ----------
    a : np.ndarray
        (H, W) or (H, W, C) pixels as stored in the file.
    orientation : int
        EXIF orientation, 1-8; other values leave the pixels as they are.

    Returns
    -------
    np.ndarray
        Contiguous upright pixels ((W, H[, C]) for orientations 5-8).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.io_meta import apply_orientation
    >>> apply_orientation(np.arange(6).reshape(2, 3), 6)
    array([[3, 0],
           [4, 1],
           [5, 2]])
    >>> apply_orientation(np.zeros((32, 48, 3)), 8).shape
    (48, 32, 3)
    """
    ops = {1: lambda x: x, 2: lambda x: x[:, ::-1], 3: lambda x: x[::-1, ::-1], 4: lambda x: x[::-1],
           5: lambda x: np.swapaxes(x, 0, 1), 6: lambda x: np.rot90(x, -1),
           7: lambda x: np.rot90(x, 2).swapaxes(0, 1), 8: lambda x: np.rot90(x, 1)}
    return np.ascontiguousarray(ops.get(int(orientation), ops[1])(a))


def _png_chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def _png_text(key: str, value: str) -> bytes:
    """An iTXt chunk (UTF-8 text; keywords are 1-79 Latin-1 characters)."""
    k = key.encode("latin-1", "replace")[:79] or b"Comment"
    return _png_chunk(b"iTXt", k + b"\x00\x00\x00\x00\x00" + value.encode("utf-8"))


def add_to_png(buf: bytes, meta: ImageMeta) -> bytes:
    """PNG bytes with the colour (gAMA, cHRM, sRGB, iCCP), pHYs, eXIf and text chunks inserted after IHDR.

    Parameters
    ----------
    buf : bytes
        An encoded PNG stream.
    meta : ImageMeta
        Metadata to insert.

    Returns
    -------
    bytes
        The PNG stream with the metadata chunks.

    Examples
    --------
    >>> import cv2
    >>> import numpy as np
    >>> from odnn_sep.image.io_meta import ImageMeta, add_to_png
    >>> buf = cv2.imencode(".png", np.zeros((32, 48), np.uint8))[1].tobytes()
    >>> out = add_to_png(buf, ImageMeta(text={"Title": "x"}))
    >>> b"iTXtTitle" in out, out.startswith(b"\\x89PNG")
    (True, True)
    """
    if not buf.startswith(b"\x89PNG\r\n\x1a\n"):
        raise FormatError("internal: the encoder did not return a PNG stream")
    ihdr_end = 8 + 12 + struct.unpack(">I", buf[8:12])[0]
    extra = b""
    for kind, data in meta.png_colour:
        extra += _png_chunk(kind, data)
    if meta.icc:
        extra += _png_chunk(b"iCCP", b"ICC profile\x00\x00" + zlib.compress(meta.icc))
    if meta.dpi:
        ppm = [max(1, round(v / 0.0254)) for v in meta.dpi]   # pixels per metre
        extra += _png_chunk(b"pHYs", struct.pack(">IIB", ppm[0], ppm[1], 1))
    if meta.exif:
        extra += _png_chunk(b"eXIf", meta.exif)
    for k, v in meta.text.items():
        extra += _png_text(k, v)
    return buf[:ihdr_end] + extra + buf[ihdr_end:]


def add_to_jpeg(buf: bytes, meta: ImageMeta) -> bytes:
    """JPEG bytes with the EXIF (APP1) and ICC (APP2) segments inserted after SOI and JFIF, and the
    resolution written into JFIF's density fields.

    Parameters
    ----------
    buf : bytes
        An encoded JPEG stream.
    meta : ImageMeta
        Metadata to insert (PNG text is not held by JPEG and is ignored).

    Returns
    -------
    bytes
        The JPEG stream with the APP1/APP2 segments.

    Examples
    --------
    >>> import cv2
    >>> import numpy as np
    >>> from odnn_sep.image.io_meta import ImageMeta, add_to_jpeg
    >>> buf = cv2.imencode(".jpg", np.zeros((32, 48), np.uint8))[1].tobytes()
    >>> out = add_to_jpeg(buf, ImageMeta(icc=b"profile"))
    >>> len(out) - len(buf), b"ICC_PROFILE" in out
    (25, True)
    """
    if not buf.startswith(b"\xff\xd8"):
        raise FormatError("internal: the encoder did not return a JPEG stream")
    pos = 2
    if buf[2:4] == b"\xff\xe0":  # keep JFIF's APP0 first
        pos = 4 + struct.unpack(">H", buf[4:6])[0]
        if meta.dpi and buf[6:11] == b"JFIF\x00" and pos >= 18:
            # the resolution: units 1 (dots per inch), X and Y density (OpenCV writes 0: aspect only)
            dens = struct.pack(">BHH", 1, *(min(65535, max(1, round(v))) for v in meta.dpi))
            buf = buf[:13] + dens + buf[18:]
    segs = b""
    if meta.exif and len(meta.exif) + 8 <= 65535:
        segs += b"\xff\xe1" + struct.pack(">H", len(meta.exif) + 8) + b"Exif\x00\x00" + meta.exif
    if meta.icc:
        parts = [meta.icc[i:i + ICC_CHUNK] for i in range(0, len(meta.icc), ICC_CHUNK)]
        if len(parts) <= 255:
            for i, p in enumerate(parts):
                body = b"ICC_PROFILE\x00" + bytes([i + 1, len(parts)]) + p
                segs += b"\xff\xe2" + struct.pack(">H", len(body) + 2) + body
    return buf[:pos] + segs + buf[pos:]


def add_metadata(buf: bytes, suffix: str, meta: ImageMeta | None) -> bytes:
    """Encoded image bytes with ``meta`` added where the format holds it (PNG, JPEG); other formats
    are returned unchanged, with a warning if metadata are dropped.

    Parameters
    ----------
    buf : bytes
        Encoded image.
    suffix : str
        File extension of the format (``".png"``, ``".jpg"``, ...).
    meta : ImageMeta or None
        Metadata to add; None or empty metadata return ``buf`` unchanged.

    Returns
    -------
    bytes

    Examples
    --------
    >>> from odnn_sep.image.io_meta import ImageMeta, add_metadata
    >>> add_metadata(b"data", ".webp", None)
    b'data'
    >>> add_metadata(b"data", ".bmp", ImageMeta(icc=b"p"))
    b'data'
    """
    if meta is None or not (meta.exif or meta.icc or meta.text or meta.dpi or meta.png_colour):
        return buf
    s = suffix.lower()
    if s == ".png":
        return add_to_png(buf, meta)
    if s in (".jpg", ".jpeg"):
        return add_to_jpeg(buf, meta)
    if meta.exif or meta.icc or meta.text:
        log.warning("EXIF/ICC metadata are not written to %s files; write PNG or JPEG to keep them", s)
    return buf
