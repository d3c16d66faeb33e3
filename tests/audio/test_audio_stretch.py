"""Pass 2's speed paths: powers per half block (stretch.py), amplitudes given by the paths, and the
file read-ahead, each against the plain computation."""
from __future__ import annotations

import numpy as np
import pytest

from odnn_sep.audio import fullblock
from odnn_sep.audio.blockplan import BlockPlan
from odnn_sep.audio.finetrack import PhaseTrack, chunk_times
from odnn_sep.audio.io import FileSource


def _fitter(L, sr, ks, fixed, phase, hop=None, n_frames=None):
    w = np.sin(np.pi * (np.arange(L) + 0.5) / L) ** 2
    fr = fullblock.FullBlockFitter(L, sr, ks, fixed, w, gram_step=1)
    fr.phase = phase
    if hop is not None:
        fr.use_stretches(hop, n_frames)
    return fr


@pytest.mark.parametrize("fixed", [[], [(60.09, [1, 2]), 333.3]])
def test_stretch_powers_give_the_block_powers_sums_and_hum(fixed):
    rng = np.random.default_rng(3)
    sr, hop = 4000, 8000
    N = 7 * hop + 1234                       # the last stretch is short
    J = -(-N // (sr // 100))
    # a wandering phase offset (cycles): drift of the fundamental by a few hundredths of a hertz
    psi = 0.02 * np.sin(2 * np.pi * chunk_times(J, sr) / 9.0) + 0.01 * chunk_times(J, sr)
    ph = PhaseTrack(psi, sr, 59.97)
    ks = [1, 2, 3, 5]
    plain = _fitter(2 * hop, sr, ks, fixed, ph)
    fast = _fitter(2 * hop, sr, ks, fixed, ph, hop, N)
    assert fast.stretches is not None
    Y = rng.standard_normal((N, 1))
    plan = BlockPlan(sr=sr, n_frames=N, hop=hop)
    for b in range(plan.count):
        i0 = max((b - 1) * hop, 0)
        n = min((b + 1) * hop, N) - i0
        fast.prepare(i0, n, b * hop, 60.0, 0.0, 0.0, slot=b % 2)       # as the worker thread does
        args = (i0, b * hop, 60.0, 0.0, 0.0, [Y[i0: i0 + n]])
        ta, tb = plain.fit(*args, n=n, slot=b % 2), fast.fit(*args, n=n, slot=b % 2)
        assert (ta is None) == (tb is None)
        if ta is None:
            continue
        np.testing.assert_allclose(tb, ta, atol=1e-5 * np.abs(ta).max())
        z = ta[0::2] - 1j * ta[1::2]
        ha = plain.block_hum(i0, n, z, tracked=True, slot=b % 2).copy()
        hb = fast.block_hum(i0, n, z, tracked=True, slot=b % 2)
        np.testing.assert_allclose(hb, ha, atol=1e-5 * np.abs(ha).max())


def test_known_tracked_amplitudes_leave_the_fixed_lines_unchanged():
    rng = np.random.default_rng(4)
    sr, L = 4000, 16000
    t = np.arange(L)
    ph = PhaseTrack(np.zeros(200), sr, 60.0)
    fr = _fitter(L, sr, [1, 2], [333.3], ph)
    Y = (np.cos(2 * np.pi * 60 * t / sr) + 0.3 * np.cos(2 * np.pi * 333.3 * t / sr + 1)
         + 0.1 * rng.standard_normal(L))[:, None]
    full = fr.fit(0, L // 2, 60.0, 0.0, 0.0, [Y])
    fr.amplitudes_given = True
    part = fr.fit(0, L // 2, 60.0, 0.0, 0.0, [Y])
    np.testing.assert_array_equal(part[4:], full[4:])     # the fixed line: the same bits
    assert np.all(part[:4] == 0.0) and np.abs(full[:2]).max() > 0.5
    only = _fitter(L, sr, [1, 2], [], ph)
    only.amplitudes_given = True
    assert np.all(only.fit(0, L // 2, 60.0, 0.0, 0.0, [Y]) == 0.0)


def test_file_read_ahead_returns_the_same_samples(tmp_path):
    sf = pytest.importorskip("soundfile", reason="sound files need soundfile")
    x = np.random.default_rng(0).uniform(-0.5, 0.5, (10007, 2))
    p = tmp_path / "a.wav"
    sf.write(p, x, 8000, subtype="FLOAT")
    src = FileSource(p)
    try:
        got = np.vstack([src.read(s, 1000) for s in range(0, 10007, 1000)])   # sequential: read ahead
        np.testing.assert_array_equal(got, x.astype(np.float32).astype(float))
        np.testing.assert_array_equal(src.read(0, 1000), got[:1000])          # off the sequence
        np.testing.assert_array_equal(src.read(1000, 500), got[1000:1500])
        np.testing.assert_array_equal(src.read(1500, 500), got[1500:2000])
        np.testing.assert_array_equal(src.read(3000, 700), got[3000:3700])    # the read-ahead not used
    finally:
        src.close()
