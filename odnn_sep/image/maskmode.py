"""``--mask`` mode: the user marks the area; the mark's exact shape, opacity and colour are estimated.

Inside the region, a blended pixel moves from the photo ``B`` straight toward the mark colour:
``y - B = m (c - B)`` with ``m = alpha M`` in [0, 1]. The photo ``B`` under the candidate mark
pixels is interpolated from the pixels around them (OpenCV TELEA inpainting of the candidate set
only), ``c`` and ``m`` are then found by alternating least squares on that rank-one model, the
candidate set is shrunk to where ``m`` is clearly non-zero, and the loop repeats. Finally the blend
fit of ``estimate`` (locally smooth photo) gives ``alpha`` and the colour from the recovered shape.
"""
from __future__ import annotations

import logging

import numpy as np

from odnn_sep.core.linalg import solve_batched
from odnn_sep.errors import InputError
from odnn_sep.image.estimate import inpaint_telea

log = logging.getLogger(__name__)


def _colour(d: np.ndarray, B: np.ndarray, D: np.ndarray, prev) -> np.ndarray:
    """The mark colour as the least-squares meeting point of the lines from photo B through y.

    Every blended pixel lies on the segment from its photo colour to the mark colour, so with the
    deviation ``d = y - B`` the colour is where those lines (weighted by |d|^2) meet. A grey image
    has no direction to use: the colour is then white or black, from the sign of the deviation.
    """
    dd = d[D]
    n2 = np.sum(dd * dd, axis=1)
    sign = 1.0 if np.sum(dd) > 0 else 0.0
    if d.shape[2] == 1 or n2.size < 3:
        return np.full(d.shape[2], sign) if prev is None else prev
    sel = n2 > np.quantile(n2, 0.5)
    u = dd[sel] / np.sqrt(n2[sel])[:, None]
    w = n2[sel]
    Bs = B[D][sel]
    eye = np.eye(d.shape[2])
    P = eye[None] - u[:, :, None] * u[:, None, :]
    A = np.einsum("i,ijk->jk", w, P)
    b = np.einsum("i,ijk,ik->j", w, P, Bs)
    try:
        c = solve_batched(A + 1e-9 * eye, b)
    except np.linalg.LinAlgError:                                   # non-finite data
        c = np.full(d.shape[2], sign)
    return np.clip(c, 0.0, 1.0)


def estimate_shape(y: np.ndarray, region: np.ndarray, *, iterations: int = 3, details: dict | None = None
                   ) -> tuple[np.ndarray, np.ndarray]:
    """Coverage ``m = alpha M`` (h, w) and colour (C,) of a mark inside ``region`` of crop ``y``.

    ``details`` (a dict, filled in): ``background`` (the interpolated photo B), ``explained`` (share of
    the deviation ``y - B`` inside the region that the one-colour blend explains), ``residual_sd``.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    region : np.ndarray
        (h, w) bool, where the mark is.
    iterations : int, default 3
        Rounds of photo interpolation and shape estimation.
    details : dict, optional
        Filled in with the fields above.

    Returns
    -------
    m : np.ndarray
        (h, w) coverage times opacity, 0 outside the region.
    color : np.ndarray
        (C,) mark colour.

    Raises
    ------
    InputError
        When ``region`` is empty.

    Examples
    --------
    >>> from odnn_sep.image.maskmode import estimate_shape
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.3 * xx, 0.3 + 0.2 * yy, 0.5 + 0.1 * xx], -1)
    >>> M = np.zeros((32, 48)); M[10:22, 12:16] = 1; M[10:14, 12:36] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None]
    >>> region = np.zeros((32, 48), bool); region[6:26, 8:40] = True
    >>> m, color = estimate_shape(y, region)
    >>> round(float(m.max()), 2), bool(color.min() > 0.9)
    (0.46, True)
    """
    import cv2

    R = region.astype(bool)
    if not R.any():
        raise InputError("mask has no nonzero pixels inside the image; mark the watermark's area")
    D = R.copy()
    c = None
    m = np.zeros(R.shape)
    for _ in range(iterations):
        B = inpaint_telea(y, D, 5)
        d = y - B
        c = _colour(d, B, D, c)
        v = c[None, None, :] - B
        m = np.clip(np.sum(d * v, axis=2) / np.maximum(np.sum(v * v, axis=2), 1e-6), 0.0, 1.0)
        m[~D] = 0.0
        noise = 1.4826 * np.median(np.abs(m[D] - np.median(m[D]))) + 1e-3
        keep = (m > max(0.03, 3 * noise)).astype(np.uint8)
        keep = cv2.dilate(keep, np.ones((3, 3), np.uint8)).astype(bool) & R
        if details is not None:
            r = d - m[:, :, None] * v
            details["background"] = B
            details["explained"] = 1.0 - float(np.sum(r[R] ** 2)) / max(float(np.sum(d[R] ** 2)), 1e-12)
            details["residual_sd"] = 1.4826 * float(np.median(np.abs(r[R]))) + 1.0 / 255
        if keep.sum() < 3:
            break
        D = keep
    m[~D] = 0.0
    return m, np.asarray(c)


# The blend is inverted only when the one-colour blend explains at least this share of the deviation
# from the interpolated photo inside the mask and the fitted opacity is below OPAQUE_ALPHA; otherwise
# the mark is opaque (or not a one-colour blend) and the photo under it is gone: it is inpainted.
MIN_BLEND_EXPLAINED = 0.5
OPAQUE_ALPHA = 0.9
# Mask mode: the blend fit replaces the shape estimate's opacity and colour only when the mark
# explains at least this share of the edge patches' photo-only residual.
MASK_MIN_EXPLAINED = 0.28
# Soft masks: prior standard deviation of M (a prior value p says "M is p, give or take this").
PRIOR_SD = 0.15


