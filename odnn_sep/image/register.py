"""Sub-pixel registration of a rendered mark against the blend model.

After the correlation search (``locate``), the geometry (centre, angle, size) is refined by
minimising the residual of the blend model itself (``estimate``): the photo polynomials and the
mark colour are projected out for the current opacity, so the objective measures only how well the
rendered coverage explains the image. The patch grid is frozen during the search so the objective is
continuous in the geometry.
"""
from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from odnn_sep.image.estimate import BlendFit, drop_clipped, fit_blend, patch_grid, take_patches
from odnn_sep.image.profile import DataProfile, design
from odnn_sep.image.render import place, render_text

# From this font size (px) on only the nearest whole size to the continuous optimum is tried, not
# both neighbours: the optimum of a large mark lies within a fraction of a pixel of its size, and on
# a 12-megapixel photo each extra registration of a large mark costs about half a second.
WHOLE_SIZE_MAX_PX = 64.0
# The registration samples the rendering at its patches' pixels instead of warping the whole crop
# when the crop has more than this many times as many pixels as the patches.
SAMPLE_RATIO = 3.0


@dataclasses.dataclass
class Placed:
    """One mark registered on the image: font, size (px), angle (degrees), centre (x, y), the box
    (x0, y0, x1, y1, exclusive) of the crop holding it, its coverage M inside the box and the blend
    fit (opacity, colour) under that coverage.

    Examples
    --------
    >>> import numpy as np
    >>> from pathlib import Path
    >>> from odnn_sep.image.estimate import BlendFit
    >>> from odnn_sep.image.register import Placed
    >>> fit = BlendFit(0.5, np.ones(3) * 0.5, 0.01, 0.0, 10, 8, 1.0)
    >>> p = Placed(Path("DejaVuSans-Bold.ttf"), 20.0, 0.0, (32.0, 24.0), (12, 9, 52, 41), np.zeros((32, 40)), fit)
    >>> p.coverage.shape, p.fit.alpha
    ((32, 40), 0.5)
    """

    font: Path
    size: float
    angle: float
    center: tuple[float, float]
    box: tuple[int, int, int, int]      # x0, y0, x1, y1 (exclusive) of the crop holding the mark
    coverage: np.ndarray                 # M inside box
    fit: BlendFit


def render_at(text, font, size, angle, center, shape):
    """Coverage of the text placed on an image of ``shape`` = (H, W); returns (M crop, box).

    Parameters
    ----------
    text : str
        The mark's text.
    font : str or Path
        Font file or name.
    size : float
        Font size (em) in px.
    angle : float
        Rotation in degrees, counter-clockwise.
    center : tuple of float
        (x, y) of the mark's centre.
    shape : tuple of int
        (H, W) of the image.

    Returns
    -------
    crop : np.ndarray
        Coverage in [0, 1] over ``box``.
    box : tuple of int
        (x0, y0, x1, y1) clipped to the image.

    Examples
    --------
    >>> from odnn_sep.image.register import render_at
    >>> m, box = render_at("Hi", "DejaVuSans-Bold", 20, 0, (32, 24), (48, 64))
    >>> m.shape, box
    ((25, 33), (16, 12, 49, 37))
    """
    return place(render_text(text, font, size), shape, center, angle)


