"""The image front-end's batched opacity profile is the core engine's Subspace separation."""
import numpy as np

from odnn_sep.core import Basis, Separator, Subspace
from odnn_sep.image.estimate import _patches
from odnn_sep.image.profile import DataProfile, design
from odnn_sep.image.synth import make_watermark_demo


def test_profile_matches_core_subspace_separator():
    y, clean, truth = make_watermark_demo(random_state=1)
    M = truth["mask"]
    Yp, Mp = _patches(y / 255.0, M, 12, 25, np.random.default_rng(0))
    Phi = design(12, 1)
    alpha = 0.3
    beta, rss_p = DataProfile(Yp, Mp, Phi).parts(alpha)
    # the same model for the core: physics column M (stacked patches), disturbance in the span of
    # the block-diagonal per-patch polynomials scaled by (1 - alpha M)
    n, k = Mp.shape[1], Phi.shape[1]
    G = np.zeros((len(Mp) * n, len(Mp) * k))
    for p in range(len(Mp)):
        G[p * n:(p + 1) * n, p * k:(p + 1) * k] = (1 - alpha * Mp[p])[:, None] * Phi
    x = np.arange(len(Mp) * n, dtype=float)
    rss = 0.0
    for c in range(3):
        sep = Separator(Basis.from_matrix(Mp.reshape(-1, 1), names=["beta"]), disturbance=Subspace(G))
        r = sep.fit(x, Yp[:, :, c].ravel()).result_
        assert abs(r.theta[0] - beta[c]) < 1e-8
        rss += float(np.sum(r.residual ** 2))
    assert abs(rss - rss_p.sum()) < 1e-8 * max(1.0, rss)


def test_photo_profile_matches_core_subspace_separator():
    # photo domain: (y / u) = planes + b (M / u) with u = 1 - alpha M
    from odnn_sep.image.profile import PhotoProfile

    y, clean, truth = make_watermark_demo(random_state=9)  # colour (164, 183, 234): inside the bounds
    Yp, Mp = _patches(y / 255.0, truth["mask"], 8, 20, np.random.default_rng(0))
    Phi = design(8, 1)
    alpha = truth["alpha"]
    beta, rss_p, u = PhotoProfile(Yp, Mp, Phi).parts(alpha)
    n, k = Mp.shape[1], Phi.shape[1]
    G = np.zeros((len(Mp) * n, len(Mp) * k))
    for p in range(len(Mp)):
        G[p * n:(p + 1) * n, p * k:(p + 1) * k] = Phi
    x = np.arange(len(Mp) * n, dtype=float)
    rss = 0.0
    for c in range(3):
        sep = Separator(Basis.from_matrix((Mp / u).reshape(-1, 1), names=["beta"]), disturbance=Subspace(G))
        r = sep.fit(x, (Yp[:, :, c] / u).ravel()).result_
        assert 0.0 < r.theta[0] < alpha  # inside the colour bounds the constrained fit is the free one
        assert abs(r.theta[0] - beta[c]) < 1e-8
        rss += float(np.sum(r.residual ** 2))
    assert abs(rss - rss_p.sum()) < 1e-8 * max(1.0, rss)
