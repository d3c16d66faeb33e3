"""A TIFF's orientation tag, cleared in memory before OpenCV decodes the file.

OpenCV's TIFF decoder turns the pixels upright itself (libtiff reads the Orientation tag), even
with ``IMREAD_UNCHANGED``, while its JPEG, PNG and WebP decoders leave them as stored. The reader
(``io.read_image_meta``) turns every format upright once, from the orientation Pillow reads; a TIFF
with orientation 2-8 was turned twice (a photo tagged "rotate 90" came out upside down). Setting
the tag to 1 in a copy of the bytes makes OpenCV return the stored pixels, whatever its version.
"""
from __future__ import annotations

import struct

ORIENTATION_TAG = 0x0112


def _first_ifd(data: bytes):
    """(byte order, offset of IFD0, big TIFF) of a TIFF stream, or None for another format."""
    if len(data) < 16 or data[:2] not in (b"II", b"MM"):
        return None
    e = "<" if data[:2] == b"II" else ">"
    magic = struct.unpack(e + "H", data[2:4])[0]
    if magic == 42:
        return e, struct.unpack(e + "I", data[4:8])[0], False
    if magic == 43:  # BigTIFF: 8-byte offsets and counts
        return e, struct.unpack(e + "Q", data[8:16])[0], True
    return None


def orientation_cleared(data: bytes) -> bytes | None:
    """A copy of the TIFF bytes ``data`` with the first image's Orientation tag set to 1 (stored
    pixels read as they are); None when ``data`` is not a TIFF or has no such tag.

    Parameters
    ----------
    data : bytes
        The whole file.

    Returns
    -------
    bytes or None

    Examples
    --------
    >>> import io
    >>> from PIL import Image
    >>> from odnn_sep.image.io_tiff import orientation_cleared
    >>> b = io.BytesIO(); ex = Image.Exif(); ex[0x0112] = 6
    >>> Image.new("RGB", (4, 2)).save(b, format="TIFF", exif=ex.tobytes())
    >>> Image.open(io.BytesIO(orientation_cleared(b.getvalue()))).getexif()[0x0112]
    1
    >>> orientation_cleared(b"\\x89PNG\\r\\n\\x1a\\n" + bytes(16)) is None
    True
    """
    head = _first_ifd(data)
    if head is None:
        return None
    e, off, big = head
    count_fmt, entry, value_at = (e + "Q", 20, 12) if big else (e + "H", 12, 8)
    step = 8 if big else 2
    if off + step > len(data):
        return None
    n = struct.unpack(count_fmt, data[off:off + step])[0]
    for i in range(min(n, (len(data) - off - step) // entry)):
        pos = off + step + i * entry
        tag, kind = struct.unpack(e + "HH", data[pos:pos + 4])
        if tag != ORIENTATION_TAG:
            continue
        fmt = {3: "H", 4: "I", 16: "Q"}.get(kind)  # SHORT as the standard says; LONG written by some tools
        if fmt is None:
            return None
        out = bytearray(data)
        v = pos + value_at
        out[v:v + struct.calcsize(fmt)] = struct.pack(e + fmt, 1)  # values sit at the field's start
        return bytes(out)
    return None
