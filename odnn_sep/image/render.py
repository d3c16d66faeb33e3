"""Text rendering: the watermark's physics basis is the glyph coverage of the user's text.

A TrueType font is rasterised upright (anti-aliased coverage in [0, 1]) with Pillow's FreeType
binding, then placed on the image grid by one affine warp (rotation about the text centre plus a
sub-pixel translation), so position and angle are continuous parameters.
"""
from __future__ import annotations

import functools
import logging
import os
from pathlib import Path

import numpy as np

from odnn_sep.errors import InputError

log = logging.getLogger(__name__)

# Tried in this order when --font is not given; the DejaVu family is guaranteed (matplotlib ships it).
DEFAULT_FONT_NAMES = (
    "DejaVuSans-Bold", "DejaVuSans", "DejaVuSerif-Bold", "DejaVuSerif", "DejaVuSansMono-Bold",
    "Arial Bold", "Arial", "LiberationSans-Bold", "LiberationSans-Regular", "Helvetica",
)
# The same family's slanted faces, tried by one more look when nothing upright is found: an italic
# mark's strokes lean away from every upright rendering (``textmode.find``).
SLANTED_FONT_NAMES = ("DejaVuSerif-Italic", "DejaVuSans-Oblique")


def font_dirs() -> list[Path]:
    """Folders searched for fonts given by name: matplotlib's, the system's, Pillow's and OpenCV's.

    Returns
    -------
    list of Path
        The folders that exist on this system, in search order.

    Examples
    --------
    >>> from odnn_sep.image.render import font_dirs
    >>> dirs = font_dirs()
    >>> all(d.is_dir() for d in dirs)
    True
    """
    import importlib.util

    dirs: list[Path] = []
    # located, not imported: importing matplotlib only for its font folder costs a command 0.15 s
    spec = importlib.util.find_spec("matplotlib")
    if spec is not None and spec.origin:
        dirs.append(Path(spec.origin).parent / "mpl-data" / "fonts" / "ttf")
    dirs += [Path("/usr/share/fonts"), Path("/usr/local/share/fonts"), Path.home() / ".fonts",
             Path("/Library/Fonts"), Path("/System/Library/Fonts"), Path("C:/Windows/Fonts")]
    for mod in ("PIL", "cv2"):
        try:
            m = __import__(mod)
            dirs.append(Path(os.path.dirname(m.__file__)))
        except ImportError:  # pragma: no cover
            pass
    return [d for d in dirs if d.is_dir()]


@functools.lru_cache(maxsize=1)
def _font_index() -> dict[str, Path]:
    idx: dict[str, Path] = {}
    for d in font_dirs():
        for p in sorted(d.rglob("*")):
            if p.suffix.lower() in (".ttf", ".otf", ".ttc"):
                for key in (p.stem.lower(), p.stem.lower().replace("-", " "), p.name.lower()):
                    idx.setdefault(key, p)
    return idx


def resolve_font(font) -> Path:
    """Turn ``--font`` (a path, or a name such as ``DejaVuSans-Bold``) into a font file path.

    Examples
    --------
    >>> resolve_font("DejaVuSans-Bold").name
    'DejaVuSans-Bold.ttf'
    """
    return _resolve(str(font))


@functools.lru_cache(maxsize=256)
def _resolve(font: str) -> Path:
    # cached: the search renders thousands of templates and each looked its font up again (a file
    # system check per rendering, about 5 % of a search's time)
    base, tracking = split_tracking(font)
    if tracking:  # a spaced variant of a font (``spaced``): the same font file, spaced
        return Path(spaced(resolve_font(base), tracking))
    p = Path(font).expanduser()
    if p.is_file():
        return p
    idx = _font_index()
    key = str(font).strip().lower()
    for k in (key, key.replace(" ", "-"), key.replace("-", " "), key + ".ttf"):
        if k in idx:
            return idx[k]
    raise InputError(
        f"font {str(font)!r} not found as a file nor by name in {', '.join(str(d) for d in font_dirs())}; "
        f"pass a .ttf/.otf path or a name such as 'DejaVuSans-Bold'"
    )


def default_fonts(names=DEFAULT_FONT_NAMES) -> list[Path]:
    """The candidate fonts tried when the user does not pin one (those present on this system).

    ``names``: the font names to look up (``SLANTED_FONT_NAMES`` for the slanted look).

    Returns
    -------
    list of Path
        Font files of ``names`` that were found, in that order, without repeats.

    Examples
    --------
    >>> from odnn_sep.image.render import default_fonts
    >>> default_fonts()[0].name
    'DejaVuSans-Bold.ttf'
    """
    out = []
    for name in names:
        try:
            p = resolve_font(name)
        except InputError:
            continue
        if p not in out:
            out.append(p)
    return out


