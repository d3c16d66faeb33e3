"""``--mask`` mode: the user marks the area; the mark's exact shape, opacity and colour are estimated.

Inside the region, a blended pixel moves from the photo ``B`` straight toward the mark colour:
``y - B = m (c - B)`` with ``m = alpha M`` in [0, 1]. The photo ``B`` under the candidate mark
pixels is interpolated from the pixels around them (OpenCV TELEA inpainting of the candidate set
only), ``c`` and ``m`` are then found by alternating least squares on that rank-one model, the
candidate set is shrunk to where ``m`` is clearly non-zero, and the loop repeats. Finally the blend
fit of ``estimate`` (locally smooth photo) gives ``alpha`` and the colour from the recovered shape.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import InputError
from odnn_sep.image.estimate import inpaint_telea


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
        c = np.linalg.solve(A + 1e-9 * eye, b)
    except np.linalg.LinAlgError:
        c = np.full(d.shape[2], sign)
    return np.clip(c, 0.0, 1.0)


def estimate_shape(y: np.ndarray, region: np.ndarray, *, iterations: int = 3) -> tuple[np.ndarray, np.ndarray]:
    """Coverage ``m = alpha M`` (h, w) and colour (C,) of a mark inside ``region`` of crop ``y``."""
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
        if keep.sum() < 3:
            break
        D = keep
    m[~D] = 0.0
    return m, np.asarray(c)
