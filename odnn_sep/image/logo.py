"""A reference watermark image (logo) as coverage ``M`` and colours ``L``, and its placement in a photo.

With an alpha channel, ``M`` is the alpha and ``L`` the colour. Without one, the logo is cut out of
its background, the median colour of its border: ``M`` is the colour distance to the background
over the largest such distance within 2 px (the nearby solid ink), and ``L`` is the colour the
anti-aliased edge pixels were mixed from (``L = bg + (logo - bg) / M``). A placement is a similarity transform: centre (x, y) in
the photo, scale and angle (degrees, counter-clockwise, as OpenCV).
"""
from __future__ import annotations

import dataclasses

import numpy as np

from odnn_sep.errors import InputError

# A logo side of at most this many pixels (the photo has its own limit through the image reader).
MAX_LOGO_PX = 4096


@dataclasses.dataclass(frozen=True)
class Logo:
    """``M`` (h, w) coverage in [0, 1]; ``L`` (h, w, C) colours in [0, 1]; ``coloured``: the logo has
    several colours (its own colours are used in the blend) rather than one (colour fitted);
    ``has_alpha``: ``M`` came from the reference image's alpha channel.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Logo
    >>> lg = Logo(np.ones((10, 12)), np.ones((10, 12, 3)), has_alpha=False, coloured=False)
    >>> lg.M.shape, lg.coloured
    ((10, 12), False)
    """

    M: np.ndarray
    L: np.ndarray
    has_alpha: bool
    coloured: bool


@dataclasses.dataclass(frozen=True)
class Placement:
    """A similarity transform of the logo into the photo: centre (``cx``, ``cy``), ``scale``, ``angle``
    (degrees, counter-clockwise) and the search ``score`` that found it.

    Examples
    --------
    >>> from odnn_sep.image.logo import Placement
    >>> Placement(24.0, 16.0, 1.0, 0.0)
    Placement(cx=24.0, cy=16.0, scale=1.0, angle=0.0, score=0.0)
    """

    cx: float
    cy: float
    scale: float
    angle: float
    score: float = 0.0


def _float(a: np.ndarray) -> np.ndarray:
    a = np.asarray(a)
    if a.dtype == np.uint8:
        return a.astype(np.float64) / 255.0
    if a.dtype == np.uint16:
        return a.astype(np.float64) / 65535.0
    if a.dtype.kind == "f":
        return np.clip(a.astype(np.float64), 0.0, 1.0)
    raise InputError(f"reference image dtype must be uint8, uint16 or float in [0, 1]; got {a.dtype}")