def coverage_at(coverage, center, angle, rows, cols) -> np.ndarray:
    """The upright ``coverage`` as ``render.place`` puts it (rotated by ``angle`` degrees about its
    centre, the centre at ``center`` = (x, y), bicubic), sampled at the pixels (``rows``, ``cols``) only.

    Parameters
    ----------
    coverage : np.ndarray
        (h, w) upright coverage in [0, 1].
    center : tuple of float
        (x, y) of its centre on the grid of ``rows`` and ``cols``.
    angle : float
        Rotation in degrees, counter-clockwise as displayed.
    rows, cols : np.ndarray
        Integer pixel coordinates, any (equal) shape.

    Returns
    -------
    np.ndarray
        float64 coverage in [0, 1], the shape of ``rows``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.register import coverage_at
    >>> from odnn_sep.image.render import place, render_text
    >>> m = render_text("Hi", "DejaVuSans-Bold", 20)
    >>> crop, (x0, y0, x1, y1) = place(m, (40, 60), (30.3, 19.6), 12.0)
    >>> rr, cc = np.mgrid[y0:y1, x0:x1]
    >>> bool(np.abs(coverage_at(m, (30.3, 19.6), 12.0, rr, cc) - crop).max() < 0.05)
    True
    """
    import cv2

    h, w = coverage.shape
    th = np.deg2rad(angle)
    c, s = np.cos(th), np.sin(th)
    # inverse of place's map src -> dst, R (p - c_src) + center with R = [[c, s], [-s, c]] (y down)
    dx, dy = cols - center[0], rows - center[1]
    sx = (c * dx - s * dy + (w - 1) / 2.0).astype(np.float32)
    sy = (s * dx + c * dy + (h - 1) / 2.0).astype(np.float32)
    out = cv2.remap(np.ascontiguousarray(coverage, dtype=np.float32), sx, sy, cv2.INTER_CUBIC,
                    borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    return np.clip(out, 0.0, 1.0).astype(np.float64)


def nelder_mead(fun, x0, step, maxiter):
    """(argmin, min) of ``fun`` by Nelder-Mead from the simplex ``x0``, ``x0 + diag(step)``.

    Parameters
    ----------
    fun : callable
        Objective of a 1-D array, returning a float.
    x0 : np.ndarray
        Starting point (n,).
    step : np.ndarray
        (n,) edge lengths of the initial simplex.
    maxiter : int
        Most iterations.

    Returns
    -------
    x : np.ndarray
        The minimiser found.
    f : float
        The objective there.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.register import nelder_mead
    >>> x, f = nelder_mead(lambda v: float(((v - 1) ** 2).sum()), np.zeros(2), np.ones(2), 200)
    >>> x.round(2).tolist(), round(f, 4)
    ([1.0, 1.0], 0.0)
    """
    from scipy.optimize import minimize

    sim = np.vstack([x0, x0 + np.diag(step)])
    r = minimize(fun, x0, method="Nelder-Mead",
                 options={"initial_simplex": sim, "maxiter": maxiter, "xatol": 0.02, "fatol": 1e-9})
    return r.x, float(r.fun)


def _whole_size(obj, p, f, size, iterations):
    """(p, f) at the better of the continuous optimum ``p`` (objective ``f``) and the whole font sizes
    next to it (``p[3]`` is the log of the size over ``size``).

    Fonts are usually rendered at a whole pixel size, and hinting makes a 29.15 px rendering differ
    from a 29 px one in ways no continuous scale reproduces: test the nearest whole size as well.
    Both neighbours: the continuous optimum of a hinted font often lies nearer the wrong one. And
    one size further each way: a search that hands over the wrong whole size leaves the continuous
    optimum stuck there ("SAMPLE" drawn at 40 px over 20 synthetic photos: registered at 41.0 px on
    13 of them, 34 dB instead of 67 dB, the mark left as outlines)."""
    s_c = size * np.exp(p[3])
    best_int = None
    near = sorted({int(np.floor(s_c)) - 1, int(np.floor(s_c)), int(np.ceil(s_c)), int(np.ceil(s_c)) + 1})
    if s_c >= WHOLE_SIZE_MAX_PX:  # a large mark's optimum is not a pixel off: the nearest size only
        near = [int(np.round(s_c))]
    for s_int in near:
        if s_int < 1 or abs(s_c - s_int) < 1e-3:
            continue
        q3 = np.log(s_int / size)
        q, g = nelder_mead(lambda v, q3=q3: obj(np.r_[v, q3]), p[:3], np.array([0.3, 0.3, 0.15]),
                           min(iterations, 25))
        if best_int is None or g < best_int[1]:
            best_int = (np.r_[q, q3], g)
    if best_int is not None and best_int[1] < f:
        return best_int
    return p, f


def _objective(crop, M, fit0, cov, geometry, random_state):
    """The registration's objective of the geometry offset p = (dx, dy, d angle, log size ratio): the
    blend model's residual at the opacity of ``fit0`` on a frozen patch grid; None without patches.

    ``cov(p)``: the coverage over the whole crop; ``geometry(p)``: (upright rendering, centre, angle)."""
    rng = np.random.default_rng(random_state)
    py, px, ps = patch_grid(M, fit0.patch, 400, rng)
    if len(py) == 0:
        return None
    Yp, py, px = drop_clipped(take_patches(crop, py, px, ps), py, px)
    a0 = float(np.clip(fit0.alpha, 0.05, 0.98))
    base = DataProfile(Yp, take_patches(M, py, px, ps)[:, :, 0], design(ps, 1))  # the image patches' part, once
    oy, ox = np.divmod(np.arange(ps * ps), ps)
    rows, cols = py[:, None] + oy[None], px[:, None] + ox[None]   # the patches' pixels in the crop
    # A large mark's crop holds many more pixels than its patches: the rendering is then sampled at
    # the patches' pixels only (per pixel that costs about 2.5 times a whole warp's, so a small crop is
    # warped whole and then cut into patches)
    sampled = M.shape[0] * M.shape[1] > SAMPLE_RATIO * rows.size

    def obj(p):
        Mp = coverage_at(*geometry(p), rows, cols) if sampled else take_patches(cov(p), py, px, ps)[:, :, 0]
        return base.with_coverage(Mp)(a0)

    return obj


def refine(y: np.ndarray, text: str, font, size: float, angle: float, center, *, iterations: int = 60,
           whole_sizes: bool = True, random_state=0) -> Placed:
    """Refine (centre, angle, size) of one mark by the blend model's residual, then fit opacity/colour.

    Why long (9 parameters): the data, the starting placement (text, font, size, angle, centre), then
    keyword options.

    ``y`` is the whole image as float (H, W, C) in [0, 1] (or a view giving float crops).
    ``whole_sizes``: also try the whole font sizes next to the optimum (off on a resampled copy).

    Parameters
    ----------
    y : np.ndarray or FloatView
        The whole image, float (H, W, C) in [0, 1].
    text : str
        The mark's text.
    font : str or Path
        Font file or name.
    size, angle : float
        Starting font size (px) and rotation (degrees).
    center : tuple of float
        Starting (x, y) of the mark's centre.
    iterations : int, default 60
        Most Nelder-Mead iterations.
    whole_sizes : bool, default True
        Also try the whole font sizes next to the optimum.
    random_state : int or Generator, default 0
        Seed of the patch grid.

    Returns
    -------
    Placed
        The refined placement with its blend fit.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.register import refine
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.repeat(np.linspace(70, 110, 48)[:, None, None], 64, 1).repeat(3, 2).astype(np.uint8)
    >>> y, _ = add_text_watermark(clean, "Hi", size=20, center=(32, 24), alpha=0.5)
    >>> p = refine(y / 255.0, "Hi", "DejaVuSans-Bold", 19.5, 0.0, (31.5, 24.5))
    >>> round(p.size), round(p.angle), abs(p.fit.alpha - 0.5) < 0.02
    (20, 0, True)
    """
    H, W = y.shape[:2]
    M0, box = render_at(text, font, size, angle, center, (H, W))
    x0, y0, x1, y1 = box
    pad = 4
    bx = (max(0, x0 - pad), max(0, y0 - pad), min(W, x1 + pad), min(H, y1 + pad))
    crop = y[bx[1]:bx[3], bx[0]:bx[2]]
    local = (center[0] - bx[0], center[1] - bx[1])
    shape = crop.shape[:2]

    def cov(p):
        c = (local[0] + p[0], local[1] + p[1])
        m, (a0, b0, a1, b1) = place(render_text(text, font, size * np.exp(p[3])), shape, c, angle + p[2])
        full = np.zeros(shape)
        full[b0:b1, a0:a1] = m
        return full

    M = cov(np.zeros(4))
    fit0 = fit_blend(crop, M, random_state=random_state)
    obj = _objective(crop, M, fit0, cov, lambda p: (render_text(text, font, size * np.exp(p[3])),
                                                    (local[0] + p[0], local[1] + p[1]), angle + p[2]), random_state)
    if obj is None:
        return Placed(Path(font), size, angle, center, bx, M, fit0)
    f_start = obj(np.zeros(4))
    p, f = nelder_mead(obj, np.zeros(4), np.array([0.5, 0.5, 0.3, 0.01]), iterations)
    if f > f_start:
        p, f = np.zeros(4), f_start
    if whole_sizes:
        p, f = _whole_size(obj, p, f, size, iterations)
    M = cov(p)
    fit = fit_blend(crop, M, random_state=random_state)
    return Placed(Path(font), float(size * np.exp(p[3])), float(angle + p[2]),
                  (float(center[0] + p[0]), float(center[1] + p[1])), bx, M, fit)


__all__ = ["refine", "Placed", "render_at", "coverage_at"]
