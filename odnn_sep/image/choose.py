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

    ``y``: the whole image as float (H, W, C) in [0, 1] (or a view giving float crops)."""
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
