"""What is left of a logo in the output: edge correlation with the registered logo, against chance.

The output's gradient magnitude is correlated (Pearson, over the mark's box) with the edge map of
the logo at its registered placement. Chance: the same correlation with the logo's edge map shifted
circularly by a quarter to three quarters of the box (same edge statistics, wrong layout). The mark
counts as still visible when the correlation exceeds the chance mean by ``VISIBLE_SD`` chance
standard deviations and by at least ``VISIBLE_MIN`` in correlation. A logo placed a pixel or two off
leaves its outline as thin rims, which the correlation over the whole box can miss: the rims along the
logo's contours are counted as in text mode (``residual_rims.rims_left``, with text mode's thresholds,
fixed before logos were looked at), and rims over them also make the mark still visible.
"""
from __future__ import annotations

import numpy as np

# Chosen on development seeds of recipes/bench_logo.py (outputs with the logo removed vs inputs).
VISIBLE_SD = 4.0
VISIBLE_MIN = 0.1
N_CHANCE = 16


def _corr(a: np.ndarray, b: np.ndarray) -> float:
    a = a.ravel() - a.mean()
    b = b.ravel() - b.mean()
    return float(a @ b / (np.linalg.norm(a) * np.linalg.norm(b) + 1e-12))


def residual_mark(y: np.ndarray, out: np.ndarray, M: np.ndarray, L: np.ndarray, *, random_state=0) -> dict:
    """Edge correlation of ``out`` (and of the input ``y``) with the logo placed as ``M``, ``L``.

    All arrays cover the same box: ``y``, ``out`` (h, w, C) floats, ``M`` (h, w), ``L`` (h, w, C).
    Returns a JSON-ready dict: ``score`` (output), ``input_score``, ``chance`` and ``chance_sd``,
    ``z``, ``rim_left`` and ``rim_levels`` (``residual_rims.rims_left`` along the contours of ``M``) and
    ``visible``.

    Parameters
    ----------
    y : np.ndarray
        (h, w, C) float input crop.
    out : np.ndarray
        (h, w, C) float output crop.
    M : np.ndarray
        (h, w) coverage of the registered logo.
    L : np.ndarray
        (h, w, C) its colours.
    random_state : int or Generator, default 0
        Seed of the chance shifts.

    Returns
    -------
    dict

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> from odnn_sep.image.logo_residual import residual_mark
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> M, L, _ = render(prepare_logo(a, (64, 96), 1), Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> I = 0.3 + 0.02 * np.random.default_rng(0).standard_normal(M.shape + (1,))
    >>> y = (1 - 0.5 * M[..., None]) * I + 0.5 * M[..., None] * L
    >>> r = residual_mark(y, I, M, L)
    >>> r["visible"], r["input_score"] > 0.9, residual_mark(y, y, M, L)["visible"]
    (False, True, True)
    """
    from odnn_sep.image.logo_features import edges, logo_edges, luminance

    T = logo_edges(M, L, 1.0)
    E_out = edges(luminance(out), 1.0)
    E_in = edges(luminance(y), 1.0)
    h, w = T.shape
    rng = np.random.default_rng(random_state)
    chance = []
    for _ in range(N_CHANCE):
        dy, dx = int(rng.uniform(0.25, 0.75) * h), int(rng.uniform(0.25, 0.75) * w)
        chance.append(_corr(np.roll(T, (dy, dx), axis=(0, 1)), E_out))
    score, mean, sd = _corr(T, E_out), float(np.mean(chance)), float(np.std(chance) + 1e-6)
    z = (score - mean) / sd
    from odnn_sep.image.residual_rims import rims_left

    def as3(a):
        a = np.asarray(a, dtype=np.float64)
        return a if a.ndim == 3 else a[:, :, None]

    rim_share, rim_lv, rims = rims_left(as3(out), as3(y), [np.asarray(M, dtype=np.float64)])
    return {"score": round(score, 4), "input_score": round(_corr(T, E_in), 4), "chance": round(mean, 4),
            "chance_sd": round(sd, 4), "z": round(z, 2), "rim_left": round(rim_share, 3),
            "rim_levels": round(rim_lv, 2), "visible": bool((z > VISIBLE_SD and score - mean > VISIBLE_MIN) or rims)}
