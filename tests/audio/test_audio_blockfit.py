"""The full-block solver (cached fixed columns, analytic tracked-comb Gram) against a float64 solve."""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import fit, fullblock, gram
from odnn_sep.audio.lines import as_combs


def test_full_block_fitter_matches_float64_least_squares():
    rng = np.random.default_rng(5)
    sr, L = 4000, 32000
    ks = [1, 2, 3, 5]
    # a second comb 0.09 Hz above the tracked one (close pairs) and a tone
    fixed = [(60.09, [1, 2, 3]), 333.3]
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    # a chunk length that does not divide the block (the last chunk is padded)
    fr = fullblock.FullBlockFitter(L, sr, ks, fixed, w, gram_step=3, chunk=3000)
    i0, centre, f0, rate, curv = 3 * 16000, 4 * 16000, 59.99, 0.002, -0.0003
    # the general basis: tracked comb in the block's reference, fixed lines in absolute time
    F = fit.block_basis(fit.BasisSpec(sr, ks, fixed), i0, L, centre, (f0, rate, curv)).astype(float)
    Y = rng.standard_normal((L, 2)) + F[:, :6] @ rng.standard_normal((6, 2))
    # the block handed over in two pieces, as the fit pass does
    theta = fr.fit(i0, centre, f0, rate, curv, [Y[: L // 2], Y[L // 2:]])
    assert theta is not None
    sw = np.sqrt(w)[:, None]
    ref = np.linalg.lstsq(F * sw, Y * sw, rcond=None)[0]
    p = fr.pm + fr.pf
    np.testing.assert_allclose(theta[:p], ref[:p], atol=2e-5 * np.abs(ref[:p]).max())
    # synthesis from the kept powers and the chunk table equals the basis times the coefficients
    z = theta[0::2] - 1j * theta[1::2]
    K = len(ks)
    hum = fr.block_hum(i0, L, z, tracked=True, slot=0)
    np.testing.assert_allclose(hum.T, F[:, :p] @ theta[:p], atol=1e-5 * np.abs(Y).max())
    # a stretch cut short (the last block of a signal)
    n = 20000
    np.testing.assert_allclose(fr.block_hum(i0, n, z, tracked=False, slot=1).T, F[:n, 2 * K:p] @ theta[2 * K:p],
                               atol=1e-5 * np.abs(Y).max())


def test_full_block_fitter_declines_harmonics_near_nyquist():
    sr, L = 1000, 16000
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    fr = fullblock.FullBlockFitter(L, sr, [1, 2, 3, 4, 5, 6, 7, 8, 9], [], w, gram_step=1)
    # harmonic 9 of 55.3 Hz is 497.7 Hz, 2.3 Hz under Nyquist: the sum-frequency terms are not
    # negligible there, so the caller must take the general path
    assert fr.fit(0, 8000, 55.3, 0.0, 0.0, np.zeros((L, 1))) is None


def test_closed_form_fixed_gram_matches_direct_sum():
    sr = 8000
    fixed = [(59.95, [2, 3, 7]), (60.002, [1, 5]), 1234.5]
    om = np.array([2 * np.pi * k * fc / sr for fc, kk in as_combs(fixed) for k in kk])
    for n in (64000, 5001):
        t = np.arange(n)
        cols = [f(np.mod(o * t, 2 * np.pi)) for o in om for f in (np.cos, np.sin)]
        F = np.stack(cols + [np.ones(n), -1 + 2 * t / (n - 1)], axis=1)
        w = np.sin(np.pi * (t + 0.5) / n) ** 2
        G = (F * w[:, None]).T @ F
        scale = np.sqrt(np.outer(np.diag(G), np.diag(G)))
        assert np.abs((gram.fixed_gram(om, n) - G) / scale).max() < 1e-11


def test_block_cut_by_the_signal_end_matches_float64_least_squares():
    rng = np.random.default_rng(6)
    sr, L, n = 4000, 32000, 21000
    ks = [1, 2, 3, 5]
    fixed = [(60.09, [1, 2, 3]), 333.3]
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    fr = fullblock.FullBlockFitter(L, sr, ks, fixed, w, gram_step=3)
    i0, centre, f0, rate, curv = 16000, 16000, 60.02, -0.001, 0.0002
    F = fit.block_basis(fit.BasisSpec(sr, ks, fixed), i0, n, centre, (f0, rate, curv)).astype(float)
    Y = 0.1 * rng.standard_normal((n, 1)) + F[:, :8] @ rng.standard_normal((8, 1))
    theta = fr.fit(i0, centre, f0, rate, curv, [Y], n=n)
    assert theta is not None
    sw = np.sqrt(np.sin(np.pi * (np.arange(n) + 0.5) / n) ** 2)[:, None]
    ref = np.linalg.lstsq(F * sw, Y * sw, rcond=None)[0]
    p = fr.pm + fr.pf
    np.testing.assert_allclose(theta[:p], ref[:p], atol=2e-5 * np.abs(ref[:p]).max())
