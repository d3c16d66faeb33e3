"""Rims left along the mark's contours: a mark removed with a glyph shape a pixel or two off.

A mark in a font the tool does not have is inverted with a coverage whose edges sit a pixel or two off
the true glyphs. Inside the letters the removal is right; along their edges it leaves thin rims, one
side too dark and the other too light, that draw the letters as outlines. The other measures of the
residual mark (``residual.measure``) average squared gradients over the mark's band: a few strong edges
of the photo there (a door frame, the rim of a cup) outweigh thin rims along every letter, so a
readable outline could be called removed.

Here every band pixel counts by its gradient, not its square: the gradient across the contours of the
mark's coverage minus that along them (``|g| cos 2 theta``, ``theta`` between the gradient and the
contour's normal), averaged with the contours' strength as weight. Photo detail runs every way and
averages out; rims run along the contours wherever the letters go. The result is in 8-bit grey levels
of a step (a Sobel gradient over 4): ``rim_levels`` of the output, and its share of the input's, where
the whole mark was.
"""
from __future__ import annotations

import numpy as np

# The output's rims count as the mark still visible when they keep at least this share of the input's
# edge strength across the mark's contours and at least RIM_LEVELS grey levels of it. Chosen on
# development seeds 1 and 7 of the unseen-font generator (recipes/_watermark_unseen.py: 67 outputs of
# marks found, 37 in fonts the tool never tries and 30 in the DejaVu family it tries, each also with
# the clean photo scored as the output of a perfect removal, which none reached): see BENCHMARKS.md,
# "Marks reported removed while their letters stay as outlines" (recipes/bench_watermark_rims.py).
RIM_SHARE = 0.25
RIM_LEVELS = 3.0


def rim_levels(y: np.ndarray, cov: np.ndarray) -> float:
    """Edge strength of ``y`` across the contours of ``cov`` minus that along them, weighted by the
    contours' strength, in 8-bit grey levels: about 0 for photo detail, the mark's step for a mark.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float image in [0, 1].
    cov : np.ndarray
        (h, w) coverage of the mark.

    Returns
    -------
    float
        0 when ``cov`` has no contour.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_rims import rim_levels
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = 0.4 + 0.2 * M[..., None]                     # a step of 51 grey levels along the letters
    >>> round(rim_levels(y, M)), round(rim_levels(np.full((32, 48, 1), 0.4), M))
    (33, 0)
    """
    from odnn_sep.image.residual import contour_components

    mag, parts = contour_components(y, cov)
    total_w = float(np.sum(mag, dtype=np.float64))
    if total_w <= 1e-12:
        return 0.0
    diff = np.zeros(cov.shape, np.float64)
    norm = np.zeros(cov.shape, np.float64)
    for across, along in parts:
        diff += across * across - along * along
        norm += across * across + along * along
    per_pixel = diff / np.sqrt(norm + 1e-12)   # |g| cos 2 theta over the channels
    return float(np.sum(mag * per_pixel, dtype=np.float64) / total_w * 255.0 / 4.0)


def rims_left(out: np.ndarray, inp: np.ndarray, coverages) -> tuple[float, float, bool]:
    """(share of the input's rim strength left, rim strength left in grey levels, still visible?)
    over the contours of several coverages; the coverage with the largest share is reported.

    Parameters
    ----------
    out, inp : np.ndarray
        (h, w, C) float output and input crops in [0, 1].
    coverages : sequence of np.ndarray or None
        (h, w) coverages the mark may have (None entries are skipped).

    Returns
    -------
    tuple of (float, float, bool)

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_rims import rims_left
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> I = np.full((32, 48, 3), 0.4); y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> Ms = np.roll(M, 2, axis=1)                             # removed with the shape 2 px off
    >>> rims = I + 0.5 * (M - Ms)[..., None] * (1 - I)
    >>> rims_left(I, y, [M])[2], rims_left(rims, y, [M])[2]      # a perfect removal, then rims
    (False, True)
    """
    best = (0.0, 0.0, False)
    for M in coverages:
        if M is None or not (M > 0.5).any():
            continue
        r_in = rim_levels(inp, M)
        if r_in <= 0:
            continue
        r_out = rim_levels(out, M)
        share = max(0.0, r_out / r_in)
        visible = share >= RIM_SHARE and r_out >= RIM_LEVELS
        if (visible, share) > (best[2], best[0]):
            best = (share, max(0.0, r_out), visible)
    return best


__all__ = ["rim_levels", "rims_left", "RIM_SHARE", "RIM_LEVELS"]