@functools.lru_cache(maxsize=512)
def _load(path: str, size: float):
    from PIL import ImageFont

    try:
        return ImageFont.truetype(path, size=size)
    except OSError as exc:
        raise InputError(f"font {path!r} could not be loaded ({exc}); pass a TrueType/OpenType font") from None


# A font with extra letter spacing (tracking, in em) is written ``<font>@tracking=<em>``: the search
# tries spaced variants of its fonts as if they were fonts of their own (``spaced``).
TRACKING_TAG = "@tracking="


def spaced(font, tracking: float) -> str:
    """The font ``font`` drawn with ``tracking`` em of extra space after every letter, as a font name
    that ``render_text`` (and everything that renders through it) understands.

    Examples
    --------
    >>> split_tracking(spaced("DejaVuSans", 0.15))[1]
    0.15
    """
    base, _ = split_tracking(font)
    if not tracking:
        return str(base)
    return f"{base}{TRACKING_TAG}{float(tracking):g}"


def split_tracking(font) -> tuple[str, float]:
    """(font name or path, tracking in em) of a font written by ``spaced`` (tracking 0 otherwise).

    Parameters
    ----------
    font : str or Path
        A font name or path, possibly with a ``@tracking=<em>`` suffix.

    Returns
    -------
    tuple of (str, float)

    Examples
    --------
    >>> from odnn_sep.image.render import split_tracking
    >>> split_tracking("DejaVuSans@tracking=0.1"), split_tracking("Arial")
    (('DejaVuSans', 0.1), ('Arial', 0.0))
    """
    s = str(font)
    if TRACKING_TAG in s:
        base, _, t = s.rpartition(TRACKING_TAG)
        try:
            return base, float(t)
        except ValueError:
            pass
    return s, 0.0


def _render_spaced(text: str, f, size: float, tracking: float) -> np.ndarray:
    """Letter by letter with ``tracking`` em of extra advance (marks are often drawn letter-spaced)."""
    from PIL import Image, ImageDraw

    extra = tracking * size
    adv = [f.getlength(ch) + extra for ch in text]
    _, y0, _, y1 = f.getbbox(text)
    margin = int(np.ceil(size)) + 4
    im = Image.new("L", (int(np.ceil(sum(adv))) + 2 * margin, int(y1 - y0) + 2 * margin), 0)
    d = ImageDraw.Draw(im)
    x = float(margin)
    for ch, a in zip(text, adv):
        d.text((x, margin - y0), ch, fill=255, font=f)
        x += a
    a = np.asarray(im, dtype=np.float32) / 255.0
    rr, cc = np.nonzero(a > 0)
    if rr.size == 0:
        return np.zeros((5, 5), np.float32)
    pad = 2
    return np.pad(a[rr.min():rr.max() + 1, cc.min():cc.max() + 1], pad)


@functools.lru_cache(maxsize=256)
def _render_cached(text: str, font: str, size: float, tracking: float = 0.0) -> np.ndarray:
    from PIL import Image, ImageDraw

    f = _load(font, float(size))
    if tracking:
        a = _render_spaced(text, f, float(size), tracking)
        a.setflags(write=False)
        return a
    x0, y0, x1, y1 = f.getbbox(text)
    pad = 2
    w, h = max(1, x1 - x0) + 2 * pad, max(1, y1 - y0) + 2 * pad
    im = Image.new("L", (int(w), int(h)), 0)
    ImageDraw.Draw(im).text((pad - x0, pad - y0), text, fill=255, font=f)
    a = np.asarray(im, dtype=np.float32) / 255.0
    a.setflags(write=False)
    return a


def render_text(text: str, font, size: float) -> np.ndarray:
    """Upright anti-aliased coverage of ``text`` at ``size`` px (em size), ink box plus a 2-px border.

    Examples
    --------
    >>> m = render_text("odnn", "DejaVuSans-Bold", 20)
    >>> float(m.max()) == 1.0 and m.ndim == 2
    True
    """
    if not str(text).strip():
        raise InputError("text is empty or only whitespace; pass the watermark's visible text")
    if not size > 0:
        raise InputError(f"font size must be > 0 px; got {size}")
    from odnn_sep.image.layout import render_layout, split_layout

    base, shifts = split_layout(font)
    if shifts is not None:  # a layout fitted glyph by glyph (``glyphfit``)
        return render_layout(str(text), str(resolve_font(base)), round(float(size), 3), shifts)
    base, tracking = split_tracking(font)
    return _render_cached(str(text), str(resolve_font(base)), round(float(size), 3), tracking)