def prepare_logo(logo, photo_shape: tuple[int, int], channels: int) -> Logo:
    """Check a reference image and split it into coverage and colours (cropped to its visible part).

    Parameters
    ----------
    logo : (h, w[, C]) array, grey, grey+alpha, RGB or RGBA
    photo_shape : (H, W) of the photo; a larger reference image is refused
    channels : colour channels of the photo (1 or 3); the logo's colours are converted to match

    Returns
    -------
    Logo
        Coverage and colours, cropped to the visible part with a 2-px margin.

    Raises
    ------
    InputError
        For an empty, oversized, fully transparent or uniform reference image.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import prepare_logo
    >>> rgba = np.zeros((12, 16, 4), np.uint8); rgba[3:9, 4:12] = (255, 255, 255, 200)
    >>> lg = prepare_logo(rgba, (32, 48), 3)
    >>> lg.M.shape, lg.L.shape, lg.has_alpha, lg.coloured, round(float(lg.M.max()), 3)
    ((10, 12), (10, 12, 3), True, False, 0.784)
    >>> lg = np.zeros((12, 16), np.uint8); lg[3:9, 4:12] = 255
    >>> prepare_logo(lg, (32, 48), 1).has_alpha       # cut out of its black background
    False
    """
    a = np.asarray(logo)
    if a.size == 0 or a.ndim not in (2, 3) or 0 in a.shape[:2]:
        raise InputError(f"reference image is empty (shape {a.shape}); pass the logo as an image with pixels")
    h, w = a.shape[:2]
    H, W = photo_shape
    if h > H or w > W:
        raise InputError(f"reference image {w}x{h} is larger than the photo {W}x{H}; crop or scale the logo to "
                         f"at most the photo's size")
    if max(h, w) > MAX_LOGO_PX:
        raise InputError(f"reference image {w}x{h} is larger than {MAX_LOGO_PX} px; scale it down")
    f = _float(a)
    if f.ndim == 2:
        f = f[:, :, None]
    alpha = None
    if f.shape[2] in (2, 4):
        alpha, f = f[:, :, -1], f[:, :, :-1]
        if alpha.max() < 1.0 / 255:
            raise InputError("reference image is fully transparent (alpha 0 everywhere); pass the logo itself")
        if alpha.min() == alpha.max():
            alpha = None  # a constant alpha says nothing about the logo's shape
    if f.shape[2] != channels:
        f = f.mean(axis=2, keepdims=True) if channels == 1 else np.repeat(f[:, :, :1], channels, axis=2)
    if alpha is not None:
        M, L = alpha, f
    else:
        M, L = _cut_out(f)
    on = M > 0.02
    if on.sum() < 4:
        raise InputError("reference image shows no logo (it is uniform, or equals its background colour); "
                         "pass the logo with an alpha channel or on a plain background")
    ys, xs = np.nonzero(on)
    y0, y1, x0, x1 = max(0, ys.min() - 2), min(h, ys.max() + 3), max(0, xs.min() - 2), min(w, xs.max() + 3)
    M, L = M[y0:y1, x0:x1], L[y0:y1, x0:x1]
    solid = M > 0.5
    spread = float(np.mean(np.std(L[solid], axis=0))) if solid.sum() > 3 else 0.0
    return Logo(np.ascontiguousarray(M), np.ascontiguousarray(L), alpha is not None, spread > 0.08)


