"""A logo with several colours: only the opacity ``alpha`` is fitted, its colours are the logo's own.

The blend is ``y = (1 - alpha M) I + alpha M L`` with ``L`` the logo's colours per pixel. As in text
mode the photo is a plane per edge patch (projected out), and ``alpha`` maximises the likelihood of
the restored photo (``ColouredProfile``); the detection score is the same held-out test as
``detect.detection_score``: the opacity fitted on one half of the mark predicts the other half.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.core.linalg import orthonormal_basis
from odnn_sep.errors import NotIdentifiableError


class ColouredProfile:
    """Negative log-likelihood(alpha) of the restored photo for a logo of known colours ``L``: the
    patches ``(y - alpha M L) / (1 - alpha M)`` with a plane per patch projected out (``plane_rss``),
    plus the change of variables ``sum log(1 - alpha M)`` (as ``profile.PhotoProfile``).

    Parameters
    ----------
    Yp : np.ndarray
        (p, n, C) image patches.
    Mp : np.ndarray
        (p, n) coverage patches.
    Lp : np.ndarray
        (p, n, C) logo colour patches.
    Phi : np.ndarray
        (n, k) polynomial design of one patch.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.profile import design
    >>> from odnn_sep.image.logo_colour import ColouredProfile
    >>> Mp = np.zeros((4, 16)); Mp[:, :8] = 1.0
    >>> Lp = np.ones((4, 16, 1)); Yp = 0.2 * (1 - 0.5 * Mp[..., None]) + 0.5 * Mp[..., None] * Lp
    >>> prof = ColouredProfile(Yp, Mp, Lp, design(4, 1))
    >>> bool(prof.rss(0.5).max() < 1e-20), bool(prof(0.5) < prof(0.3))
    (True, True)
    """

    def __init__(self, Yp, Mp, Lp, Phi):
        self.Yp, self.Mp, self.MLp = Yp, Mp, Mp[:, :, None] * Lp
        self.Q = orthonormal_basis(Phi, method="qr", rtol=None)
        self.k = Phi.shape[1]

    def rss(self, alpha: float) -> np.ndarray:
        from odnn_sep.image.profile import plane_rss

        u = 1.0 - alpha * self.Mp
        return plane_rss((self.Yp - alpha * self.MLp) / u[:, :, None], self.Q)

    def __call__(self, alpha: float) -> float:
        C = self.Yp.shape[2]
        n_eff = len(self.Mp) * (self.Mp.shape[1] - self.k) * C
        rss = float(np.sum(self.rss(alpha)))
        return 0.5 * n_eff * np.log(max(rss, 1e-300) / n_eff) + C * float(np.sum(np.log(1.0 - alpha * self.Mp)))


def fit_coloured(y, M, L, *, patch: int = 8, random_state=0) -> tuple[float, float]:
    """(alpha, explained) of a logo with its own colours ``L`` (h, w, C) and coverage ``M`` in crop ``y``.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) coverage of the placed logo.
    L : np.ndarray
        (h, w, C) its colours.
    patch : int, default 8
        Patch side in px.
    random_state : int or Generator, default 0
        Seed of the patch subset.

    Returns
    -------
    alpha : float
        Opacity.
    explained : float
        Share of the patches' photo-only residual the mark explains.

    Raises
    ------
    NotIdentifiableError
        With fewer than four edge patches.

    Examples
    --------
    >>> from odnn_sep.image.logo_colour import fit_coloured
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((24, 24, 4), np.uint8); a[4:20, 4:9] = (255, 40, 40, 255); a[4:9, 4:20] = (40, 40, 255, 255)
    >>> logo = prepare_logo(a, (64, 96), 3)
    >>> M, L, _ = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> yy, xx = np.mgrid[0:M.shape[0], 0:M.shape[1]] / 40.0
    >>> I = np.stack([0.3 + 0.2 * xx, 0.4 + 0.1 * yy, 0.5 + 0.0 * xx], -1)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None] * L
    >>> alpha, explained = fit_coloured(y, M, L)
    >>> round(alpha, 3), round(explained, 3)
    (0.5, 1.0)
    """
    from odnn_sep.image.estimate import drop_clipped, minimise_profile, patch_grid, take_patches
    from odnn_sep.image.profile import DataProfile, design, plane_rss

    py, px, ps = patch_grid(M, patch, 800, np.random.default_rng(random_state))
    Yp, Mp, Lp = take_patches(y, py, px, ps), take_patches(M, py, px, ps)[:, :, 0], take_patches(L, py, px, ps)
    Yp, Mp, Lp = drop_clipped(Yp, Mp, Lp)
    if len(Mp) < 4:
        raise NotIdentifiableError("the logo has too few sharp edges inside the photo to fit its opacity")
    Phi = design(ps, 1)
    prof = ColouredProfile(Yp, Mp, Lp, Phi)
    alpha = float(minimise_profile(prof, 0.995, 17, 1e-5).x)
    rss0 = plane_rss(Yp, prof.Q)
    # image-domain residual of the mark model at that alpha: y - alpha M L = P (1 - alpha M)
    rss1 = DataProfile(Yp - alpha * prof.MLp, Mp, Phi).parts(alpha, np.zeros(Yp.shape[2]))[1]
    return alpha, max(0.0, 1.0 - float(np.sum(rss1)) / max(float(np.sum(rss0)), 1e-300))


def coloured_detection_score(y, M, L, *, random_state=0) -> float:
    """``detect.detection_score`` for a logo of known colours: the opacity fitted on one half of the
    edge patches (along the mark's principal axis) predicts the other half; the score is the mean
    clipped log-ratio of photo-only to predicted residual, discounted for few patches.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float crop in [0, 1].
    M : np.ndarray
        (h, w) coverage of the placed logo.
    L : np.ndarray
        (h, w, C) its colours.
    random_state : int or Generator, default 0
        Seed of the patch subset.

    Returns
    -------
    float
        Score in [-CLIP, CLIP]; 0 with too few patches.

    Examples
    --------
    >>> from odnn_sep.image.detect import THRESHOLD
    >>> from odnn_sep.image.logo_colour import coloured_detection_score
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((24, 24, 4), np.uint8); a[4:20, 4:9] = (255, 40, 40, 255); a[4:9, 4:20] = (40, 40, 255, 255)
    >>> logo = prepare_logo(a, (64, 96), 3)
    >>> M, L, _ = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> yy, xx = np.mgrid[0:M.shape[0], 0:M.shape[1]] / 40.0
    >>> I = np.stack([0.3 + 0.2 * xx, 0.4 + 0.1 * yy, 0.5 + 0.0 * xx], -1)
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None] * L
    >>> coloured_detection_score(y, M, L) > THRESHOLD, coloured_detection_score(I, M, L) < THRESHOLD
    (True, True)
    """
    from odnn_sep.image.detect import CLIP, FULL_WEIGHT_PATCHES, principal_halves
    from odnn_sep.image.estimate import drop_clipped, minimise_profile, patch_grid, stroke_width, take_patches
    from odnn_sep.image.profile import DataProfile, design, plane_rss

    patch = int(np.clip(round(2.5 * stroke_width(M) + 4), 8, 32))
    n_max = int(np.clip(150_000 // patch**2, FULL_WEIGHT_PATCHES, 600))
    py, px, ps = patch_grid(M, patch, n_max, np.random.default_rng(random_state))
    Yp, Mp, Lp = take_patches(y, py, px, ps), take_patches(M, py, px, ps)[:, :, 0], take_patches(L, py, px, ps)
    Yp, Mp, Lp, py, px = drop_clipped(Yp, Mp, Lp, py, px)
    yy, xx = np.nonzero(M > 0.5)
    if len(Mp) < 4 or len(yy) < 2:
        return 0.0
    Phi = design(ps, 1)
    prof = ColouredProfile(Yp, Mp, Lp, Phi)
    rss0 = plane_rss(Yp, prof.Q)
    low = principal_halves(xx, yy, py, px, ps)
    if low is None:
        return 0.0
    rss1 = np.empty_like(rss0)
    for fit_on in (low, ~low):
        a = float(minimise_profile(ColouredProfile(Yp[fit_on], Mp[fit_on], Lp[fit_on], Phi), 0.995, 9, 1e-3).x)
        other = ~fit_on
        # image-domain residual of the other half under that opacity: y - a M L = P (1 - a M)
        rss1[other] = DataProfile(Yp[other] - a * prof.MLp[other], Mp[other], Phi).parts(a, np.zeros(Yp.shape[2]))[1]
    votes = np.clip(np.log((rss0 + 1e-12) / (rss1 + 1e-12)), -CLIP, CLIP)
    return float(np.mean(votes) * min(1.0, np.sqrt(len(votes) / FULL_WEIGHT_PATCHES)))
