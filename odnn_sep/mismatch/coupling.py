"""Per-channel coupling for hum: part of one channel's mismatch is a scaled copy of another channel.

In a multichannel recording, crosstalk puts a little of channel B's content into channel A. The
effect ``channel_coupling`` adds, for every other ("aux") channel ``j``,

    kappa_j * c_j(t) + kappaq_j * H[c_j](t)

to the analysed channel's hum model, where ``c_j`` is channel j's *non-hum* content and ``H`` the
Hilbert transform (the quadrature component: a small delay or phase shift of the coupled copy is
``kappa cos(phi) c + kappa sin(phi) H[c]`` to first order).

Why the aux channel's own hum is removed first: mains hum is the same physics on every channel, so
an aux channel's hum is almost collinear with the analysed channel's own hum basis. Used raw, the
coupling regressor would duplicate the hum model (and coupled hum is indistinguishable from own hum
anyway: it only changes the fitted amplitudes a_h, b_h). The regressor is therefore built from the
aux channel with its fitted hum removed (least-squares fit of the harmonics at its own refined
mains frequency), followed by a narrow band-stop around every harmonic of the mains frequency: that
removes what the fitted hum leaves behind (frequency drift, harmonics beyond the model's count)
which would otherwise correlate with the analysed channel's *own* hum mismatch and let coupling
stand in for ``frequency_drift`` or ``missing_harmonic``.
"""
from __future__ import annotations

from dataclasses import replace

import numpy as np

from odnn_sep.core.linalg import solve
from odnn_sep.errors import InputError, as_float_array

EFFECT = "channel_coupling"
# half-width of the band-stop around each harmonic: at least this many Hz, and at least
# NOTCH_CYCLES natural-resolution bins (1 / record length)
NOTCH_HZ = 1.0
NOTCH_CYCLES = 3.0


def check_aux(aux, n):
    """Validate ``aux`` (dict name -> (n,) array, or an (n, k) array) into a dict of float arrays."""
    if aux is None:
        return {}
    if isinstance(aux, np.ndarray) or not hasattr(aux, "items"):
        a = np.asarray(aux, dtype=float)
        if a.ndim == 1:
            a = a[:, None]
        if a.ndim != 2:
            raise InputError(f"aux must be a dict name -> (n,) array or an (n, k) array; got shape {a.shape}")
        aux = {f"ch{j + 1}": a[:, j] for j in range(a.shape[1])}
    out = {}
    for name, v in aux.items():
        arr = as_float_array(f"aux[{name!r}]", v, ndim=(1,))
        if len(arr) != n:
            raise InputError(f"aux[{name!r}] has {len(arr)} samples but y has {n}; aux channels must be "
                             f"sampled at the same time stamps as y")
        out[str(name)] = arr.copy()
    return out


def hum_free(t, a, *, f0, harmonics):
    """Channel ``a`` with its mains hum removed: fitted harmonics subtracted, then band-stopped.

    ``f0`` is the analysed channel's calibrated mains frequency (the start of the aux channel's own
    refinement: the grid frequency is common to all channels).
    """
    from odnn_sep.mismatch.presets_fields import Hum, hum_columns

    t = np.asarray(t, float)
    dt = float(np.median(np.diff(t)))
    nyq = 0.5 / dt
    # every harmonic of the model, and a few more when the sample rate allows (no more than 12)
    H = max(int(harmonics), min(12, int(nyq // max(f0, 1e-9)) - 1))
    H = max(H, 1)
    guess = Hum().initial_guess(t, a, {"f0": f0, "harmonics": H})
    f = guess["f0"]
    F = hum_columns(t, f, H)
    coef = np.array([guess[k] for k in Hum().amplitude_names(H)])
    r = a - F @ coef
    n = len(r)
    spec = np.fft.rfft(r)
    freqs = np.fft.rfftfreq(n, dt)
    half = max(NOTCH_HZ, NOTCH_CYCLES / max(n * dt, 1e-300))
    k = np.arange(1, int(nyq // max(f, 1e-9)) + 1)
    for fk in k * f:
        spec[np.abs(freqs - fk) <= half] = 0.0
    spec[0] = 0.0   # the mean belongs to the disturbance class, not to the coupling
    c = np.fft.irfft(spec, n)
    q = np.fft.irfft(-1j * spec, n)   # Hilbert transform: -i sign(f) on the one-sided spectrum
    return c, q


def coupling_regressors(t, aux, *, f0, harmonics):
    """{name: (in-phase, quadrature)} non-hum content of every aux channel."""
    return {name: hum_free(t, a, f0=f0, harmonics=harmonics) for name, a in aux.items()}


def param_names(regressors):
    return [p for name in regressors for p in (f"kappa_{name}", f"kappaq_{name}")]


def with_coupling(model, regressors):
    """``model`` with the ``channel_coupling`` effect: kappa_j c_j + kappaq_j H[c_j] per aux channel."""
    regs = {k: (np.asarray(c), np.asarray(q)) for k, (c, q) in regressors.items()}
    n = len(next(iter(regs.values()))[0])
    inner_builder = model.builder

    def builder(effects):
        inner = inner_builder(tuple(e for e in effects if e != EFFECT))
        if EFFECT not in effects:
            return inner

        def predict(t, p):
            if len(t) != n:
                raise InputError(f"channel_coupling is defined on the {n} time stamps of its aux channels; "
                                 f"got {len(t)}")
            out = np.asarray(inner(t, p), dtype=float)
            for name, (c, q) in regs.items():
                out = out + p[f"kappa_{name}"] * c + p[f"kappaq_{name}"] * q
            return out

        return predict

    start = dict(model.start)
    start.update({k: 0.0 for k in param_names(regs)})
    bounds = dict(model.bounds)
    bounds.update({k: (-np.inf, np.inf) for k in param_names(regs)})
    return replace(model, start=start, bounds=bounds, builder=builder, native=model.native | {EFFECT},
                   effects=model.effects + (EFFECT,))


def coupling_start(model, base, t, y, G, regressors):
    """Least-squares kappas on the calibrated residual (the effect is linear in them)."""
    cols = [v for c, q in regressors.values() for v in (c, q)]
    A = np.column_stack(cols)
    r = base.residual
    from odnn_sep.mismatch.fitting import disturbance_projector

    P = disturbance_projector(G)
    if P is not None:
        A = P.project_out(A)
    kap = solve(A, r, method="lstsq")
    s = dict(model.start)
    s.update(base.params)
    s.update(zip(param_names(regressors), (float(v) for v in kap), strict=True))
    return s