def _cut_out(f: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(M, L) of a logo without alpha on a plain background (the border's median colour)."""
    border = np.concatenate([f[0], f[-1], f[:, 0], f[:, -1]])
    bg = np.median(border, axis=0)
    d = np.sqrt(np.mean((f - bg) ** 2, axis=2))
    if d.max() < 0.05:
        raise InputError("reference image shows no logo (it is uniform, or equals its background colour); "
                         "pass the logo with an alpha channel or on a plain background")
    import cv2

    # each pixel against the strongest ink near it: a logo's inks differ in contrast with the ground
    # (all of them are solid), while an anti-aliased edge pixel is a partial mix with its own ink
    near = cv2.dilate(np.ascontiguousarray(d, np.float32), np.ones((5, 5), np.uint8)).astype(np.float64)
    M = np.where(near > 0.05, np.clip(d / np.maximum(near, 1e-6), 0.0, 1.0), 0.0)
    M[M < 0.1] = 0.0  # the background's own noise and JPEG ringing are not logo
    L = np.clip(bg + (f - bg) / np.maximum(M, 1e-6)[:, :, None], 0.0, 1.0)
    L[M == 0] = bg
    return M, L


def affine(logo_shape, p: Placement) -> np.ndarray:
    """2x3 matrix taking logo pixel coordinates to photo coordinates.

    Parameters
    ----------
    logo_shape : tuple of int
        (h, w[, C]) of the logo.
    p : Placement
        Where the logo's centre goes, with scale and angle.

    Returns
    -------
    np.ndarray
        (2, 3) affine matrix, as OpenCV's warps take it.

    Examples
    --------
    >>> from odnn_sep.image.logo import Placement, affine
    >>> affine((10, 12), Placement(24.0, 16.0, 1.0, 0.0))[:, 2].tolist()
    [18.5, 11.5]
    """
    h, w = logo_shape[:2]
    t = np.deg2rad(p.angle)
    c, s = p.scale * np.cos(t), p.scale * np.sin(t)
    R = np.array([[c, s], [-s, c]])  # counter-clockwise on screen (y down), as cv2.getRotationMatrix2D
    ctr = np.array([(w - 1) / 2.0, (h - 1) / 2.0])
    return np.hstack([R, (np.array([p.cx, p.cy]) - R @ ctr)[:, None]])


def render(logo: Logo, p: Placement, shape: tuple[int, int]):
    """(M, L, box) of the logo placed at ``p`` in a photo of ``shape`` (H, W): coverage and colours
    inside ``box`` = (x0, y0, x1, y1) (clipped to the photo; empty arrays when outside).

    Parameters
    ----------
    logo : Logo
        The prepared logo.
    p : Placement
        Its placement.
    shape : tuple of int
        (H, W) of the photo.

    Returns
    -------
    M : np.ndarray
        (h, w) coverage inside ``box``.
    L : np.ndarray
        (h, w, C) colours inside ``box``.
    box : tuple of int
        (x0, y0, x1, y1); (0, 0, 0, 0) when the logo is outside the photo.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> lg = np.zeros((12, 16), np.uint8); lg[3:9, 4:12] = 255
    >>> logo = prepare_logo(lg, (32, 48), 1)
    >>> M, L, box = render(logo, Placement(24.0, 16.0, 1.0, 0.0), (32, 48))
    >>> M.shape, box, round(float(M.sum()), 1)
    ((13, 15), (17, 10, 32, 23), 48.0)
    >>> render(logo, Placement(200.0, 16.0, 1.0, 0.0), (32, 48))[2]
    (0, 0, 0, 0)
    """
    import cv2

    H, W = shape
    A = affine(logo.M.shape, p)
    h, w = logo.M.shape
    corners = A @ np.array([[0, w - 1, 0, w - 1], [0, 0, h - 1, h - 1], [1, 1, 1, 1]], float)
    x0, y0 = int(np.floor(corners[0].min())) - 1, int(np.floor(corners[1].min())) - 1
    x1, y1 = int(np.ceil(corners[0].max())) + 2, int(np.ceil(corners[1].max())) + 2
    x0, y0, x1, y1 = max(0, x0), max(0, y0), min(W, x1), min(H, y1)
    if x1 <= x0 or y1 <= y0:
        return np.zeros((0, 0)), np.zeros((0, 0, logo.L.shape[2])), (0, 0, 0, 0)
    M, L = logo.M, logo.L
    if p.scale < 0.8:  # shrink with area averaging first: a plain warp would alias thin strokes
        k = p.scale
        M = cv2.resize(M, None, fx=k, fy=k, interpolation=cv2.INTER_AREA)
        L = cv2.resize(L * logo.M[:, :, None], None, fx=k, fy=k, interpolation=cv2.INTER_AREA)
        L = L.reshape(M.shape + (-1,)) / np.maximum(M, 1e-6)[:, :, None]
        A = affine(M.shape, Placement(p.cx, p.cy, 1.0, p.angle))
    A = A.copy()
    A[:, 2] -= (x0, y0)
    size = (x1 - x0, y1 - y0)
    Mw = cv2.warpAffine(np.ascontiguousarray(M, np.float32), A.astype(np.float64), size, flags=cv2.INTER_LINEAR,
                        borderValue=0.0)
    Lm = np.ascontiguousarray((L * M[:, :, None] if L.ndim == 3 else L), np.float32)
    Lw = cv2.warpAffine(Lm, A, size, flags=cv2.INTER_LINEAR, borderValue=0.0)
    Lw = Lw.reshape(Mw.shape + (-1,)) / np.maximum(Mw, 1e-6)[:, :, None]
    return np.clip(Mw, 0.0, 1.0).astype(np.float64), np.clip(Lw, 0.0, 1.0).astype(np.float64), (x0, y0, x1, y1)
