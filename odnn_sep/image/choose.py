"""Choice between rival renderings of one mark (another font or size at the same place) by the
likelihood of the blend model on the same pixels.

Each rival's own fit (``BlendFit.explained``) is measured on the patches along its own glyph edges,
so a bolder or larger rendering is judged on other pixels than a thinner one, and the shares are not
comparable. Here every rival explains the same patches (the union of their edge patches) and the
one whose restored photo is most likely (``profile.PhotoProfile``, opacity and colour profiled out,
the same number of parameters for each) wins.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.image.estimate import drop_clipped, minimise_profile, patch_grid, take_patches
from odnn_sep.image.profile import PhotoProfile, design


def most_likely(y, rivals, *, patch: int = 8, max_patches: int = 800, random_state=0) -> int:
    """Index of the rival placement (``register.Placed``) under which the data are most likely.

    ``y``: the whole image as float (H, W, C) in [0, 1] (or a view giving float crops).

    Parameters
    ----------
    y : np.ndarray or FloatView
        The whole image, float (H, W, C) in [0, 1].
    rivals : list of Placed
        Rival placements of one mark; fewer than two give 0.
    patch : int, default 8
        Patch size in pixels.
    max_patches : int, default 800
        Most patches used (a random subset beyond).
    random_state : int or Generator, default 0
        Seed of the patch subset.

    Returns
    -------
    int
        Index in ``rivals`` of the most likely placement.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.choose import most_likely
    >>> from odnn_sep.image.register import Placed, refine
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.repeat(np.linspace(70, 110, 48)[:, None, None], 64, 1).repeat(3, 2).astype(np.uint8)
    >>> y, _ = add_text_watermark(clean, "Hi", size=20, center=(32, 24), alpha=0.5)
    >>> p = refine(y / 255.0, "Hi", "DejaVuSans-Bold", 19.5, 0.0, (31.5, 24.5))
    >>> shifted = Placed(p.font, p.size, p.angle, p.center, p.box, np.roll(p.coverage, 3, axis=1), p.fit)
    >>> most_likely(y / 255.0, [shifted, p]), most_likely(y / 255.0, [p])
    (1, 0)
    """
    if len(rivals) < 2:
        return 0
    X0, Y0 = min(p.box[0] for p in rivals), min(p.box[1] for p in rivals)
    X1, Y1 = max(p.box[2] for p in rivals), max(p.box[3] for p in rivals)
    crop = np.asarray(y[Y0:Y1, X0:X1], dtype=np.float64)
    if crop.ndim == 2:
        crop = crop[:, :, None]
    covs = []
    for p in rivals:
        c = np.zeros((Y1 - Y0, X1 - X0))
        x0, y0, x1, y1 = p.box
        c[y0 - Y0:y1 - Y0, x0 - X0:x1 - X0] = p.coverage
        covs.append(c)
    rng = np.random.default_rng(random_state)
    pts: set = set()
    size = patch
    for c in covs:
        py, px, size = patch_grid(c, patch, 10**9, rng)
        pts.update(zip(py.tolist(), px.tolist()))
    if not pts:
        return 0
    pts_a = np.array(sorted(pts))
    if len(pts_a) > max_patches:
        pts_a = pts_a[np.sort(rng.choice(len(pts_a), max_patches, replace=False))]
    py, px = pts_a[:, 0], pts_a[:, 1]
    Yp, keep = drop_clipped(take_patches(crop, py, px, size), np.arange(len(py)))
    Phi = design(size, 1)
    nll = []
    for c in covs:
        prof = PhotoProfile(Yp, take_patches(c, py, px, size)[keep, :, 0], Phi)
        nll.append(float(minimise_profile(prof, 0.995, 17, 1e-4).fun))
    return int(np.argmin(nll))


__all__ = ["most_likely"]
