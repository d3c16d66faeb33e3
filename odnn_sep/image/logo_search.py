"""Where is the logo? Coarse-to-fine search over position, scale (0.25-4x) and rotation, single or tiled.

A blended logo shows in the photo as edges: its outline (a step of ``alpha (L - I)``) and the colour
edges inside it. Edge magnitudes do not depend on whether the mark is lighter or darker than the
photo under it, so the photo's gradient magnitude is compared with the logo's. Coarse: on a reduced
copy (longest side ``COARSE_PX``), the logo's edge map at every scale and angle of a grid is matched
by FFT normalised cross-correlation (OpenCV ``matchTemplate``), edges blurred so that half a grid
step still overlaps. Fine: the best few candidates are refined by Nelder-Mead on (x, y, scale,
angle), maximising the correlation of edge maps in a crop, at up to ``FINE_PX`` and then at full
resolution. Tiled copies: the peaks of the best template's correlation map near the best score.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.image.logo import Logo, Placement, render
from odnn_sep.image.logo_features import edges, logo_edges, logo_orientation, match_orientation, orientation

COARSE_PX = 320
FINE_PX = 1024
SCALE_STEP = 2 ** 0.25
MIN_TEMPLATE_PX = 8
# The coarse search of a scale runs on a finer copy when the logo's short side would be under this.
MIN_SHORT_PX = 24
# Local maxima kept per correlation map (the logo need not be any template's global maximum).
PEAKS_PER_MAP = 3
# A tiled copy is a peak of the best template's correlation map at this share of the best peak.
COPY_SHARE = 0.6


def _template(logo: Logo, scale: float, angle: float, sigma: float):
    big = int(np.ceil(np.hypot(*logo.M.shape) * scale)) + 6
    M, L, (bx, by, _, _) = render(logo, Placement(big / 2.0, big / 2.0, scale, angle), (big, big))
    on = np.nonzero(M > 0.02)
    if on[0].size == 0:
        return None, (0, 0)
    y0, y1, x0, x1 = on[0].min(), on[0].max() + 1, on[1].min(), on[1].max() + 1
    pad = int(np.ceil(2 * sigma)) + 1
    y0, x0 = max(0, y0 - pad), max(0, x0 - pad)
    y1, x1 = min(M.shape[0], y1 + pad), min(M.shape[1], x1 + pad)
    re, im = logo_orientation(M, L, sigma)
    T = (np.ascontiguousarray(re[y0:y1, x0:x1]), np.ascontiguousarray(im[y0:y1, x0:x1]))
    # the template's centre (the logo's centre, at big / 2 on the canvas) relative to its top-left corner
    return T, (big / 2.0 - bx - x0, big / 2.0 - by - y0)


def rank_z(v, R, T) -> float:
    """The peak over its map's spread: fair to small templates, which correlate highly by chance.

    Parameters
    ----------
    v : float
        The peak's correlation.
    R : np.ndarray
        The correlation map.
    T : tuple of np.ndarray
        The template (unused; the signature is shared with :func:`rank_neff`).

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_search import rank_z
    >>> R = np.zeros((10, 10)); R[5, 5] = 1.0
    >>> round(rank_z(1.0, R, None), 2)
    9.95
    """
    return (v - float(R.mean())) / (float(R.std()) + 1e-9)


def rank_neff(v, R, T) -> float:
    """The peak times the square root of the template's effective number of edge pixels: the z-score
    of a correlation under random orientations; fair to large templates, whose maps are smooth.

    Parameters
    ----------
    v : float
        The peak's correlation.
    R : np.ndarray
        The correlation map (unused; the signature is shared with :func:`rank_z`).
    T : tuple of np.ndarray
        (re, im) field of the template.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_search import rank_neff
    >>> T = (np.ones((4, 4)), np.zeros((4, 4)))      # 16 equal edge pixels
    >>> rank_neff(0.5, None, T)
    2.0
    """
    e = np.hypot(T[0], T[1]).ravel()
    return v * float(np.sqrt(e.sum() ** 2 / max(float(e @ e), 1e-12)))


def coarse(level, logo: Logo, f: float, scales, angle_range: float, sigma: float = 1.5, cap: float = 1.0):
    """(rank_z, rank_neff, Placement in full-resolution coordinates, level) of the best position per
    (scale, angle) of a grid. ``level(g)`` gives the photo reduced to ``g`` times full size; the search runs
    at ``f`` unless the logo's short side would be under ``MIN_SHORT_PX`` there, then at 2f, 4f, ...
    up to ``cap`` (a small logo's strokes vanish on the coarse copy). The two ranks favour small
    and large templates respectively; candidates are taken from both.

    Parameters
    ----------
    level : callable
        ``level(g)``: the photo (h, w[, C]) reduced to ``g`` times full size.
    logo : Logo
        The prepared logo.
    f : float
        Level of the coarse search.
    scales : list of float
        Scales of the grid.
    angle_range : float
        Largest rotation, degrees either way (0: upright only).
    sigma : float, default 1.5
        Gaussian blur in px.
    cap : float, default 1.0
        Finest level a small logo may use.

    Returns
    -------
    list of tuple
        (rank_z, rank_neff, Placement, level) per peak.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_search import coarse
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> c = coarse(lambda g: photo, logo, 1.0, [1.0], 0.0)
    >>> best = max(c, key=lambda t: t[0])[2]
    >>> len(c), best.cx, best.cy, best.scale
    (3, 39.5, 29.5, 1.0)
    """

    fields: dict = {}
    out = []
    r_logo = 0.5 * np.hypot(*logo.M.shape)
    for s in scales:
        fl = level_for(s, logo, f, cap)
        if fl not in fields:
            fields[fl] = orientation(level(fl), sigma)
        E = fields[fl]
        h, w = E[0].shape
        sf = s * fl
        r = r_logo * sf
        if 2 * r < MIN_TEMPLATE_PX:
            continue
        step = float(np.clip(np.rad2deg(3.0 / max(r, 1.0)), 3.0, 10.0))
        n = int(np.ceil(angle_range / step))
        for a in (np.linspace(-angle_range, angle_range, 2 * n + 1) if angle_range > 0 else [0.0]):
            T, (tx, ty) = _template(logo, sf, float(a), sigma)
            if T is None or T[0].shape[0] >= h or T[0].shape[1] >= w or not np.any(T[0]):
                continue
            R = match_orientation(E, T)
            for v, px, py in _peaks(R, PEAKS_PER_MAP, max(3, int(0.5 * min(T[0].shape)))):
                out.append((rank_z(v, R, T), rank_neff(v, R, T),
                            Placement((px + tx) / fl, (py + ty) / fl, float(s), float(a), float(v)), fl))
    return out


def _peaks(R: np.ndarray, n: int, sep: int):
    """The ``n`` highest local maxima of ``R`` at least ``sep`` px apart, as (value, x, y)."""
    import cv2

    R = R.copy()
    out = []
    for _ in range(n):
        _, v, _, (px, py) = cv2.minMaxLoc(R)
        if not np.isfinite(v) or v <= 0:
            break
        out.append((float(v), px, py))
        R[max(0, py - sep):py + sep + 1, max(0, px - sep):px + sep + 1] = -np.inf
    return out


def refine(grey: np.ndarray, logo: Logo, p: Placement, g: float, sigma: float, steps, maxiter: int = 200
           ) -> Placement:
    """Nelder-Mead on (x, y, log scale, angle) maximising the edge correlation in a crop of ``grey``
    (the photo at ``g`` times full size); returns the placement in full-resolution coordinates.

    Parameters
    ----------
    grey : np.ndarray
        (H, W[, C]) photo at ``g`` times full size.
    logo : Logo
        The prepared logo.
    p : Placement
        Starting placement, full-resolution coordinates.
    g : float
        Scale of ``grey`` relative to full size.
    sigma : float
        Gaussian blur in px.
    steps : sequence of float
        Initial simplex steps of (x, y, log scale, angle).
    maxiter : int, default 200
        Most Nelder-Mead iterations.

    Returns
    -------
    Placement
        The refined placement; ``score`` is its edge correlation.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_search import refine
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> q = refine(photo, logo, Placement(41, 31, 1.0, 0.0), 1.0, 1.5, [1, 1, 0.05, 2])
    >>> round(q.cx), round(q.cy), round(q.scale, 1), round(q.score, 2)
    (40, 30, 1.0, 0.99)
    """
    from scipy.optimize import minimize

    H, W = grey.shape[:2]
    half = 0.5 * np.hypot(*logo.M.shape) * p.scale * g * 1.15 + 6
    x0, y0 = int(max(0, p.cx * g - half)), int(max(0, p.cy * g - half))
    x1, y1 = int(min(W, p.cx * g + half + 1)), int(min(H, p.cy * g + half + 1))
    E = edges(grey[y0:y1, x0:x1], sigma)

    def ncc(v):
        q = Placement(v[0], v[1], float(np.exp(v[2])), v[3])
        M, L, (a0, b0, a1, b1) = render(logo, q, E.shape)
        if M.size == 0 or M.max() < 0.1:
            return 1.0
        T = logo_edges(M, L, sigma).ravel()
        e = E[b0:b1, a0:a1].ravel()
        T, e = T - T.mean(), e - e.mean()
        return -float(T @ e / (np.linalg.norm(T) * np.linalg.norm(e) + 1e-12))

    v0 = np.array([p.cx * g - x0, p.cy * g - y0, np.log(p.scale * g), p.angle])
    simplex = [v0] + [v0 + np.eye(4)[i] * steps[i] for i in range(4)]
    res = minimize(ncc, v0, method="Nelder-Mead",
                   options={"initial_simplex": np.array(simplex), "xatol": 0.02, "fatol": 1e-5, "maxiter": maxiter})
    v = res.x
    return Placement((v[0] + x0) / g, (v[1] + y0) / g, float(np.exp(v[2]) / g), float(v[3]), -float(res.fun))


def level_for(scale: float, logo: Logo, f: float, cap: float = 1.0) -> float:
    """The pyramid level (times full size) the coarse search uses for a scale: ``f``, or finer (up to
    ``cap``) for a logo whose short side would be under ``MIN_SHORT_PX`` there.

    Parameters
    ----------
    scale : float
        Scale of the logo.
    logo : Logo
        The prepared logo.
    f : float
        Level of the coarse search.
    cap : float, default 1.0
        Finest level allowed.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Logo
    >>> from odnn_sep.image.logo_search import level_for
    >>> logo = Logo(np.ones((40, 40)), np.ones((40, 40, 1)), False, False)
    >>> level_for(1.0, logo, 0.25), level_for(0.25, logo, 0.25), level_for(4.0, logo, 0.25)
    (1.0, 1.0, 0.25)
    """
    fl, short = f, min(logo.M.shape)
    while scale * fl * short < MIN_SHORT_PX and fl < cap:
        fl = min(cap, 2 * fl)
    return fl


def copies(level, logo: Logo, best: Placement, f: float, max_copies: int, sigma: float = 1.5, cap: float = 1.0):
    """Other copies of the best template (same scale and angle): peaks of its correlation map at its
    pyramid level at ``COPY_SHARE`` of the best peak, at least half a logo apart; full-resolution
    centres.

    Parameters
    ----------
    level : callable
        ``level(g)``: the photo reduced to ``g`` times full size.
    logo : Logo
        The prepared logo.
    best : Placement
        The best copy found.
    f : float
        Level of the coarse search.
    max_copies : int
        Most copies returned.
    sigma : float, default 1.5
        Gaussian blur in px.
    cap : float, default 1.0
        Finest level a small logo may use.

    Returns
    -------
    list of Placement
        The copies, strongest first (``best`` among them).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_search import copies
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(24, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); tile = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> photo[b[1]:b[3], b[0]:b[2]] = tile; photo[b[1]:b[3], b[0] + 48:b[2] + 48] = tile
    >>> sorted(round(c.cx) for c in copies(lambda g: photo, logo, Placement(24, 30, 1.0, 0.0), 1.0, 4))
    [24, 72]
    """
    import cv2

    f = level_for(best.scale, logo, f, cap)
    T, (tx, ty) = _template(logo, best.scale * f, best.angle, sigma)
    E = orientation(level(f), sigma)
    if T is None or T[0].shape[0] >= E[0].shape[0] or T[0].shape[1] >= E[0].shape[1]:
        return []
    T0 = T[0]
    R = match_orientation(E, T)
    top = float(R.max())
    k = max(3, int(0.5 * min(T0.shape)) | 1)
    peaks = (R >= cv2.dilate(R, np.ones((k, k), np.uint8))) & (R >= COPY_SHARE * top)
    py, px = np.nonzero(peaks)
    order = np.argsort(-R[py, px])[: 4 * max_copies]
    out: list[Placement] = []
    for i in order:
        c = Placement((px[i] + tx) / f, (py[i] + ty) / f, best.scale, best.angle, float(R[py[i], px[i]]))
        if all(np.hypot(c.cx - o.cx, c.cy - o.cy) > 0.5 * min(T0.shape) / f for o in out):
            out.append(c)
        if len(out) >= max_copies:
            break
    return out


def scale_grid(logo: Logo, shape, lo: float = 0.25, hi: float = 4.0) -> list[float]:
    """Scales from ``lo`` to ``hi`` (geometric, ``SCALE_STEP``) at which the logo fits in the photo.

    Parameters
    ----------
    logo : Logo
        The prepared logo.
    shape : tuple of int
        (H, W) of the photo.
    lo, hi : float
        Smallest and largest scale.

    Returns
    -------
    list of float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Logo
    >>> from odnn_sep.image.logo_search import scale_grid
    >>> logo = Logo(np.ones((16, 16)), np.ones((16, 16, 1)), False, False)
    >>> g = scale_grid(logo, (64, 96))
    >>> len(g), round(g[0], 2), round(g[-1], 2)
    (17, 0.25, 4.0)
    """
    H, W = shape
    h, w = logo.M.shape
    n = int(np.floor(np.log(hi / lo) / np.log(SCALE_STEP) + 1e-9)) + 1
    s = lo * SCALE_STEP ** np.arange(n)
    return [float(v) for v in s if v * max(h, w) <= max(H, W) and v * min(h, w) <= min(H, W)]
