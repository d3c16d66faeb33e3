"""A splice (the hum's phase jumps at one instant) is followed at once, not smoothed over seconds."""
import numpy as np

from odnn_sep.audio import denoise
from odnn_sep.audio.phasesteps import find_steps


def _spliced(jump_cycles: float, sr=4000, dur=30.0, seed=0):
    rng = np.random.default_rng(seed)
    t = np.arange(int(dur * sr)) / sr
    host = 0.3 * rng.standard_normal(t.size)
    ph = 2 * np.pi * 50.01 * t + 2 * np.pi * jump_cycles * (t >= 15.0)
    hum = sum(np.cos(k * ph + k) / k for k in range(1, 6))
    return host, hum, sr


def _gain_db(host, hum, out):
    return 10 * np.log10(np.sum(hum ** 2) / np.sum((out - host) ** 2))


def test_hum_with_a_quarter_cycle_jump_is_removed_as_well_as_steady_hum():
    host, hum, sr = _spliced(0.25)
    g = _gain_db(host, hum, denoise(host + hum, sr).y)
    steady_host, steady_hum, _ = _spliced(0.0)
    g0 = _gain_db(steady_host, steady_hum, denoise(steady_host + steady_hum, sr).y)
    # without the step kept whole the two seconds around the jump keep the hum (about 20 dB)
    assert g > 30 and g > g0 - 8


def test_no_step_is_found_in_frequency_modulation():
    rng = np.random.default_rng(1)
    t = np.arange(600) / 10.0
    prec = np.full(600, 1 / (2 * (2 * np.pi * 2e-3) ** 2))
    for period in (5.0, 12.0, 40.0):
        e = 0.05 * np.sin(2 * np.pi * t / period) + 2e-3 * rng.standard_normal(600)
        assert find_steps(e, prec, 24) == []
    assert find_steps(0.05 * np.sin(2 * np.pi * t / 12) + 0.05 * (t >= 30), prec, 24) == [300]


def test_hum_with_a_half_cycle_jump_is_removed_as_well_as_steady_hum():
    # at half a cycle the odd harmonics flip sign and the even ones do not move: averaging the
    # harmonics' wrapped phase errors finds no step, the joint estimate does (phasejumps.py)
    for jump in (0.45, 0.6):
        host, hum, sr = _spliced(jump)
        g = _gain_db(host, hum, denoise(host + hum, sr).y)
        steady_host, steady_hum, _ = _spliced(0.0)
        g0 = _gain_db(steady_host, steady_hum, denoise(steady_host + steady_hum, sr).y)
        # (the phase is interpolated between 10 ms chunk centres, so the jump's own chunk keeps
        # some hum: a few dB below the quarter-cycle case, where fewer harmonics wrap)
        assert g > 30 and g > g0 - 10, (jump, g, g0)
    # the report says where the phase jumps (to the sample: the jump is at 15 s exactly)
    steps = denoise(host + hum, sr).info["phase_steps"]
    assert len(steps) == 1 and abs(steps[0]["time_s"] - 15.0) < 2e-3 and abs(abs(steps[0]["cycles"]) - 0.4) < 0.03


def test_no_jump_is_found_in_steady_or_modulated_lines():
    from odnn_sep.audio.phasejumps import find_jumps

    rng = np.random.default_rng(2)
    ks = np.arange(1.0, 8.0)
    t = np.arange(600)[:, None, None] / 10.0
    noise = 0.1 * (rng.standard_normal((600, 1, 7)) + 1j * rng.standard_normal((600, 1, 7)))
    steady = np.ones((600, 1, 7)) + noise
    # a level that switches (a device on and off) and a slow phase wander are not jumps
    level = steady * np.where((t > 20) & (t < 40), 0.3, 1.0)
    wander = steady * np.exp(2j * np.pi * ks * 0.05 * np.sin(2 * np.pi * t / 12))
    for v in (steady, level, wander):
        assert find_jumps(v, ks, 24) == []
    # one loud line whose phase changes (a note partial on "harmonic" 33) beside two weak ones
    # is not a jump of the comb, though delta = 0.77 matches that line and costs the others little
    high = np.array([11.0, 22.0, 33.0])
    partial = np.full((600, 1, 3), 0.3 + 0j) + noise[:, :, :3]
    partial[:, :, 2] = 20 * np.exp(2j * np.pi * 0.45 * (t[:, :, 0] >= 30)) + noise[:, :, 2]
    assert find_jumps(partial, high, 24) == []
    jumped = steady * np.exp(2j * np.pi * ks * 0.4 * (t >= 30))
    assert [(i, round(d, 1)) for i, d in find_jumps(jumped, ks, 24)] == [(300, 0.4)]


def test_a_splice_in_a_short_input_is_followed():
    # shorter than the four 2.4 s windows of the search: windows of a quarter of the input
    rng = np.random.default_rng(5)
    sr = 4000
    t = np.arange(3 * sr) / sr
    host = 0.3 * rng.standard_normal(t.size)
    ph = 2 * np.pi * 50.01 * t + np.pi * (t >= 1.5)
    hum = sum(np.cos(k * ph + k) / k for k in range(1, 6))
    assert _gain_db(host, hum, denoise(host + hum, sr).y) > 30


def test_a_splice_near_either_end_is_followed():
    rng = np.random.default_rng(3)
    sr = 4000
    t = np.arange(30 * sr) / sr
    host = 0.3 * rng.standard_normal(t.size)
    for at in (0.8, 29.2):
        ph = 2 * np.pi * 50.01 * t + np.pi * (t >= at)
        hum = sum(np.cos(k * ph + k) / k for k in range(1, 6))
        # the half-second side of the splice would otherwise keep its hum whole (about 13 dB)
        assert _gain_db(host, hum, denoise(host + hum, sr).y) > 35, at


def test_a_jump_is_found_with_two_harmonics_only():
    # EEG at 250 Hz holds 50 and 100 Hz only; a discontinuity of the recording jumps both
    from odnn_sep.audio.phasejumps import find_jumps

    rng = np.random.default_rng(4)
    ks = np.array([1.0, 2.0])
    t = np.arange(600)[:, None, None] / 10.0
    v = np.ones((600, 1, 2)) + 0.05 * (rng.standard_normal((600, 1, 2)) + 1j * rng.standard_normal((600, 1, 2)))
    v = v * np.exp(2j * np.pi * ks * 0.45 * (t >= 20))
    assert [(i, round(d, 2)) for i, d in find_jumps(v, ks, 24)] == [(200, 0.45)]


def test_many_jumps_are_followed_and_a_frequency_step_makes_none():
    rng = np.random.default_rng(7)
    sr, dur = 8000, 60
    t = np.arange(dur * sr) / sr
    host = 0.3 * rng.standard_normal(t.size)
    times = np.arange(3, dur, 3.0)                                   # a splice every 3 s
    ph = 2 * np.pi * 50.01 * t + 2 * np.pi * sum(j * (t >= a) for a, j in zip(times, rng.uniform(0, 1, times.size)))
    hum = sum(np.cos(k * ph + k) / k for k in range(1, 6))
    r = denoise(host + hum, sr)
    assert _gain_db(host, hum, r.y) > 33 and len(r.info["phase_steps"]) >= 15
    # a generator 0.05 Hz faster from 30 s on: the phase bends, it does not jump
    ph = 2 * np.pi * np.cumsum(np.where(t < 30, 50.01, 50.06)) / sr
    hum = sum(np.cos(k * ph + k) / k for k in range(1, 6))
    r = denoise(host + hum, sr)
    assert r.info["phase_steps"] == [] and _gain_db(host, hum, r.y) > 38
