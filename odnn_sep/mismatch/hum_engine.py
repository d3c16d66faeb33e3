"""The hum preset on long audio: explain() on the harmonics' basebands (see :mod:`.hum_baseband`).

``explain("hum", t, y)`` on a long uniformly sampled record (more than :data:`MIN_SAMPLES`)
detects and tracks the mains hum with the audio front-end, demodulates every harmonic the model
and its effects can touch (``1 .. H + 6``) with the tracked phase, and runs the usual selection
(forward/backward, held-out test) on the stacked low-rate basebands. Why it is right and not an
approximation: the hum model and its native effects (frequency drift, a missing harmonic), the
amplitude modulation of the output and the channel coupling are all evaluated exactly on the
basebands; only content far from the lines (more than about 8 Hz away) is left out, which no
effect of the hum preset is about.

Cases it does not take (they run on the samples, as before): short records, declared lines
(``periodic:HZ``, ``lines``), effects that live off the lines (``offset``, ``drift``,
``periodic_pickup``) when asked for explicitly, and records where the audio front-end finds no
phase-locked hum.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.mismatch.hum_baseband import (
    BASEBAND_HZ,
    EXTRA_HARMONICS,
    band_noise,
    demodulate_bands,
    hilbert_stack,
    notch_lines,
    stack,
    track_mains,
)
from odnn_sep.mismatch.hum_wander import wander_bounds, wander_cycles
from odnn_sep.mismatch.presets_base import INF, Preset

MIN_SAMPLES = 40_000            # shorter records are analysed on their samples
TARGET_VALUES = 6000            # about this many stacked values (2 per band and low-rate step)
MIN_RATE_HZ = 4.0               # ... but at least this low rate (modulations up to 1.6 Hz stay visible)
MAX_HARMONICS = 12              # model harmonics taken from the detection at most
AM_MAX_STEPS = 0.4               # highest modulation frequency seen on the bands, in units of the low rate
BAND_EFFECTS = ("missing_harmonic", "frequency_drift", "frequency_wander", "amplitude_modulation",
                "channel_coupling")


class HumBands(Preset):
    """The hum preset evaluated on the stacked basebands of :mod:`.hum_baseband` (values per band noise).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.hum_baseband import Bands, MainsTrack
    >>> mains = MainsTrack(50.0, 50.0, [1], np.array([0.0, 10.0]), np.zeros(2))
    >>> bands = Bands(ks=[1, 2], tau=np.arange(4) * 0.05, step=0.05, z=np.zeros((2, 4), complex))
    >>> pre = HumBands(bands, np.ones(2), mains, t0=0.0)
    >>> p = {"f0": 50.0, "harmonics": 1, "a1": 1.0, "b1": 0.5}
    >>> pre.build(())(pre.times(), p)[:4].tolist()    # step 0: harmonic 1 (re, im), harmonic 2 (re, im)
    [1.0, -0.5, 0.0, 0.0]
    """

    name = "hum"
    family = "hum"
    description = "mains hum on the basebands of its harmonics (audio engine)"
    params = {"f0": 50.0, "harmonics": 1}
    bounds = {"f0": (0.0, INF)}
    fixed = frozenset({"harmonics"})
    # amplitude modulation is evaluated here on the true time of each step (the generic wrapper would
    # use the stacked vector's time stamps, whose pattern across bands it could then imitate)
    native = frozenset({"missing_harmonic", "frequency_drift", "frequency_wander", "amplitude_modulation"})
    baseband = True                 # already at its analysis rate (rate.reduce_rate leaves it alone)

    def __init__(self, bands, sigma, mains, *, t0):
        self.ks = np.asarray(bands.ks, int)
        self.sigma = np.asarray(sigma, float)
        self.mains = mains
        self.tau0, self.step, self.m = float(bands.tau[0]), float(bands.step), bands.z.shape[1]
        self.t0 = float(t0)                                   # time of the record's first sample
        self.t_mid = 0.5 * (bands.tau[0] + bands.tau[-1])     # the drift's reference time
        self.coupling = {}                                    # {name: (c, q)} stacked aux regressors

    def effect_bounds(self, effect):
        """Data bounds of an effect's parameters (the wander frequency: see :func:`.hum_wander.wander_bounds`)."""
        if effect == "frequency_wander":
            return wander_bounds(self.m * self.step, self.step, AM_MAX_STEPS)
        return {}

    def times(self):
        """The stacked vector's time stamps: strictly increasing, within one step of the true time."""
        n = 2 * len(self.ks) * self.m
        return self.tau0 + np.arange(n) * (self.step / (2 * len(self.ks)))

    def _layout(self, t):
        per = 2 * len(self.ks)
        j = np.rint((np.asarray(t, float) - self.tau0) / (self.step / per)).astype(np.int64)
        return self.tau0 + (j // per) * self.step, (j // 2) % len(self.ks), j % 2

    def build(self, effects):
        effects = frozenset(effects) & self.native
        ks = self.ks

        def predict(t, p):
            tau, kk, part = self._layout(t)
            # phase of the model's fundamental relative to the demodulation reference (cycles)
            cyc = (p["f0"] - self.mains.f_ref) * tau + self.mains.f_ref * self.t0 \
                - self.mains.psi_at(tau - self.t0)
            if "frequency_drift" in effects:
                cyc = cyc + 0.5 * p["f1"] * ((tau - self.t_mid) ** 2 - (self.tau0 - self.t_mid) ** 2)
            if "frequency_wander" in effects:
                cyc = cyc + wander_cycles(tau - self.tau0, p)
            coef = np.zeros(len(ks), complex)
            H = int(p["harmonics"])
            for i, k in enumerate(ks):
                if k <= H:
                    coef[i] = p[f"a{k}"] - 1j * p[f"b{k}"]
            if "missing_harmonic" in effects:
                coef[ks == int(round(p["k_h"]))] += p["a_h"] - 1j * p["b_h"]
            z = coef[kk] * np.exp(2j * np.pi * np.mod(ks[kk] * cyc, 1.0))
            if "amplitude_modulation" in effects and p["f_am"] <= AM_MAX_STEPS / self.step:
                # faster modulations lie outside the decimated bands: they cannot be seen here
                z = z * (1.0 + p["m_am"] * np.cos(2 * np.pi * p["f_am"] * (tau - self.tau0) + p["phase_am"]))
            return np.where(part == 0, z.real, z.imag) / self.sigma[kk]

        return predict

    def initial_guess(self, t, y, p):
        from odnn_sep.core.linalg import solve
        H = int(p.get("harmonics", 1))
        names = [f"{ab}{h}" for h in range(1, H + 1) for ab in ("a", "b")]
        f0 = float(p.get("f0", self.mains.mean_f0()))
        base = {"f0": f0, "harmonics": H, **{n: 0.0 for n in names}}
        predict = self.build(())
        F = np.column_stack([predict(t, {**base, n: 1.0}) for n in names])
        coef = solve(F, y, method="lstsq")
        return {"f0": f0, **{n: float(c) for n, c in zip(names, coef, strict=True)}}


def explain_on_audio_engine(model, t, y, options):
    """explain() of a long hum record on its basebands, or None when the case is not the engine's.

    Parameters
    ----------
    model : str or Model
        ``"hum"`` or the hum preset's model (anything else: None).
    t, y : array (n,)
        Uniform time stamps (s) and samples.
    options : dict
        explain()'s keyword arguments (``params``, ``effects``, ``disturbance``, ``aux``, ``inputs``, ...).

    Returns
    -------
    MismatchResult or None

    Examples
    --------
    >>> import numpy as np
    >>> explain_on_audio_engine("cooling", np.arange(5.0), np.zeros(5), {}) is None
    True
    """
    case = _engine_case(model, t, y, options)
    if case is None:
        return None
    t, y, sr = case
    mains = track_mains(y, sr)
    if mains is None:
        return None
    from odnn_sep.mismatch.explain import explain
    m, aux_bb, notes = _band_model(t, y, sr, mains, options)
    import inspect
    own = set(inspect.signature(explain).parameters) - {"model", "t", "y", "params", "aux", "inputs", "disturbance"}
    opts = {k: v for k, v in options.items() if k in own}
    # a spike of the recording is spread over many samples of the decimated basebands: nothing
    # there is a single-sample outlier, and a line's own bursts would be taken for some
    opts["despike"] = False
    if options.get("effects") is None and not aux_bb:
        opts["effects"] = [e for e in BAND_EFFECTS if e != "channel_coupling"]
    elif options.get("effects") is None:
        opts["effects"] = list(BAND_EFFECTS)
    # explain() runs BLAS on one thread itself (core/threads.py)
    res = explain(m, m.preset.times(), m.preset.data, aux=aux_bb or None, disturbance="none", **opts)
    if str(options.get("disturbance", "auto")) == "slow":
        notes.append("--disturbance slow: the slow band lies outside the analysed bands (nothing to absorb)")
    res.notes[:0] = notes
    return res


def _engine_case(model, t, y, options):
    """(t, y, sr) as arrays when the engine takes this case, else None."""
    from odnn_sep.mismatch.model import Model
    from odnn_sep.mismatch.presets_fields import Hum
    if isinstance(model, Model):
        if not isinstance(model.preset, Hum) or model.effects:
            return None
    elif model != "hum":
        return None
    if options.get("inputs") or str(options.get("disturbance", "auto")) not in ("auto", "slow", "none"):
        return None
    eff = options.get("effects")
    if eff is not None and not set(eff) <= set(BAND_EFFECTS):
        return None
    t = np.asarray(t, float)
    y = np.asarray(y, float)
    if t.ndim != 1 or y.ndim != 1 or len(t) != len(y) or len(y) <= MIN_SAMPLES or not np.all(np.isfinite(y)):
        return None
    d = np.diff(t)
    dt = float(np.median(d))
    if dt <= 0 or np.max(np.abs(d - dt)) > 1e-3 * dt:
        return None
    return t, y, int(round(1.0 / dt))


def _band_model(t, y, sr, mains, options):
    """The baseband hum model (with the data in its preset), the aux regressors and notes in words."""
    from odnn_sep.mismatch.model import Model
    params = {k: v for k, v in (options.get("params") or {}).items() if not isinstance(v, str)}
    given_h = "harmonics" in params
    H = int(params["harmonics"]) if given_h else min(max(mains.harmonics), MAX_HARMONICS)
    ks = [k for k in range(1, H + EXTRA_HARMONICS + 1) if k * mains.f_ref + BASEBAND_HZ < 0.5 * sr]
    # a low rate that keeps the stacked vector near TARGET_VALUES (the fits' cost grows with it)
    rate = float(np.clip(TARGET_VALUES / (2 * len(ks) * float(t[-1] - t[0])), MIN_RATE_HZ, BASEBAND_HZ))
    bands = demodulate_bands(y, float(t[0]), sr, ks, mains, rate_hz=rate)
    sigma = band_noise(bands.z)
    preset = HumBands(bands, sigma, mains, t0=float(t[0]))
    preset.data = stack(bands.z, sigma)
    aux_bb = _aux_regressors(options.get("aux"), t, sr, ks, mains, sigma, preset, rate)
    start = {"f0": mains.mean_f0(), "harmonics": H}
    start.update({f"{ab}{h}": 0.0 for h in range(1, H + 1) for ab in ("a", "b")})
    start.update({k: float(v) for k, v in params.items() if k in start and k not in ("f0", "harmonics")})
    m = Model(name="hum", family="hum", start=start, bounds=dict(preset.bounds), fixed=preset.fixed,
              builder=preset.build, native=preset.native, preset=preset)
    notes = [_engine_note(mains, H, given_h, ks, bands, len(y), len(preset.data))]
    f_user = params.get("f0")
    if f_user is not None and abs(float(f_user) - mains.mean_f0()) > 1.0:
        notes.append(f"--param f0={float(f_user):g} ignored: the audio front-end tracks the mains at "
                     f"{mains.mean_f0():.3f} Hz ({mains.nominal_hz:g} Hz family)")
    return m, aux_bb, notes


def _engine_note(mains, H, given_h, ks, bands, n, n_bb):
    locked = ", ".join(str(k) for k in mains.harmonics[:12]) + (" ..." if len(mains.harmonics) > 12 else "")
    how = "as given" if given_h else "from the detection (pass --param harmonics=N to test for missing ones)"
    return (f"audio engine: {mains.nominal_hz:g} Hz mains (phase-locked harmonics {locked}; tracked fundamental "
            f"{mains.mean_f0():.4f} Hz on average); model harmonics 1..{H} {how}; harmonics {ks[0]}..{ks[-1]} "
            f"demodulated with the tracked phase and decimated to {1 / bands.step:.0f} Hz "
            f"(+-{AM_MAX_STEPS / bands.step:.1f} Hz around each line): {n_bb} values instead of {n} samples; "
            f"residuals are in units of each band's noise level")


def _aux_regressors(aux, t, sr, ks, mains, sigma, preset, rate):
    """Stacked (c, q) baseband regressors of each aux channel's non-hum content; ``{name: c}`` for explain."""
    if not aux:
        return {}
    from odnn_sep.mismatch.coupling import NOTCH_CYCLES, NOTCH_HZ, check_aux
    aux = check_aux(aux, len(t))
    half = max(NOTCH_HZ, NOTCH_CYCLES / float(t[-1] - t[0]))
    out = {}
    for name, a in aux.items():
        zb = notch_lines(demodulate_bands(a, float(t[0]), sr, ks, mains, rate_hz=rate).z, preset.step, half)
        preset.coupling[name] = (stack(zb, sigma), hilbert_stack(zb, sigma))
        out[name] = preset.coupling[name][0]
    return out
