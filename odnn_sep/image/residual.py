"""What is left of a mark after removal: the detection statistic on the output, in the mark's band.

The output is searched for nothing: the mark's own coverage (the estimate used for the removal, and
the registered rendering it started from) is placed where the mark was, and the detection statistic
(``detect.detection_score``: do the edge patches of the output still follow a blend with one opacity
and colour, out of sample?) is computed on the output. A removed mark leaves nothing that the blend
model explains better than the photo alone; a mark removed with the wrong glyph shape leaves its true
edges, which the rendering's band still covers.

The statistic is invariant to the contrast of what is left, so a mark counts as still visible only if
it also has contrast: the opacity fitted to what is left, times the distance of its colour from the
photo under it, in grey levels of 8 bits.

A mark removed with the wrong glyph shape leaves rims along its true edges rather than a blend of
its estimated shape, which the statistic does not see. So the edges are counted as well: how much
more edge energy the mark's band holds than the ring of photo around it, on the output, as a share
of the same excess on the input. The tool's shapes may both sit a pixel or two off the true glyphs
(a font it does not have), so the edges are also counted in the band of the coverage the input itself
shows around the rendering (``coverage_data.data_coverage``: the photo predicted from outside the band,
the mark's share per pixel from the blend); that band holds the true edges.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import NotIdentifiableError
from odnn_sep.image.detect import THRESHOLD, detection_score

# A residual mark with less contrast than this (8-bit grey levels, RMS over its glyph pixels) is not
# counted as visible whatever its score: a step of a few levels across a glyph edge is below what
# one sees on a photo.
VISIBLE_LEVELS = 4.0
# Edges: the mark counts as still there when its band keeps this share of the input's excess edge
# energy (band over ring) and that excess is at least EDGE_EXCESS (the band has that much more detail
# than the photo around it). Provisional values, to be checked on development seeds.
EDGE_LEFT = 0.3
EDGE_EXCESS = 0.5
# ... or when the band keeps at least EDGE_LEFT_STRONG of the input's excess and the input's excess was
# at least EDGE_SIGNAL: a mark over a busy photo (the ring around the band as detailed as the band)
# has a small excess on the input already, and rims left along its true edges keep all of it. Chosen
# on development seeds 7, 11 and 13 with the clean photo scored as the output (a perfect removal):
# its share of the input's excess was at most 0.34 where that excess was >= EDGE_SIGNAL. Only in the
# band of the coverage the input shows where it departs from the rendering: with the right font a
# faint mark over texture has a small input excess and a perfect removal can keep half of it (a
# DejaVu mark of development seed 7 did, 0.54).
EDGE_LEFT_STRONG = 0.5
EDGE_SIGNAL = 0.3
# ... and in either case only when the edges left run along the mark's contours: the output keeps at
# least this share of the input's edge energy across the contours of the registered rendering in
# excess of that along them (``aligned_share``). A photo with more detail under the mark than around
# it (a white mark over a patterned sleeve, ringed by sky) has a band excess of its own, which a
# perfect removal keeps in full, and the coverage the input shows there takes in the photo's own
# edges: a clean output was called still visible (exit 3) on 4 of 7 placements of a DejaVu mark over
# the astronaut. Photo detail runs every way, with as much energy along the rendering's contours as
# across them; rims left along the true glyph edges run along them, also a pixel or two off. Chosen
# on development seeds 1 and 7 (20 unseen-font marks found) and those 7 placements: the 6 outputs
# whose letters stay as rims keep 0.24-0.83 of it; with 0.15-0.2 no clean photo scored as the output
# is called visible (with 0.25 one rim output is no longer).
ALIGNED_LEFT = 0.2
# A blend of the mark's own shape with this much contrast left (8-bit levels, RMS over its glyph
# pixels) is visible whatever the detection statistic says. That statistic reads the mark's edges; a
# mark with an outline or a drop shadow (two colours) leaves its glyphs darkened or lightened as a
# whole once its one-colour blend is inverted, with little edge where the tool's shape ends. On clean
# photos (a perfect removal; 179 placements of DejaVu renderings over the four photos of
# ../shared/data/photos_clean_skimage) the blend fitted to the photo alone had at most 14.6 levels
# (median 1.3); outlined and shadowed marks left 51-55.
STRONG_LEVELS = 25.0


def contrast_levels(y: np.ndarray, M: np.ndarray, *, random_state=0) -> float:
    """RMS contrast (8-bit levels) over the glyph pixels (M > 0.5) of the blend fitted to ``y``.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) coverage of the mark.
    random_state : int or Generator, default 0
        Seed of the blend fit's patch subset.

    Returns
    -------
    float
        Contrast in 8-bit grey levels; 0 when no blend can be fitted.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import contrast_levels
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> I = np.full((32, 48, 3), 0.4); y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> round(contrast_levels(y, M), 1), contrast_levels(I, M) < 1e-6
    (76.5, True)
    """
    from odnn_sep.image.estimate import fit_blend, invert

    try:
        fit = fit_blend(y, M, max_patches=300, irls=0, xatol=1e-3, random_state=random_state)
    except NotIdentifiableError:
        return 0.0
    photo, _ = invert(y, M, fit.alpha, fit.color, inpaint=False)
    on = M > 0.5
    if not on.any():
        return 0.0
    d = fit.alpha * (fit.color[None, :] - photo[on])
    return float(255.0 * np.sqrt(np.mean(np.sum(d * d, axis=1) / d.shape[1])))


def step_left(out: np.ndarray, inp: np.ndarray, M: np.ndarray, *, random_state=0) -> tuple[float, float]:
    """(signed share, 8-bit levels) of the step along the edges of ``M`` that the output keeps.

    Over the edge patches of ``M`` the image is fitted as a plane per patch plus one step ``b M``
    shared by all patches (``b`` of any sign, per channel). The share is the output's step projected on
    the input's, over the input's: about 0 after a removal, 1 for a mark left as it was, negative for
    a mark removed too far (an opacity fitted too high leaves the letters in the opposite colour, which
    a blend fit, with its opacity in [0, 1], cannot see). The levels are the output step's RMS size.

    Parameters
    ----------
    out, inp : np.ndarray
        (h, w, C) float output and input crops in [0, 1].
    M : np.ndarray
        (h, w) coverage of the mark.
    random_state : int or Generator, default 0
        Seed of the patch subset.

    Returns
    -------
    tuple of (float, float)
        (0, 0) when ``M`` has no edges or the input no step.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import step_left
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> I = np.full((32, 48, 3), 0.4); y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> over = (1 + 0.2 * M[..., None]) * I - 0.2 * M[..., None]       # removed with too high an opacity
    >>> [round(v, 2) for v in step_left(y, y, M)], [round(v, 2) for v in step_left(over, y, M)]
    ([1.0, 76.5], [-0.4, 30.6])
    """
    from odnn_sep.image.estimate import patch_grid, take_patches
    from odnn_sep.image.profile import DataProfile, design

    out = out[:, :, None] if out.ndim == 2 else out
    inp = inp[:, :, None] if inp.ndim == 2 else inp
    py, px, ps = patch_grid(np.asarray(M, dtype=np.float64), 8, 400, np.random.default_rng(random_state))
    if len(py) < 4:
        return 0.0, 0.0
    Mp = take_patches(M, py, px, ps)[:, :, 0]
    Phi = design(ps, 1)
    steps = []
    for img in (out, inp):
        sxx, sxy, _ = DataProfile(take_patches(img, py, px, ps), Mp, Phi).stats(0.0)
        steps.append(np.sum(sxy, axis=0) / max(float(np.sum(sxx)), 1e-300))
    b_out, b_in = steps
    n_in = float(np.sum(b_in * b_in))
    if n_in <= 0:
        return 0.0, 0.0
    return float(np.sum(b_out * b_in) / n_in), float(255.0 * np.sqrt(np.mean(b_out * b_out)))


def _gradient(ch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Sobel gradient (x, y) of one (h, w) channel, in single precision."""
    import cv2

    ch = np.ascontiguousarray(ch, dtype=np.float32)
    return cv2.Sobel(ch, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(ch, cv2.CV_32F, 0, 1, ksize=3)


def _edge_energy(y: np.ndarray) -> np.ndarray:
    """Squared gradient magnitude (Sobel, summed over channels) of a (h, w, C) image."""
    g = np.zeros(y.shape[:2])
    for c in range(y.shape[2]):
        gx, gy = _gradient(y[:, :, c])
        g += gx ** 2 + gy ** 2
    return g


def edge_excess(y: np.ndarray, cov: np.ndarray) -> float:
    """Mean edge energy in the mark's band (glyphs of ``cov`` dilated by most of a stroke width) over
    that of a ring around it, minus 1: about 0 when there is as much detail under the mark as beside
    it, more when the mark (or the rim of a mark removed with the wrong glyph shape) is still there.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float image in [0, 1].
    cov : np.ndarray
        (h, w) coverage of the mark.

    Returns
    -------
    float
        Band-over-ring edge energy minus 1; 0 when the band or ring has fewer than 20 pixels.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import edge_excess
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> I = np.full((32, 48, 3), 0.4); y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> edge_excess(y, M) > 10, round(edge_excess(I, M), 1)
    (True, -1.0)
    """
    import cv2

    from odnn_sep.image.estimate import stroke_width

    s = stroke_width(cov)
    r = int(np.ceil(max(2.0, 0.8 * s)))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    band = cv2.dilate((cov > 0.05).astype(np.uint8), disk).astype(bool)
    w = int(np.ceil(2 * s)) + 3
    ring = cv2.dilate(band.astype(np.uint8), np.ones((2 * w + 1, 2 * w + 1), np.uint8)).astype(bool) & ~band
    if band.sum() < 20 or ring.sum() < 20:
        return 0.0
    g = _edge_energy(y)
    return float(np.mean(g[band]) / max(float(np.mean(g[ring])), 1e-12) - 1.0)


def aligned_energy(y: np.ndarray, cov: np.ndarray) -> float:
    """Edge energy of ``y`` across the contours of ``cov`` minus that along them, weighted by the
    contours' strength (the gradient of ``cov`` smoothed over a pixel, so a contour a pixel or two off
    the true one still points the same way): about 0 for detail that runs every way, the mark's
    edge energy for a mark (or the rims it left).

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float image in [0, 1].
    cov : np.ndarray
        (h, w) coverage of the mark.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import aligned_energy
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = (1 - 0.5 * M[..., None]) * 0.4 + 0.5 * M[..., None]
    >>> aligned_energy(y, M) > 0, abs(aligned_energy(np.full((32, 48, 1), 0.4), M)) < 1e-9
    (True, True)
    """
    mag, parts = contour_components(y, cov)
    return sum(float(np.sum(mag ** 2 * (across ** 2 - along ** 2), dtype=np.float64)) for across, along in parts)


def contour_components(y: np.ndarray, cov: np.ndarray) -> tuple[np.ndarray, list]:
    """(contour strength (h, w), [(across, along) per channel]): the Sobel gradient of each channel of
    ``y`` across and along the contours of ``cov`` smoothed over a pixel (so a contour a pixel or two off
    the true one still points the same way), and the strength of those contours.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float image.
    cov : np.ndarray
        (h, w) coverage of the mark.

    Returns
    -------
    tuple
        ``mag`` (h, w) and a list of C pairs of (h, w) arrays.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import contour_components
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1
    >>> mag, parts = contour_components(0.4 + 0.2 * M[..., None], M)
    >>> across, along = parts[0]                            # a step along the contours: mostly across
    >>> len(parts), bool(np.sum(mag * across ** 2) > 10 * np.sum(mag * along ** 2))
    (1, True)
    """
    import cv2

    mx, my = _gradient(cv2.GaussianBlur(np.ascontiguousarray(cov, dtype=np.float32), (0, 0), 1.0))
    mag = np.hypot(mx, my)
    nx, ny = mx / np.maximum(mag, 1e-12), my / np.maximum(mag, 1e-12)
    parts = []
    for c in range(y.shape[2]):
        gx, gy = _gradient(y[:, :, c])
        parts.append((gx * nx + gy * ny, gy * nx - gx * ny))
    return mag, parts


def aligned_share(out: np.ndarray, inp: np.ndarray, cov: np.ndarray) -> float:
    """The output's :func:`aligned_energy` as a share of the input's (0 when the input has none).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import aligned_share
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> y = (1 - 0.5 * M[..., None]) * 0.4 + 0.5 * M[..., None]
    >>> round(aligned_share(y, y, M), 3), round(aligned_share(np.full((32, 48, 1), 0.4), y, M), 3)
    (1.0, 0.0)
    """
    e_in = aligned_energy(inp, cov)
    return aligned_energy(out, cov) / e_in if e_in > 0 else 0.0


def edges_left_over(out: np.ndarray, inp: np.ndarray, coverages, departing: np.ndarray | None = None
                    ) -> tuple[float, bool]:
    """(share of the mark's excess edge energy left, are the mark's edges still there?) over the bands
    of several coverages.

    The mark's edges count as still there when, in the band of any one coverage, the output keeps at
    least ``EDGE_LEFT`` of the input's excess edge energy and still has an excess of ``EDGE_EXCESS``.
    In the band of ``departing`` (the coverage the input shows where it departs from the rendering,
    ``coverage_data.data_coverage``) they count as there when the output keeps at least
    ``EDGE_LEFT_STRONG`` of an input excess of at least ``EDGE_SIGNAL``: the rims a wrong glyph shape
    leaves over a busy photo (that band also takes in some photo texture, so a perfect removal can
    keep up to 0.4 of its excess). Either way the output must also keep ``ALIGNED_LEFT`` of the input's
    edge energy across the contours of that coverage (``aligned_share``): the photo's own detail
    under the mark runs every way. The share returned is the largest over the bands that pass, or over
    all bands when none does.

    Parameters
    ----------
    out, inp : np.ndarray
        (h, w, C) float output and input crops in [0, 1].
    coverages : sequence of np.ndarray
        (h, w) coverages the mark may have.
    departing : np.ndarray or None
        (h, w) the data's coverage where it departs from the rendering.

    Returns
    -------
    tuple of (float, bool)

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual import edges_left_over
    >>> M = np.zeros((32, 48)); M[8:24, 10:16] = 1; M[8:12, 10:40] = 1
    >>> I = np.full((32, 48, 3), 0.4); y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None]
    >>> edges_left_over(y, y, [M]), edges_left_over(I, y, [M])
    ((1.0, True), (0.0, False))
    """
    shares, passing = [], []
    bands = [(M, False) for M in coverages] + ([(departing, True)] if departing is not None else [])
    for M, busy_rule in bands:
        e_out, e_in = edge_excess(out, M), edge_excess(inp, M)
        if e_in <= 0:
            continue
        shares.append(max(0.0, e_out / e_in))
        if ((not busy_rule and shares[-1] >= EDGE_LEFT and e_out >= EDGE_EXCESS) or (
                busy_rule and shares[-1] >= EDGE_LEFT_STRONG and e_in >= EDGE_SIGNAL)) \
                and aligned_share(out, inp, M if not busy_rule else coverages[-1]) >= ALIGNED_LEFT:
            passing.append(shares[-1])
    if passing:
        return max(passing), True
    return max(shares, default=0.0), False


def measure(out: np.ndarray, inp: np.ndarray, *coverages: np.ndarray, threshold: float = THRESHOLD,
            random_state=0, data_band: bool = True, rims: bool = False) -> dict:
    """Residual mark of an output crop ``out`` (h, w, C) in [0, 1], given the input crop ``inp`` and
    the coverages (h, w) the mark may have (the estimated one, the registered rendering; the last is
    the rendering). With ``data_band`` the edges are also counted in the band of the coverage the
    input shows around the last one (``coverage_data.data_coverage``): where the tool's shapes are a
    pixel or two off the true glyphs, the rims the removal leaves along the true edges are there.
    With ``rims`` (text mode: the last coverage is the registered rendering) the edge strength left
    across the rendering's contours is counted as well (``residual_rims.rims_left``).

    Returns
    -------
    dict: ``score`` (the largest detection score on the output over the coverages),
    ``contrast_levels`` (RMS contrast of the blend fitted to what is left for that coverage, 8-bit
    levels), ``edge_left`` (the mark band's excess edge energy over the ring around it, on the output,
    as a share of the same on the input; the largest over the coverages), ``threshold`` and
    ``visible``: a blend still detected with contrast, most of the mark's edges still there, or a
    blend of the estimated shape with ``STRONG_LEVELS`` of contrast whatever the statistic says;
    ``second_colour``: None, or the outline or shadow left beside the mark
    (``residual_second.second_colour``: its shape, score and contrast), which also makes it visible;
    with ``rims``, ``rim_left`` and ``rim_levels``: the edge strength across the rendering's contours
    left in the output (a share of the input's, and 8-bit grey levels), visible from
    ``residual_rims.RIM_SHARE`` and ``RIM_LEVELS``.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> I = 0.5 + 0.02 * rng.standard_normal((60, 90, 1))
    >>> M = np.zeros((60, 90)); M[15:45, 20:25] = 1; M[15:20, 10:80] = 1; M[40:45, 30:70] = 1
    >>> y = (1 - 0.3 * M[..., None]) * I + 0.3 * M[..., None]
    >>> measure(y, y, M)["visible"], measure(I, y, M)["visible"]
    (True, False)
    """
    out = np.asarray(out, dtype=np.float64)
    inp = np.asarray(inp, dtype=np.float64)
    out = out[:, :, None] if out.ndim == 2 else out
    inp = inp[:, :, None] if inp.ndim == 2 else inp
    coverages = [M for M in coverages if M is not None and (M > 0.5).any()]
    best, best_m = 0.0, None
    for M in coverages:
        s = detection_score(out, M, random_state=random_state)
        if best_m is None or s > best:
            best, best_m = s, M
    Md = None
    if coverages and data_band:
        from odnn_sep.image.coverage_data import data_coverage

        Md = data_coverage(inp, coverages[-1], random_state=random_state)
        Md = Md if Md is not None and (Md > 0.5).any() else None
    left, edges_visible = edges_left_over(out, inp, coverages, Md)
    rim = None
    if rims and coverages:
        from odnn_sep.image.residual_rims import rims_left

        rim = rims_left(out, inp, coverages[-1:])
    levels = contrast_levels(out, best_m, random_state=random_state) if best_m is not None and best >= threshold \
        else 0.0
    visible = (best >= threshold and levels >= VISIBLE_LEVELS) or edges_visible
    if not visible and coverages:
        # a strong blend of the estimated shape left (an outlined or shadowed mark): visible too
        levels = max(levels, contrast_levels(out, coverages[0], random_state=random_state))
        visible = levels >= STRONG_LEVELS
    second = None
    if not visible:
        # the other colour of a two-colour mark (outline, shadow), beside the shape that was inverted;
        # the rendering first: its outline is exact where the estimated shape may have taken in photo
        from odnn_sep.image.residual_second import second_colour

        checked = []
        for M in coverages[::-1]:
            on = M > 0.5
            if any(np.count_nonzero(on & c) >= 0.95 * np.count_nonzero(on | c) for c in checked):
                continue                # the same shape as one checked already: same shapes, same answer
            checked.append(on)
            second = second_colour(out, M, threshold=threshold, random_state=random_state)
            if second is not None:
                visible = True
                break
    if rim is not None and rim[2]:
        visible = True              # after the second colour: an outline or shadow is named when there is one
    report = {"score": round(float(best), 4), "contrast_levels": round(levels, 2), "edge_left": round(left, 3),
              "threshold": threshold, "visible": bool(visible), "second_colour": second}
    if rim is not None:
        report.update(rim_left=round(rim[0], 3), rim_levels=round(rim[1], 2))
    return report


__all__ = ["measure", "step_left", "edge_excess", "edges_left_over", "aligned_energy", "aligned_share", "contour_components", "ALIGNED_LEFT", "VISIBLE_LEVELS", "EDGE_LEFT", "EDGE_EXCESS", "EDGE_LEFT_STRONG",
           "EDGE_SIGNAL", "STRONG_LEVELS"]
