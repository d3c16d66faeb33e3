"""Glyph coverage from the data: the registered rendering is the starting reference, not the truth.

A mark drawn in a font the tool does not have (another face, weight, letter spacing, a blur or a
resampling after the blend) is found and registered with a rendering that is close but not right:
its glyph edges sit a pixel or two off, its strokes are thinner or bolder. Inverting the blend with
that coverage leaves the true glyph edges in the photo. Here the coverage ``M`` is estimated per
pixel, inside a band around the rendered glyphs, jointly with the photo under it:

* the photo ``I`` is predicted at every band pixel from the pixels where it is seen directly: outside
  the glyphs, and inside them after the blend is undone (a normalised Gaussian average). A photo is
  smooth across a glyph edge on the scale of a pixel or two; the mark is not.
* given ``I``, opacity ``a`` and colour ``c``, the blend ``y = I + a M (c - I)`` is linear in ``M`` at
  each pixel: ``M`` is the projection of ``y - I`` on ``a (c - I)`` over the channels, with a variance
  from the photo's local texture (how well the prediction does where the photo is seen directly);
* the rendering is a prior on ``M``: where the data agree with it within their noise the two are
  averaged (the rendering's anti-aliasing is better than a per-pixel estimate when the font is right),
  where they disagree the data win (the rendering is wrong there), and where the mark's colour is too
  close to the photo's for the data to tell, the rendering stays;
* opacity and colour are fitted again with the new coverage (``estimate.fit_blend``), and the steps
  repeat a few times.
"""
from __future__ import annotations

import dataclasses

import numpy as np

from odnn_sep.errors import NotIdentifiableError

# Prior standard deviation of the coverage around the rendering where the data agree with it.
PRIOR_SD = 0.15
# Data further than this many of their standard deviations from the rendering replace it.
DISAGREE_Z = 2.5
# The rendering stands when the data depart from it at fewer than this share of the glyph pixels.
AGREE_SHARE = 0.35
# The data's coverage replaces the rendering only if it leaves at least this much less of the
# mark's edge energy (a share of the input's; ``residual.edge_excess``).
EDGE_MARGIN = 0.05
# Half-width of the band around the rendered glyphs, in stroke widths of the rendering.
BAND_STROKES = 1.2
# The opacity is read from pixels where a M is known to this standard deviation (the mark's colour
# far enough from the photo's, for the photo's texture there).
CONFIDENT_SD = 0.1
# The data's coverage is refused when it makes more than this share of the rendering's glyph pixels
# nearly opaque (a M > OPAQUE_AM: the inversion gives them up and inpaints them) while the rendering's
# own blend is nowhere that opaque. A white mark over a white cup rim or suit: the photo predicted
# from outside the band is darker there, so the rim reads as fully covered, the opacity read from
# the strongest pixels went from 0.35 to 0.94 and the rim was inpainted away (a DejaVu mark, the
# right font). On development seeds 1 and 7 the 13 accepted coverages of unseen-font marks had no
# such pixel.
OPAQUE_SHARE = 0.02
OPAQUE_AM = 0.9
# Floor of the photo's prediction error (a fraction of full scale: quantisation and sensor noise).
NOISE_FLOOR = 1.5 / 255


def _smooth(a: np.ndarray, sigma: float) -> np.ndarray:
    import cv2

    return cv2.GaussianBlur(np.ascontiguousarray(a, dtype=np.float32), (0, 0), sigma,
                            borderType=cv2.BORDER_REFLECT)


