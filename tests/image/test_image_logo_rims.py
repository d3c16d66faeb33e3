"""A logo removed with its placement one pixel off leaves its outline as rims; the logo's residual
check (logo_residual.residual_mark) counts them, and a perfect removal stays 'removed'."""
import numpy as np
import pytest

from odnn_sep.image.logo import Placement, prepare_logo, render
from odnn_sep.image.logo_residual import residual_mark
from odnn_sep.image.residual_rims import RIM_SHARE
from odnn_sep.image.synth import photo_like


def _case(seed: int):
    """(watermarked, clean, coverage one pixel off, colours) of a 0.7-opacity logo over a photo
    crossed by a lattice of bright thin lines."""
    a = np.zeros((60, 60), np.uint8)
    a[10:50, 10:22] = 255
    a[10:22, 10:50] = 255
    a[30:40, 30:50] = 255
    M, L, _ = render(prepare_logo(a, (120, 160), 1), Placement(80, 60, 1.5, 0.0), (120, 160))
    H, W = M.shape
    photo = photo_like((H, W), random_state=seed).astype(float) / 255
    xx, yy = np.meshgrid(np.arange(W), np.arange(H))
    lines = ((np.abs(xx % 11 - 5) < 1) | (np.abs(yy % 11 - 5) < 1)) * 0.5
    clean = np.clip(0.5 * photo + 0.3 + lines[:, :, None] * np.array([1.0, 0.9, 0.7]), 0, 1)
    y = (1 - 0.7 * M[..., None]) * clean + 0.7 * M[..., None] * L
    return y, clean, M, np.roll(M, 1, axis=1), L


@pytest.mark.parametrize("seed", [0, 1])
def test_rims_of_a_logo_placed_one_pixel_off_make_it_visible(seed):
    y, clean, M, off, L = _case(seed)
    out = np.clip(clean + 0.7 * (M - off)[..., None] * (L - clean), 0, 1)
    r = residual_mark(y, out, off, L)
    assert r["z"] < 4.0                          # the edge correlation alone calls it removed
    assert r["visible"] and r["rim_left"] >= RIM_SHARE


@pytest.mark.parametrize("seed", [0, 1])
def test_a_perfect_logo_removal_is_not_called_visible(seed):
    y, clean, M, off, L = _case(seed)
    r = residual_mark(y, clean, off, L)
    assert not r["visible"] and r["rim_left"] < RIM_SHARE
