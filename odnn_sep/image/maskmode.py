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


def _inpaint(y: np.ndarray, hole: np.ndarray) -> np.ndarray:
    import cv2

    m8 = hole.astype(np.uint8) * 255
    out = np.empty_like(y)
    for c in range(y.shape[2]):
        out[:, :, c] = cv2.inpaint(y[:, :, c].astype(np.float32), m8, 5, cv2.INPAINT_TELEA)
    return out


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
        B = _inpaint(y, D)
        d = y - B
        if c is None:
            c = np.full(y.shape[2], 1.0 if d[D].mean() > 0 else 0.0)
        for _ in range(8):
            v = c[None, None, :] - B
            m = np.clip(np.sum(d * v, axis=2) / np.maximum(np.sum(v * v, axis=2), 1e-6), 0.0, 1.0)
            m[~D] = 0.0
            sel = m > 0.05
            if sel.sum() < 3:
                break
            mm = m[sel]
            c = np.clip(np.sum(mm[:, None] * (d[sel] + mm[:, None] * B[sel]), axis=0) / np.sum(mm * mm), 0, 1)
        noise = 1.4826 * np.median(np.abs(m[D] - np.median(m[D]))) + 1e-3
        keep = (m > max(0.03, 3 * noise)).astype(np.uint8)
        keep = cv2.dilate(keep, np.ones((3, 3), np.uint8)).astype(bool) & R
        if keep.sum() < 3:
            break
        D = keep
    m[~D] = 0.0
    return m, np.asarray(c)