def predict_photo(R: np.ndarray, w: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Normalised Gaussian average of the photo ``R`` (h, w, C) seen with weights ``w`` (h, w):
    the prediction (h, w, C) and the local RMS prediction error where it is seen (h, w).

    Parameters
    ----------
    R : np.ndarray
        (h, w, C) photo estimate.
    w : np.ndarray
        (h, w) weights, 0 where the photo is not seen.
    sigma : float
        Gaussian width in px.

    Returns
    -------
    pred : np.ndarray
        (h, w, C) predicted photo.
    err : np.ndarray
        (h, w) local RMS prediction error.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import predict_photo
    >>> R = np.full((32, 48, 3), 0.4); R[10:20, 10:20] = 0.9
    >>> w = np.ones((32, 48)); w[10:20, 10:20] = 0
    >>> pred, err = predict_photo(R, w, 2.0)
    >>> round(float(pred[15, 15, 0]), 3), bool(err.max() < 1e-6)
    (0.4, True)
    """
    pred, err = _predicted_channels(R, w, sigma)
    return np.stack(pred, axis=2), err


def _channels(a: np.ndarray) -> list[np.ndarray]:
    """The channels of ``a`` (h, w, C) as contiguous float64 planes."""
    return [np.ascontiguousarray(a[:, :, c], dtype=np.float64) for c in range(a.shape[2])]


def _predicted_channels(R, w, sigma) -> tuple[list[np.ndarray], np.ndarray]:
    """``predict_photo`` with the prediction as a list of float64 planes.

    Channel by channel on contiguous planes: a sum over a length-3 last axis costs about as much as
    the rest of a matting step, and adding the planes in channel order gives the same bits."""
    Rc = R if isinstance(R, list) else _channels(R)
    den = _smooth(w, sigma) + 1e-6
    pred = [_smooth(w * r, sigma) / den for r in Rc]
    err = None
    for r, p in zip(Rc, pred):
        d = r - p
        d *= d
        err = d if err is None else err + d
    err /= len(Rc)
    var = _smooth(w * err, sigma) / den
    return [p.astype(np.float64) for p in pred], np.sqrt(np.maximum(var, 0.0)).astype(np.float64)


def coverage_step(y, M, prior, band, alpha, color, sigma, first):
    """One matting step: the photo predicted from where it is seen, then ``M`` per band pixel.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) current coverage.
    prior : np.ndarray
        (h, w) registered rendering (the prior on M).
    band : np.ndarray
        (h, w) bool, where M is estimated (:func:`band_around`).
    alpha : float
        Opacity.
    color : array_like
        (C,) mark colour.
    sigma : float
        Width (px) of the photo's prediction.
    first : bool
        Predict the photo from outside the band only (else from outside and inside the glyphs).

    Returns
    -------
    M_new : np.ndarray
        (h, w) coverage, 0 outside the band.
    Q : np.ndarray
        (h, w) per-pixel ``a M`` where determined well enough, NaN elsewhere.
    disagree : np.ndarray
        (h, w) bool, confident pixels where the data overrule the rendering.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import band_around, coverage_step
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = 0.4 * (1 - 0.5 * M[..., None]) + 0.5 * M[..., None] * np.ones(3)
    >>> band, s = band_around(M)
    >>> M_new, Q, dis = coverage_step(y, M, M, band, 0.5, np.ones(3), 5.0, True)
    >>> round(float(np.abs(M_new - M).max()), 3), round(float(np.nanmax(Q)), 3), int(dis.sum())
    (0.0, 0.5, 0)
    """
    a = float(alpha)
    col = np.asarray(color, dtype=np.float64).reshape(-1)
    yc = _channels(y)
    if first:  # the rendering's glyphs may be wrong: only the photo outside the band is trusted
        w = (~band).astype(np.float64)
        R = yc
    else:
        aM = a * M
        keep = np.maximum(1.0 - aM, 0.05)
        R = [(v - aM * k) / keep for v, k in zip(yc, col)]
        # outside the glyphs the photo is seen as is; inside, after the inversion (its noise is
        # amplified 1 / (1 - a)); at the glyph edges, where M is uncertain, not at all
        w = np.where(M < 0.03, 1.0, np.where(M > 0.97, (1.0 - a) ** 2, 0.0))
    I_hat, sd = _predicted_channels(R, w, sigma)
    dd = num = None
    for v, k, i in zip(yc, col, I_hat):  # channel sums in channel order (the same bits as np.sum)
        D = a * (k - i)
        dd = D * D if dd is None else dd + D * D
        num = (v - i) * D if num is None else num + (v - i) * D
    dd += 1e-12
    M_data = num / dd
    sd_M = (1.5 * sd + NOISE_FLOOR) / np.sqrt(dd)
    prec_d, prec_p = 1.0 / sd_M**2, 1.0 / PRIOR_SD**2
    post = (M_data * prec_d + prior * prec_p) / (prec_d + prec_p)
    disagree = np.abs(M_data - prior) > DISAGREE_Z * np.sqrt(sd_M**2 + PRIOR_SD**2)
    M_new = np.clip(np.where(disagree, M_data, post), 0.0, 1.0)
    # where a M is known well enough to read the opacity from
    confident = band & (a * sd_M < CONFIDENT_SD)
    return np.where(band, M_new, 0.0), np.where(confident, a * M_data, np.nan), disagree & confident


def disagreement(Q: np.ndarray, prior: np.ndarray) -> float:
    """Share of the glyph pixels where the per-pixel ``a M`` (``Q``, NaN where not determined) departs
    from the rendering scaled by its best opacity by more than a third of that opacity (an opacity
    fitted with a wrong rendering is itself off, so it is not used).

    Parameters
    ----------
    Q : np.ndarray
        (h, w) per-pixel ``a M`` (:func:`coverage_step`), NaN where not determined.
    prior : np.ndarray
        (h, w) registered rendering.

    Returns
    -------
    float
        Share in [0, 1]; 0 when fewer than 50 pixels are determined.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import disagreement
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> disagreement(0.5 * M, M), disagreement(0.5 * np.roll(M, 4, axis=1), M) > 0.3
    (0.0, True)
    """
    ok = np.isfinite(Q)
    if ok.sum() < 50:
        return 0.0
    q = Q[ok]
    p = prior[ok]
    a_best = float(np.sum(q * p) / max(float(np.sum(p * p)), 1e-12))
    if a_best <= 0:
        return 1.0
    zone = (p > 0.5) | (q > 0.5 * a_best)
    if zone.sum() < 50:
        return 0.0
    return float(np.mean(np.abs(q - a_best * p)[zone] > a_best / 3))


def interior_opacity(Q: np.ndarray) -> float | None:
    """Opacity from the per-pixel ``a M`` (``Q``, NaN where not determined): its upper quartile over
    the strongly covered pixels, or None when fewer than 50 are seen.

    Per pixel only ``a M`` is seen, so the split between opacity and coverage comes from the glyphs
    being solid: inside a stroke and along its centre line ``M`` is 1. An opacity
    fitted with the wrong glyph shape is wrong by the ratio of the two.

    Parameters
    ----------
    Q : np.ndarray
        (h, w) per-pixel ``a M``, NaN where not determined.

    Returns
    -------
    float or None

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import interior_opacity
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> interior_opacity(0.5 * M), interior_opacity(np.full((4, 4), np.nan))
    (0.5, None)
    """
    v = np.nan_to_num(Q, nan=0.0)
    ok = np.isfinite(Q)
    if ok.sum() < 50:
        return None
    hi = float(np.quantile(Q[ok], 0.98))
    if hi <= 0:
        return None
    strong = (v > 0.5 * hi) & ok
    if strong.sum() < 50:
        return None
    # The upper quartile of the strongly covered pixels: the interiors and centre lines of the strokes
    # (strokes of 2-3 px have no eroded interior of their own). The top decile of the eroded interior,
    # used before, read the photo's bright texture as opacity: on development seeds 7, 11 and 13 it
    # was 0.11 off the true opacity on average (up to 0.25), this quartile 0.09 (0.01 on 7 of 13).
    return float(np.quantile(Q[strong], 0.75))


def refine_coverage(y: np.ndarray, prior: np.ndarray, alpha: float, color, *, iterations: int = 3,
                    random_state=0):
    """Coverage, opacity and colour of a mark estimated from ``y`` around its registered rendering.

    Parameters
    ----------
    y : (h, w, C) float array in [0, 1], a crop holding the mark with a margin of a few stroke widths
    prior : (h, w) registered rendering of the mark's text (coverage in [0, 1])
    alpha, color : opacity and colour fitted with the rendering (``estimate.fit_blend``)
    iterations : matting steps with the photo predicted from nearby (after the first two from afar)

    Returns
    -------
    (M (h, w), BlendFit or None): the coverage and the last fit; (``prior``, None) when the data agree
    with the rendering (or the fit failed): then ``alpha`` and ``color`` stand

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import refine_coverage
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> yy, xx = np.mgrid[0:32, 0:48] / 48.0
    >>> I = np.stack([0.2 + 0.3 * xx, 0.3 + 0.2 * yy, 0.5 + 0.1 * xx], -1)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> M_out, fit = refine_coverage(y, M, 0.5, np.ones(3))   # the rendering is right: it stands
    >>> M_out is M, fit
    (True, None)
    """
    from odnn_sep.image.estimate import fit_blend

    y = np.asarray(y, dtype=np.float64)
    if y.ndim == 2:
        y = y[:, :, None]
    prior = np.asarray(prior, dtype=np.float64)
    band, s = band_around(prior)
    alpha0, color0 = alpha, color
    wide = max(1.5, float(int(np.ceil(max(2.0, BAND_STROKES * s)))))
    # 1. the photo from outside the band only (it does not depend on the opacity or the coverage),
    #    so the per-pixel a M and the opacity of the glyph interiors follow in one step
    M, fit = prior, None
    for k in range(2):
        M, Q, _ = coverage_step(y, prior, prior, band, alpha, color, wide, first=True)
        if k == 0 and disagreement(Q, prior) < AGREE_SHARE:
            return prior, None  # the rendering is right: its anti-aliasing beats a per-pixel estimate
        a_in = interior_opacity(Q)
        if a_in is None:
            return prior, None
        alpha = float(np.clip(a_in, 1e-3, 0.995))
        M, _, _ = coverage_step(y, prior, prior, band, alpha, color, wide, first=True)
        # the colour from the blend fit with that coverage (its opacity is tied to the coverage's scale)
        try:
            fit = fit_blend(y, M, random_state=random_state)
        except NotIdentifiableError:
            return prior, None
        color = fit.color
    # 2. the photo from closer by (outside the glyphs and, inverted, inside them), opacity fixed
    for _ in range(iterations):
        M, _, _ = coverage_step(y, M, prior, band, alpha, color, max(1.0, 0.4 * s), first=False)
    if fit is None:
        return prior, None
    fit = dataclasses.replace(fit, alpha=alpha, beta=alpha * np.asarray(color))
    # The rendering stands unless the data's coverage leaves clearly less of the mark's edges: with
    # the right font the rendering's anti-aliasing beats any per-pixel estimate.
    from odnn_sep.image.coverage_data import edges_left

    if alpha0 <= OPAQUE_AM and np.count_nonzero(fit.alpha * M > OPAQUE_AM) > OPAQUE_SHARE * np.count_nonzero(prior > 0.5):
        return prior, None
    left_prior = edges_left(y, prior, alpha0, color0, prior)
    left_data = edges_left(y, M, fit.alpha, fit.color, prior)
    if left_data < left_prior - EDGE_MARGIN:
        return M, fit
    return prior, None


def band_around(prior: np.ndarray) -> tuple[np.ndarray, float]:
    """(band, stroke width): where a glyph of a similar font drawn at the rendering's place can reach.

    Parameters
    ----------
    prior : np.ndarray
        (h, w) registered rendering.

    Returns
    -------
    band : np.ndarray
        (h, w) bool, the rendering dilated by ``BAND_STROKES`` stroke widths.
    s : float
        Stroke width of the rendering (px).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.coverage import band_around
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> band, s = band_around(M)
    >>> int(band.sum()), round(s, 2)
    (712, 3.82)
    """
    import cv2

    from odnn_sep.image.estimate import stroke_width

    s = stroke_width(prior)
    r = int(np.ceil(max(2.0, BAND_STROKES * s)))
    band = cv2.dilate((prior > 0.02).astype(np.uint8), cv2.getStructuringElement(
        cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))).astype(bool)
    return band, s


__all__ = ["refine_coverage", "coverage_step", "predict_photo", "band_around"]
