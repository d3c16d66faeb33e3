"""Harmonics whose phase against the fundamental wanders on its own (ownwander.py): the shared
phase follows the fundamental's own frequency, not the harmonics' wander, and hum whose harmonics
hold still is untouched."""
import numpy as np
import pytest

from odnn_sep.audio.finetrack import refine_phase
from odnn_sep.audio.io import ArraySource
from odnn_sep.audio.track import demodulate

SR, F0, KS = 1000, 50.0, np.arange(1, 9)


def _hum(wander_rad: float, seed: int, seconds: float = 90.0):
    """A steady 50 Hz comb (amplitudes 1/k) whose harmonics each wander by ``wander_rad`` on
    their own (sinusoids of 15-40 s periods), in white noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(int(seconds * SR)) / SR
    x = 0.05 * rng.standard_normal(t.size)
    for k in KS:
        own = wander_rad * np.sin(2 * np.pi * t / rng.uniform(15, 40) + rng.uniform(0, 2 * np.pi))
        x += np.cos(2 * np.pi * k * F0 * t + rng.uniform(0, 2 * np.pi) + own) / k
    return x


def _track_error(x) -> float:
    """RMS error (rad) of the refined track at the highest harmonic, its mean removed (the true
    fundamental is steady)."""
    D = demodulate(ArraySource(x, SR), F0, KS)
    psi = refine_phase(D, SR, F0, KS, np.ones((1, len(KS))), np.zeros(len(D)))
    inner = psi[len(psi) // 10: -len(psi) // 10]          # away from the ends' one-sided kernels
    return float(np.sqrt(np.mean((inner - inner.mean()) ** 2)) * KS[-1] * 2 * np.pi)


def test_the_harmonics_own_wander_does_not_steer_the_shared_phase():
    # each harmonic weighted k^2 / (noise + its wander): the high harmonics' wander is the smaller
    # share of a fundamental cycle. With the SNR alone in the weights, the low harmonics' wander
    # reached the eighth harmonic at 0.27 rad RMS over these seeds (0.18 now; 0.12 would be the
    # best possible for this comb, on average over draws)
    assert np.mean([_track_error(_hum(0.3, seed)) for seed in (0, 1, 2)]) < 0.22


@pytest.mark.parametrize("seed", [0, 1])
def test_still_harmonics_keep_a_flat_shared_phase(seed):
    assert _track_error(_hum(0.0, seed)) < 0.015