def mask_mode(y, prepared, random_state=0):
    """(M (H, W) float32, alpha, colour, report fields) of the mark inside a prepared mask.

    ``y``: (H, W, C) float array or ``io.FloatView``; ``prepared``: ``maskprep.PreparedMask``. An
    opaque mark (or one the one-colour blend does not explain) comes back as ``M = 1`` over the
    region with ``alpha = 1``: the blend inversion then inpaints all of it, and the report says so.

    Parameters
    ----------
    y : np.ndarray or FloatView
        (H, W, C) float image in [0, 1].
    prepared : PreparedMask
        The user's mask (:func:`odnn_sep.image.maskprep.prepare_mask`).
    random_state : int or Generator, default 0
        Seed of the blend fit.

    Returns
    -------
    M : np.ndarray
        (H, W) float32 coverage.
    alpha : float
        Opacity.
    color : np.ndarray
        (C,) mark colour.
    info : dict
        Report fields (``bbox``, ``mask_soft``, ``blend_explained``, ...).

    Examples
    --------
    >>> from odnn_sep.image.maskmode import mask_mode
    >>> from odnn_sep.image.maskprep import prepare_mask
    >>> import numpy as np
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.3 * xx, 0.3 + 0.2 * yy, 0.5 + 0.1 * xx], -1)
    >>> M = np.zeros((32, 48)); M[10:22, 12:16] = 1; M[10:14, 12:36] = 1
    >>> y = (1 - 0.4 * M[..., None]) * I + 0.4 * M[..., None]
    >>> region = np.zeros((32, 48), bool); region[6:26, 8:40] = True
    >>> M_est, alpha, color, info = mask_mode(y, prepare_mask(region.astype(np.uint8) * 255, (32, 48)))
    >>> round(alpha, 1), M_est.shape, info["bbox"], info["mask_soft"]
    (0.4, (32, 48), [0, 0, 48, 32], False)
    """
    from odnn_sep.errors import NotIdentifiableError
    from odnn_sep.image.estimate import fit_blend

    H, W = y.shape[:2]
    region = prepared.region
    ys, xs = np.nonzero(region)
    pad = 8
    x0, y0 = max(0, xs.min() - pad), max(0, ys.min() - pad)
    x1, y1 = min(W, xs.max() + pad + 1), min(H, ys.max() + pad + 1)
    crop = y[y0:y1, x0:x1]
    Rc = region[y0:y1, x0:x1]
    det: dict = {}
    m, color = estimate_shape(crop, Rc, details=det)
    alpha = float(np.quantile(m[m > 0.05], 0.9)) if (m > 0.05).sum() >= 10 else float(m.max())
    try:
        fit = fit_blend(crop, np.clip(m / max(alpha, 1e-6), 0.0, 1.0), random_state=random_state)
        if 0.02 < fit.alpha <= 1.0 and fit.explained > MASK_MIN_EXPLAINED:
            alpha, color = fit.alpha, fit.color
    except NotIdentifiableError:
        pass
    Mc = np.clip(m / max(alpha, 1e-6), 0.0, 1.0)
    if prepared.soft:
        Mc = _with_prior(Mc, prepared.prior[y0:y1, x0:x1], det.get("background", crop), alpha, color,
                         det.get("residual_sd", 0.02))
    explained = float(det.get("explained", 0.0))
    info = {"bbox": [int(x0), int(y0), int(x1), int(y1)], "marks": [], "mask_soft": prepared.soft,
            "mask_inverted": prepared.inverted, "blend_explained": round(explained, 4)}
    if prepared.note:
        info["mask_note"] = prepared.note
    if alpha >= OPAQUE_ALPHA or explained < MIN_BLEND_EXPLAINED:
        why = f"opacity {alpha:.2f}" if alpha >= OPAQUE_ALPHA else f"a one-colour blend explains {explained:.0%}"
        info["opaque"] = True
        info["mask_note"] = (info.get("mask_note", "") + "; " if "mask_note" in info else "") + \
            f"mark is opaque or not a one-colour blend ({why}): the masked area is inpainted"
        log.warning(info["mask_note"].split("; ")[-1])
        Mc = Rc.astype(np.float64) if not prepared.soft else (prepared.prior[y0:y1, x0:x1] > 0.5).astype(float)
        if not Mc.any():
            Mc = Rc.astype(np.float64)
        alpha, color = 1.0, np.asarray(color)
    else:
        info["opaque"] = False
    M = np.zeros((H, W), np.float32)
    M[y0:y1, x0:x1] = Mc
    return M, float(alpha), np.asarray(color), info


def _with_prior(Mc, prior, B, alpha, color, sd):
    """Coverage combining the data with a soft mask's prior value: the shape estimate of M has the
    variance sd^2 / (alpha^2 |c - B|^2) (pixel noise over the contrast between mark colour and photo),
    the prior the variance PRIOR_SD^2; the two are averaged with their precisions."""
    v = np.asarray(color)[None, None, :] - np.asarray(B)
    w_data = alpha ** 2 * np.sum(v * v, axis=2) / sd ** 2
    w_prior = 1.0 / PRIOR_SD ** 2
    return np.clip((w_data * Mc + w_prior * prior) / (w_data + w_prior), 0.0, 1.0)
