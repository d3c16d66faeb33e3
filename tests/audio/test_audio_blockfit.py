"""The full-block solver (cached fixed columns, analytic tracked-comb Gram) against a float64 solve."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import fit, fullblock


def test_full_block_fitter_matches_float64_least_squares():
    rng = np.random.default_rng(5)
    sr, L = 4000, 32000
    ks = [1, 2, 3, 5]
    # a second comb 0.09 Hz above the tracked one (close pairs) and a tone
    fixed = [(60.09, [1, 2, 3]), 333.3]
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    fr = fullblock.FullBlockFitter(L, sr, ks, fixed, w, gram_step=3)
    i0, centre, f0, rate, curv = 3 * 16000, 4 * 16000, 59.99, 0.002, -0.0003
    Mb = fit.block_basis(i0, L, centre, sr, f0, rate, curv, ks, [], nuisance=False).astype(float)
    R = fr.R.astype(float)
    F = np.hstack([Mb, R])
    Y = rng.standard_normal((L, 2)) + F[:, :6] @ rng.standard_normal((6, 2))
    got = fr.fit(i0, centre, f0, rate, curv, Y)
    assert got is not None
    theta, cols = got
    sw = np.sqrt(w)[:, None]
    ref = np.linalg.lstsq(F * sw, Y * sw, rcond=None)[0]
    pm, pf = fr.pm, fr.pf
    # the solver reports the fixed lines in absolute time: turn the reference the same way
    z = (ref[pm:pm + pf:2] - 1j * ref[pm + 1:pm + pf:2]) * np.exp(-1j * fr._alpha(i0))[:, None]
    ref_abs = ref[:pm + pf].copy()
    ref_abs[pm::2], ref_abs[pm + 1::2] = z.real, -z.imag
    np.testing.assert_allclose(theta[:pm + pf], ref_abs, atol=2e-5 * np.abs(ref_abs).max())
    np.testing.assert_allclose(cols, Mb, atol=1e-5)


def test_full_block_fitter_declines_harmonics_near_nyquist():
    sr, L = 1000, 16000
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    fr = fullblock.FullBlockFitter(L, sr, [1, 2, 3, 4, 5, 6, 7, 8, 9], [], w, gram_step=1)
    # harmonic 9 of 55.3 Hz is 497.7 Hz, 2.3 Hz under Nyquist: the sum-frequency terms are not
    # negligible there, so the caller must take the general path
    assert fr.fit(0, 8000, 55.3, 0.0, 0.0, np.zeros((L, 1))) is None