def place(coverage: np.ndarray, shape: tuple[int, int], center: tuple[float, float], angle: float,
          scale: float = 1.0) -> tuple[np.ndarray, tuple[int, int, int, int]]:
    """Warp an upright coverage onto an image grid: rotate ``angle`` degrees (counter-clockwise as
    displayed) about its centre, scale, and put the centre at ``center`` = (x, y) (sub-pixel).

    Returns the coverage crop and its box (x0, y0, x1, y1) clipped to the image (x1, y1 exclusive);
    an empty box means the mark lies outside the image.

    Parameters
    ----------
    coverage : np.ndarray
        (h, w) upright coverage in [0, 1].
    shape : tuple of int
        (H, W) of the image grid.
    center : tuple of float
        (x, y) of the mark's centre on the grid.
    angle : float
        Rotation in degrees, counter-clockwise as displayed.
    scale : float, default 1.0
        Scale factor.

    Returns
    -------
    crop : np.ndarray
        float32 coverage in [0, 1] over ``box``.
    box : tuple of int
        (x0, y0, x1, y1), clipped to the image; (0, 0, 0, 0) when the mark is outside.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.render import place
    >>> crop, box = place(np.ones((5, 9)), (32, 48), (24, 16), 0)
    >>> crop.shape, box
    ((11, 15), (17, 11, 32, 22))
    >>> place(np.ones((5, 9)), (32, 48), (200, 16), 0)[1]
    (0, 0, 0, 0)
    """
    import cv2

    h, w = coverage.shape
    H, W = shape
    cx, cy = (w - 1) / 2.0, (h - 1) / 2.0
    th = np.deg2rad(angle)
    c, s = np.cos(th) * scale, np.sin(th) * scale
    # extent of the rotated box around the destination centre
    hw = 0.5 * (abs(c) * w + abs(s) * h) + 2
    hh = 0.5 * (abs(s) * w + abs(c) * h) + 2
    x0 = max(0, int(np.floor(center[0] - hw)))
    y0 = max(0, int(np.floor(center[1] - hh)))
    x1 = min(W, int(np.ceil(center[0] + hw)) + 1)
    y1 = min(H, int(np.ceil(center[1] + hh)) + 1)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0), np.float32), (0, 0, 0, 0)
    # forward map src->dst: R (p - c_src) + center - (x0, y0); cv2's image y axis points down, so a
    # counter-clockwise rotation on screen is [[c, s], [-s, c]].
    A = np.array([[c, s], [-s, c]])
    t = np.array([center[0] - x0, center[1] - y0]) - A @ np.array([cx, cy])
    Mx = np.hstack([A, t[:, None]]).astype(np.float64)
    out = cv2.warpAffine(np.ascontiguousarray(coverage, dtype=np.float32), Mx, (x1 - x0, y1 - y0),
                         flags=cv2.INTER_CUBIC, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return np.clip(out, 0.0, 1.0), (x0, y0, x1, y1)


def rotated(coverage: np.ndarray, angle: float, scale: float = 1.0) -> np.ndarray:
    """The whole coverage rotated about its centre with the canvas expanded to hold it.

    Parameters
    ----------
    coverage : np.ndarray
        (h, w) upright coverage in [0, 1].
    angle : float
        Rotation in degrees, counter-clockwise.
    scale : float, default 1.0
        Scale factor.

    Returns
    -------
    np.ndarray
        float32 coverage on a canvas that holds the whole rotated (and scaled) mark.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.render import rotated
    >>> rotated(np.ones((5, 9)), 90).shape
    (11, 8)
    """
    h, w = coverage.shape
    th = np.deg2rad(angle)
    W = int(np.ceil(abs(np.cos(th)) * w * scale + abs(np.sin(th)) * h * scale)) + 2
    H = int(np.ceil(abs(np.sin(th)) * w * scale + abs(np.cos(th)) * h * scale)) + 2
    m, _ = place(coverage, (H, W), ((W - 1) / 2.0, (H - 1) / 2.0), angle, scale)
    return m
