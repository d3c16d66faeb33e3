"""Opacity and colour of a blended mark with known coverage M, and the blend's inversion.

Model, per channel c:  ``y_c = (1 - a M) I_c + a M col_c``.

The photo I is the disturbance. It is confined to a class that cannot imitate the mark: inside
each small patch that straddles a glyph edge, I is a low-order 2-D polynomial (a ``Subspace`` of
smooth functions). Glyph coverage jumps from 0 to 1 across an edge one or two pixels wide, which no
low-order polynomial can follow, so the mark is identified. With ``b_c = a col_c`` the model is

    y_c ~= P_c,patch(x) (1 - a M) + b_c M,

linear in the polynomial coefficients and in ``b`` for a fixed ``a``. ``a`` is shared by all
channels and patches and ``b`` by all patches; the polynomial of every patch is projected out
exactly (variable projection), which leaves a one-dimensional profile over ``a``. ``a`` is chosen
by the likelihood of the *restored* photo (``profile.PhotoProfile``: texture the polynomials miss
has the same statistics under the mark and beside it only after the blend is undone). What pins ``a``
down is that the photo's own contrast under the mark is scaled by ``1 - a`` while ``b`` is the same
everywhere; on a perfectly flat background only the combination ``(1 - a) I + b`` is seen, and the
returned standard error says so. Patches whose residual is large (photo texture) are down-weighted
(IRLS, Cauchy weights).
"""
from __future__ import annotations

import dataclasses
import logging

import numpy as np

from odnn_sep.image.profile import DataProfile, PhotoProfile, design, plane_rss

log = logging.getLogger(__name__)


@dataclasses.dataclass(frozen=True)
class BlendFit:
    """Fitted blend of a mark of known coverage: opacity ``alpha``, ``beta = alpha * colour`` (C,),
    the standard error of ``alpha``, the weighted residual ``rss``, the number and side of the patches
    used, and ``explained``, the share of the patches' photo-only residual the mark explains.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import BlendFit
    >>> fit = BlendFit(0.5, np.array([0.5, 0.25, 0.0]), 0.01, 0.0, 10, 8)
    >>> fit.color.tolist()
    [1.0, 0.5, 0.0]
    """

    alpha: float
    beta: np.ndarray          # (C,) = alpha * colour
    alpha_stderr: float
    rss: float
    n_patches: int
    patch: int
    explained: float = float("nan")   # 1 - RSS(mark) / RSS(photo only) over the edge patches

    @property
    def color(self) -> np.ndarray:
        return np.clip(self.beta / max(self.alpha, 1e-9), 0.0, 1.0)


def stroke_width(M: np.ndarray) -> float:
    """Typical glyph stroke width (px) of a coverage map: twice the median inner distance on the ridge.

    Parameters
    ----------
    M : np.ndarray
        (h, w) coverage in [0, 1].

    Returns
    -------
    float
        Stroke width in px, at least 1 (2 for an empty coverage).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import stroke_width
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> round(stroke_width(M), 2), stroke_width(np.zeros((4, 4)))
    (3.82, 2.0)
    """
    import cv2

    b = M > 0.5
    rows, cols = np.flatnonzero(b.any(axis=1)), np.flatnonzero(b.any(axis=0))
    if not rows.size:
        return 2.0
    # The distances inside the strokes' box grown by 2 px (a ring of uncovered pixels, or the image's
    # edge) equal those of the whole map: a path to an uncovered pixel further out crosses the ring.
    # A 12-megapixel map costs a tenth of a second less.
    b = b[max(0, rows[0] - 2):rows[-1] + 3, max(0, cols[0] - 2):cols[-1] + 3].astype(np.uint8)
    d = cv2.distanceTransform(b, cv2.DIST_L2, 3)
    ridge = d[(d > 0) & (d >= cv2.dilate(d, np.ones((3, 3), np.uint8)) - 1e-6)]
    if not ridge.size:
        return 2.0
    if float(d.max()) > sum(M.shape):
        # a coverage without any uncovered pixel has no distance to one (OpenCV returns a huge
        # number): no stroke is wider than the crop
        return float(max(M.shape))
    return float(max(1.0, 2.0 * np.median(ridge)))


