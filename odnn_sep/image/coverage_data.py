"""What the image says about a mark's coverage beside the rendering: the coverage the data show
(for the residual mark's band), and the check that decides whether the data's coverage replaces the
rendering (how much of the mark's edges an inversion leaves)."""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import NotIdentifiableError
from odnn_sep.image.coverage import (
    AGREE_SHARE,
    BAND_STROKES,
    band_around,
    coverage_step,
    disagreement,
    interior_opacity,
)


def data_coverage(y: np.ndarray, prior: np.ndarray, *, random_state=0) -> np.ndarray | None:
    """The coverage the data show around a rendering, read from ``y`` alone (no refinement kept).

    The first step of :func:`refine_coverage`: the photo predicted from outside the band around the
    rendering only, the opacity from the glyph interiors, then ``M`` per band pixel (the rendering
    stays only where the data cannot tell). Where the rendering is a pixel or two off the true
    glyphs, this coverage sits on the true ones, so the residual mark's band can be placed there.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1] holding the mark (the input, not the output).
    prior : np.ndarray
        (h, w) registered rendering.
    random_state : int or Generator, default 0
        Seed of the blend fit's patch subset.

    Returns
    -------
    np.ndarray or None
        (h, w) coverage in [0, 1]; None when no blend can be fitted or the data agree with the
        rendering (depart from it at fewer than ``AGREE_SHARE`` of the glyph pixels).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage_data import data_coverage
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.3 * xx, 0.3 + 0.2 * yy, 0.5 + 0.1 * xx], -1)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> Md = data_coverage(y, np.roll(M, 3, axis=1))   # a rendering 3 px off: the data put it back
    >>> bool(np.mean(np.abs(Md - M)) < 0.1 * np.mean(np.abs(np.roll(M, 3, axis=1) - M)))
    True
    >>> data_coverage(y, M) is None                    # the right rendering: nothing to add
    True
    """
    from odnn_sep.image.estimate import fit_blend

    y = np.asarray(y, dtype=np.float64)
    if y.ndim == 2:
        y = y[:, :, None]
    prior = np.asarray(prior, dtype=np.float64)
    if not (prior > 0.5).any():
        return None
    try:
        fit = fit_blend(y, prior, max_patches=300, irls=0, xatol=1e-3, random_state=random_state)
    except NotIdentifiableError:
        return None
    band, s = band_around(prior)
    wide = max(1.5, float(int(np.ceil(max(2.0, BAND_STROKES * s)))))
    _, Q, _ = coverage_step(y, prior, prior, band, fit.alpha, fit.color, wide, first=True)
    if disagreement(Q, prior) < AGREE_SHARE:
        return None  # the data agree with the rendering: its band is the mark's
    a_in = interior_opacity(Q)
    if a_in is None:  # too few glyph pixels seen to read the opacity: the rendering's fit stands
        a_in = fit.alpha
    M, _, _ = coverage_step(y, prior, prior, band, float(np.clip(a_in, 1e-3, 0.995)), fit.color, wide, first=True)
    return M


def edges_left(y, M, alpha, color, prior) -> float:
    """Share of the mark's excess edge energy left after inverting with (M, alpha, color), in the
    band of the rendering and of ``M`` (the larger).

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) coverage to invert with.
    alpha : float
        Opacity.
    color : array_like
        (C,) mark colour.
    prior : np.ndarray
        (h, w) registered rendering.

    Returns
    -------
    float
        Share of the input's excess edge energy left (0 = none).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage_data import edges_left
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = 0.4 * (1 - 0.5 * M[..., None]) + 0.5 * M[..., None] * np.ones(3)
    >>> round(edges_left(y, M, 0.5, np.ones(3), M), 3)
    0.0
    """
    from odnn_sep.image.estimate import invert
    from odnn_sep.image.residual import edge_excess

    out, _ = invert(y, M, alpha, color, inpaint=False)
    left = 0.0
    for cov in (prior, M):
        e_in = edge_excess(y, cov)
        if e_in > 0:
            left = max(left, edge_excess(out, cov) / e_in)
    return left


__all__ = ["data_coverage", "edges_left"]
