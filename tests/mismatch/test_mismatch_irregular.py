"""Records sampled at irregular times: spectra, starting frequencies and a pickup near the system's line."""
import numpy as np
from scipy.integrate import solve_ivp

from odnn_sep.core.spectrum import is_uniform, spectrum
from odnn_sep.mismatch import explain
from odnn_sep.mismatch.calibrate import slow_cutoff
from odnn_sep.mismatch.locate import locate_frequency
from odnn_sep.mismatch.model import make_model
from odnn_sep.mismatch.presets_base import dominant_omega


def _random_times(n, T, seed):
    t = np.sort(np.random.default_rng(seed).uniform(0.0, T, n))
    t[0], t[-1] = 0.0, T
    return t


def test_uniform_times_give_the_fft_bit_for_bit():
    t = np.arange(300) * 0.01
    r = np.random.default_rng(0).normal(size=300)
    f, X = spectrum(t, r, nfft=1024, taper=True)
    assert np.array_equal(X, np.fft.rfft(r * np.hanning(300), 1024))
    assert np.array_equal(f, np.fft.rfftfreq(1024, float(np.median(np.diff(t)))))


def test_peaks_of_an_irregular_record_are_at_its_own_frequency():
    # the FFT of these samples, taken with the median spacing, put the line at about 1.44 x 3 Hz
    t = _random_times(400, 10.0, 1)
    assert not is_uniform(t)
    y = np.cos(2 * np.pi * 3.0 * t)
    assert abs(dominant_omega(t, y) / (2 * np.pi) - 3.0) < 0.02
    r = 0.2 * np.random.default_rng(2).normal(size=400) + 0.3 * np.sin(2 * np.pi * 5.0 * t)
    assert abs(locate_frequency(t, r, sigma=0.2)[0]["peak_hz"] - 5.0) < 0.1
    # the slow class stays below the oscillation (half its frequency)
    assert abs(slow_cutoff(t, y, make_model("oscillator")) - 1.5) < 0.02


def test_pickup_beating_with_an_irregularly_sampled_oscillator_is_a_disturbance():
    # a linear damped oscillator (2.66 Hz, 9 cycles, 235 random sample times) and a pickup 10 % above
    # its frequency: the slow beat was named Coulomb friction plus a cubic stiffness
    f0, T, n = 2.66, 3.38, 235
    k, c = (2 * np.pi * f0) ** 2, 0.6
    t = _random_times(n, T, 3)
    sol = solve_ivp(lambda _, s: [s[1], -k * s[0] - c * s[1]], (0, T), [0.113, 0.0], t_eval=t,
                    rtol=1e-10, atol=1e-12)
    rng = np.random.default_rng(4)
    sigma = 0.003
    y = sol.y[0] + sigma * rng.normal(size=n) + 3 * sigma * np.cos(2 * np.pi * 2.92 * t + 1.0)
    res = explain("oscillator", t, y)
    assert res.effects == []
    pk = [d for d in res.disturbances if d["effect"] == "periodic_pickup"]
    assert len(pk) == 1 and abs(pk[0]["parameters"]["omega_pk"] / (2 * np.pi) - 2.92) < 0.05


def test_a_sinusoid_near_the_own_frequency_with_the_swing_s_amplitude_is_the_swing_not_a_pickup():
    from types import SimpleNamespace as NS

    from odnn_sep.mismatch.selection import _own_line
    t = np.linspace(0, 45.0, 300)
    w = 2 * np.pi * 0.28
    cur = NS(params={"w2": w ** 2}, model=NS(family="pendulum"), prediction=0.9 * np.cos(w * t))

    def pickup(hz, amp):
        return NS(effect="periodic_pickup", fit=NS(params={"omega_pk": 2 * np.pi * hz, "a_pk": amp, "b_pk": 0.0}))
    assert not _own_line(pickup(0.30, 0.02), cur, t)     # a pickup beating with the swing
    assert _own_line(pickup(0.29, 0.5), cur, t)          # the swing itself, refitted
    assert _own_line(pickup(0.56, 0.02), cur, t)         # at a harmonic: the nonlinearity's line
    assert not _own_line(pickup(0.45, 0.5), cur, t)      # off the system's lines
    cur.model.family = "hum"
    cur.params = {"f0": 0.28}
    assert _own_line(pickup(0.30, 0.02), cur, t)         # hum does not beat: its own line is physics


def test_a_driven_oscillator_at_irregular_times_is_fitted_not_refused():
    # scipy's lsim needs equal steps: a driven model at irregular times ended in "Time steps are not
    # equally spaced"; it is now simulated on a fine uniform grid and read back at the sample times
    from odnn_sep.mismatch.inputs import linear_response
    t = _random_times(200, 20.0, 5)
    u = np.sin(0.7 * t)
    A, B = [[0.0, 1.0], [-4.0, -0.3]], [0.0, 2.0]
    ref = solve_ivp(lambda tt, s: np.array(A) @ s + np.array(B) * np.interp(tt, t, u), (0, 20), [1.0, 0.0],
                    t_eval=t, rtol=1e-11, atol=1e-12, max_step=0.01).y.T
    assert np.max(np.abs(linear_response(A, B, [1.0, 0.0], t, u) - ref)) < 1e-4
    m = make_model("oscillator", {"k": 4.0, "c": 0.3, "x0": 0.5, "v0": 0.0, "kd_u": 2.0}, inputs={"u": (t, u)})
    y = m.predict(t) + 0.01 * np.random.default_rng(6).normal(size=len(t))
    res = explain("oscillator", t, y, inputs={"u": u}, effects=["cubic_stiffness"])
    assert res.effects == []
    p = res.final_fit.params
    assert abs(p["k"] - 4.0) < 0.1 and abs(p["kd_u"] - 2.0) < 0.1