def patch_grid(M: np.ndarray, size: int, max_patches: int, rng) -> tuple[np.ndarray, np.ndarray, int]:
    """Top-left corners of overlapping square patches (stride size/2) that straddle a glyph edge.

    Parameters
    ----------
    M : np.ndarray
        (h, w) coverage in [0, 1].
    size : int
        Patch side in px (clipped to [3, min(h, w)]).
    max_patches : int
        Most patches kept (a random subset beyond).
    rng : np.random.Generator
        Draws the subset.

    Returns
    -------
    py, px : np.ndarray
        Row and column of each patch's top-left corner.
    size : int
        The patch side used.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import patch_grid
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> py, px, size = patch_grid(M, 8, 1000, np.random.default_rng(0))
    >>> len(py), size, py[:3].tolist(), px[:3].tolist()
    (27, 8, [4, 4, 4], [4, 8, 12])
    """
    import cv2

    h, w = M.shape
    size = int(max(3, min(size, h, w)))
    step = max(1, size // 2)
    ys = np.arange(0, h - size + 1, step)
    xs = np.arange(0, w - size + 1, step)
    # window max - min at every top-left corner (morphology anchored at the corner), then the grid
    k = np.ones((size, size), np.uint8)
    Mf = np.ascontiguousarray(M, dtype=np.float32)
    mx = cv2.dilate(Mf, k, anchor=(0, 0), borderType=cv2.BORDER_REPLICATE)
    mn = cv2.erode(Mf, k, anchor=(0, 0), borderType=cv2.BORDER_REPLICATE)
    ptp = (mx - mn)[np.ix_(ys, xs)]
    iy, ix = np.nonzero(ptp > 0.4)
    if iy.size > max_patches:
        keep = np.sort(rng.choice(iy.size, max_patches, replace=False))
        iy, ix = iy[keep], ix[keep]
    return ys[iy], xs[ix], size


def take_patches(a: np.ndarray, py: np.ndarray, px: np.ndarray, size: int) -> np.ndarray:
    """(n, size*size, C) stack of patches of a (h, w[, C]) array at the given corners.

    Parameters
    ----------
    a : np.ndarray
        (h, w) or (h, w, C) array.
    py, px : np.ndarray
        (n,) rows and columns of the patches' top-left corners.
    size : int
        Patch side in px.

    Returns
    -------
    np.ndarray
        float64 (n, size * size, C), pixels in row-major order.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import take_patches
    >>> a = np.arange(32 * 48, dtype=float).reshape(32, 48)
    >>> P = take_patches(a, np.array([0, 4]), np.array([0, 10]), 2)
    >>> P.shape, P[1, :, 0].tolist()
    ((2, 4, 1), [202.0, 203.0, 250.0, 251.0])
    """
    if a.ndim == 2:
        a = a[:, :, None]
    py, px = np.asarray(py), np.asarray(px)
    h, w = a.shape[:2]
    if isinstance(a, np.ndarray) and py.size and py.dtype.kind in "iu" and px.dtype.kind in "iu" \
            and py.min() >= 0 and px.min() >= 0 and py.max() + size <= h and px.max() + size <= w:
        # one gather of whole pixel rows by flat index: the same values as the 2-D fancy index below,
        # about four times faster (the fits and registrations take thousands of patch sets)
        flat = a.reshape(h * w, a.shape[2]) if a.flags["C_CONTIGUOUS"] else np.ascontiguousarray(a).reshape(h * w, -1)
        offs = (np.arange(size)[:, None] * w + np.arange(size)[None, :]).ravel()
        start = py.astype(np.intp) * w + px.astype(np.intp)  # flat index of each corner, no overflow
        return np.ascontiguousarray(flat.take(start[:, None] + offs[None], axis=0), dtype=np.float64)
    oy, ox = np.mgrid[0:size, 0:size]
    rows = py[:, None] + oy.ravel()[None]
    cols = px[:, None] + ox.ravel()[None]
    return np.ascontiguousarray(a[rows, cols], dtype=np.float64)


def drop_clipped(Yp: np.ndarray, *arrays: np.ndarray) -> tuple[np.ndarray, ...]:
    """Leave out the patches of ``Yp`` (n, size*size, C) holding clipped pixels (0 or full scale), which
    break the blend model, with the matching rows of ``arrays``; all are kept unless enough remain.

    Parameters
    ----------
    Yp : np.ndarray
        (n, size * size, C) patches in [0, 1].
    *arrays : np.ndarray
        Arrays with one row per patch, filtered alike.

    Returns
    -------
    tuple of np.ndarray
        ``Yp`` and ``arrays`` without the clipped patches (unchanged when fewer than
        max(8, 20 %) would remain).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import drop_clipped
    >>> Yp = np.full((20, 64, 1), 0.5); Yp[0, 0] = 1.0
    >>> Y, idx = drop_clipped(Yp, np.arange(20))
    >>> Y.shape, int(idx[0])
    ((19, 64, 1), 1)
    """
    ok = ~((Yp <= 0.5 / 65535) | (Yp >= 1 - 0.5 / 65535)).any(axis=(1, 2))
    if ok.sum() >= max(8, 0.2 * len(ok)):
        return (Yp[ok], *(a[ok] for a in arrays))
    return (Yp, *arrays)


def _patches(y, M, size, max_patches, rng):
    py, px, size = patch_grid(M, size, max_patches, rng)
    return take_patches(y, py, px, size), take_patches(M, py, px, size)[:, :, 0]


def fit_blend(y: np.ndarray, M: np.ndarray, *, patch: int | None = None, degree: int = 1,
              max_patches: int = 800, alpha_max: float = 1.0, irls: int = 3, xatol: float = 1e-6,
              random_state=0) -> BlendFit:
    """Estimate opacity ``alpha`` and ``beta = alpha * colour`` of a mark of known coverage ``M``.

    Why long (9 parameters): the data, then keyword options of the fit with defaults for the usual case.

    Parameters
    ----------
    y : (h, w, C) float array in [0, 1], the watermarked image (crop around the mark)
    M : (h, w) coverage in [0, 1]
    patch : patch side in px (default 8)
    degree : polynomial degree of the photo inside a patch (0, 1 or 2)
    xatol : tolerance on ``alpha`` (a screening fit that only needs ``explained`` can be coarse)

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:40, 0:60] / 60.0
    >>> I = np.stack([0.2 + 0.5 * xx, 0.3 + 0.4 * yy, 0.5 + 0.2 * xx * yy], -1)
    >>> M = np.zeros((40, 60)); M[10:30, 20:24] = 1; M[10:14, 10:50] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None] * np.array([1.0, 1.0, 0.0])
    >>> fit = fit_blend(y, M)
    >>> round(fit.alpha, 4), np.round(fit.color, 4).tolist()
    (0.4, [1.0, 1.0, 0.0])
    """
    from scipy.optimize import minimize_scalar

    y = np.asarray(y, dtype=np.float64)
    if y.ndim == 2:
        y = y[:, :, None]
    M = np.asarray(M, dtype=np.float64)
    if patch is None:
        # Small patches: only the glyph edges carry information, and the smaller the patch the
        # better a plane follows real photo texture (measured: 8 px beats stroke-scaled patches on
        # both synthetic and real photos)
        patch = 8
    rng = np.random.default_rng(random_state)
    py, px, patch_px = patch_grid(M, patch, max_patches, rng)
    Yp, Mp = take_patches(y, py, px, patch_px), take_patches(M, py, px, patch_px)[:, :, 0]
    Yp, Mp, py, px = drop_clipped(Yp, Mp, py, px)
    if len(Mp) == 0:
        from odnn_sep.errors import NotIdentifiableError

        raise NotIdentifiableError("the mark has no sharp edges inside the image; opacity cannot be estimated")
    Phi = design(int(np.sqrt(Mp.shape[1])), degree)
    prof = PhotoProfile(Yp, Mp, Phi)
    a_hi = min(alpha_max, 0.995)  # the photo-domain likelihood needs 1 - a M > 0
    alpha = float(minimise_profile(prof, a_hi, 17, xatol).x)
    for _ in range(irls):
        _, rss_p, _ = prof.parts(alpha)
        s = np.median(rss_p) + 1e-30
        prof.w = 1.0 / (1.0 + (rss_p / (2.0 * s)) ** 2)
        alpha = float(minimize_scalar(prof, bounds=(max(1e-4, alpha - 0.08), min(a_hi, alpha + 0.08)),
                                      method="bounded", options={"xatol": xatol}).x)
    return _summarise(prof, alpha, a_hi, patch)


def _summarise(prof, alpha: float, a_hi: float, patch: int) -> BlendFit:
    """The ``BlendFit`` of the photo-domain profile ``prof`` at its optimum ``alpha``."""
    beta, rss_p, _ = prof.parts(alpha)
    rss = float(np.sum(prof.w * rss_p))
    # standard error from the curvature of the negative log-likelihood
    h = 1e-3
    curv = (prof(min(alpha + h, a_hi)) - 2 * prof(alpha) + prof(max(alpha - h, 1e-4))) / h**2
    se = float(1.0 / np.sqrt(curv)) if curv > 0 else float("inf")
    # share of the patches' photo-only residual (image domain) that the mark explains: ~0 for a
    # wrong template; it ranks the hypotheses of the search (``detect`` decides on detection)
    rss0_p = plane_rss(prof.Yp, prof.Q)
    rss1_p = DataProfile(prof.Yp, prof.Mp, prof.Phi).parts(alpha)[1]
    explained = max(0.0, 1.0 - float(np.sum(rss1_p)) / max(float(np.sum(rss0_p)), 1e-300))
    return BlendFit(alpha=alpha, beta=np.asarray(beta), alpha_stderr=se, rss=rss, n_patches=len(prof.Mp),
                    patch=patch, explained=explained)


def minimise_profile(prof, a_hi: float, n_grid: int, xatol: float):
    """Minimum of a one-dimensional opacity profile on (0, ``a_hi``]: the best of ``n_grid - 1``
    grid points, then a bounded search between its neighbours (the profile can have several local
    minima, a bounded search alone may stop in the wrong one). Returns scipy's OptimizeResult.

    Parameters
    ----------
    prof : callable
        The profile, a float function of the opacity.
    a_hi : float
        Largest opacity searched.
    n_grid : int
        Grid points on [0, ``a_hi``] (0 itself is left out).
    xatol : float
        Tolerance of the bounded search.

    Returns
    -------
    scipy.optimize.OptimizeResult
        ``x`` the minimising opacity, ``fun`` the profile there.

    Examples
    --------
    >>> from odnn_sep.image.estimate import minimise_profile
    >>> r = minimise_profile(lambda a: (a - 0.3) ** 2, 0.995, 17, 1e-6)
    >>> round(float(r.x), 4)
    0.3
    """
    from scipy.optimize import minimize_scalar

    grid = np.linspace(0.0, a_hi, n_grid)[1:]
    k = int(np.argmin([prof(a) for a in grid]))
    lo, hi = (grid[k - 1] if k else 1e-4), grid[min(k + 1, len(grid) - 1)]
    return minimize_scalar(prof, bounds=(lo, hi), method="bounded", options={"xatol": xatol})


def inpaint_telea(y: np.ndarray, hole: np.ndarray, radius: int) -> np.ndarray:
    """``y`` (h, w, C) in [0, 1] with the ``hole`` pixels filled from around them (OpenCV TELEA).

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float image in [0, 1].
    hole : np.ndarray
        (h, w) bool, the pixels to fill.
    radius : int
        Inpainting radius in px.

    Returns
    -------
    np.ndarray
        The filled image, (h, w, C) float (16-bit precision).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import inpaint_telea
    >>> y = np.full((32, 48, 3), 0.5); hole = np.zeros((32, 48), bool); hole[10:14, 10:14] = True
    >>> y[hole] = 0.0
    >>> round(float(inpaint_telea(y, hole, 3)[12, 12, 0]), 3)
    0.5
    """
    import cv2

    m8 = hole.astype(np.uint8) * 255
    out = np.empty_like(y)
    for c in range(y.shape[2]):
        # 16-bit, not float: OpenCV's float inpainting assumes a 0-255 range
        out[:, :, c] = cv2.inpaint(np.round(np.clip(y[:, :, c], 0, 1) * 65535).astype(np.uint16), m8, radius,
                                   cv2.INPAINT_TELEA) / 65535.0
    return out


def invert(y: np.ndarray, M: np.ndarray, alpha: float, color: np.ndarray, *, levels: int = 255,
           lost_threshold: float = 0.1, inpaint: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Undo the blend: ``I = (y - a M col) / (1 - a M)``; inpaint only pixels whose data are gone.

    ``y`` is in [0, 1] (``levels`` quantisation steps, 255 for 8-bit). Lost pixels: ``1 - a M <
    lost_threshold`` (nearly opaque: quantisation noise would be amplified more than 10x) or a
    channel clipped at 0 or 1 where the mark is. Returns the restored float image (same channels as
    ``y``) and the boolean lost mask.

    Parameters
    ----------
    y : np.ndarray
        (h, w) or (h, w, C) watermarked image in [0, 1].
    M : np.ndarray
        (h, w) coverage of the mark.
    alpha : float
        Opacity.
    color : np.ndarray
        (C,) mark colour in [0, 1].
    levels : int, default 255
        Quantisation steps of the data.
    lost_threshold : float, default 0.1
        Pixels with ``1 - a M`` below it are lost.
    inpaint : bool, default True
        Inpaint the lost pixels (else leave them as inverted).

    Returns
    -------
    out : np.ndarray
        Restored image, shaped as ``y``.
    lost : np.ndarray
        (h, w) bool, the pixels whose data were gone.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.estimate import invert
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1
    >>> I = np.full((32, 48, 3), 0.4)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> out, lost = invert(y, M, 0.5, np.ones(3))
    >>> bool(np.allclose(out, I)), int(lost.sum())
    (True, 0)
    >>> int(invert(y, M, 0.95, np.ones(3))[1].sum())
    96
    """
    y = np.asarray(y, dtype=np.float64)
    squeeze = y.ndim == 2
    if squeeze:
        y = y[:, :, None]
    M = np.asarray(M, dtype=np.float64)
    col = np.asarray(color, dtype=np.float64).reshape(1, 1, -1)
    aM = (alpha * M)[:, :, None]
    den = 1.0 - aM
    out = y.copy()
    on = M > 0
    out[on] = ((y - aM * col) / np.maximum(den, lost_threshold))[on]
    out = np.clip(out, 0.0, 1.0)
    half = 0.5 / levels
    clipped = ((y <= half) | (y >= 1.0 - half)).any(axis=2) & (M > 0.05)
    lost = ((den[:, :, 0] < lost_threshold) & on) | clipped
    if inpaint and lost.any():
        out[lost] = inpaint_telea(out, lost, 3)[lost]
    return (out[:, :, 0] if squeeze else out), lost
