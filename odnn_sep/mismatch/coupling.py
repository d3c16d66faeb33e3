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
    """Validate ``aux`` (dict name -> (n,) array, or an (n, k) array) into a dict of float arrays.

    Parameters
    ----------
    aux : dict, ndarray or None
        Other channels; the columns of an array are named ``ch1``, ``ch2``, ...
    n : int
        Number of samples of the analysed channel.

    Returns
    -------
    dict
        ``{name: (n,) float array}`` (empty for None).

    Examples
    --------
    >>> import numpy as np
    >>> list(check_aux(np.zeros((3, 2)), 3)), check_aux(None, 3)
    (['ch1', 'ch2'], {})
    """
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

    Parameters
    ----------
    t : ndarray
        Sample times (s).
    a : ndarray
        The aux channel.
    f0 : float
        Mains frequency (Hz).
    harmonics : int
        Harmonics of the hum model (more are removed when the sample rate allows).

    Returns
    -------
    c, q : ndarray
        In-phase content and its Hilbert transform.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 200.0   # 2 s at 200 Hz
    >>> b = np.sin(2 * np.pi * 50 * t) + 0.5 * np.sin(2 * np.pi * 7 * t)   # hum + its own 7 Hz content
    >>> c, q = hum_free(t, b, f0=50.0, harmonics=1)
    >>> round(float(np.corrcoef(c, np.sin(2 * np.pi * 7 * t))[0, 1]), 3), c.shape == q.shape
    (1.0, True)
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
    """{name: (in-phase, quadrature)} non-hum content of every aux channel.

    Parameters
    ----------
    t : ndarray
        Sample times (s).
    aux : dict
        ``{name: samples}`` (:func:`check_aux`).
    f0 : float
        Mains frequency (Hz).
    harmonics : int
        Harmonics of the hum model.

    Returns
    -------
    dict
        ``{name: (c, q)}`` from :func:`hum_free`.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 200.0   # 2 s at 200 Hz
    >>> b = np.sin(2 * np.pi * 50 * t) + 0.5 * np.sin(2 * np.pi * 7 * t)   # hum + its own 7 Hz content
    >>> regs = coupling_regressors(t, {"B": b}, f0=50.0, harmonics=1)
    >>> list(regs), len(regs["B"])
    (['B'], 2)
    """
    return {name: hum_free(t, a, f0=f0, harmonics=harmonics) for name, a in aux.items()}


def param_names(regressors):
    """Coupling gains of the aux channels: ``kappa_<name>`` and ``kappaq_<name>`` each.

    Parameters
    ----------
    regressors : dict
        ``{name: (c, q)}`` (only the names are used).

    Returns
    -------
    list of str

    Examples
    --------
    >>> param_names({"B": None, "C": None})
    ['kappa_B', 'kappaq_B', 'kappa_C', 'kappaq_C']
    """
    return [p for name in regressors for p in (f"kappa_{name}", f"kappaq_{name}")]


def with_coupling(model, regressors):
    """``model`` with the ``channel_coupling`` effect: kappa_j c_j + kappaq_j H[c_j] per aux channel.

    Parameters
    ----------
    model : Model
        The hum model.
    regressors : dict
        ``{name: (c, q)}`` from :func:`coupling_regressors`.

    Returns
    -------
    Model
        The model with the effect and its gains (start 0).

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 200.0   # 2 s at 200 Hz
    >>> b = np.sin(2 * np.pi * 50 * t) + 0.5 * np.sin(2 * np.pi * 7 * t)   # hum + its own 7 Hz content
    >>> from odnn_sep.mismatch.model import make_model
    >>> m = with_coupling(make_model("hum"), coupling_regressors(t, {"B": b}, f0=50.0, harmonics=1))
    >>> m.effects, [k for k in m.start if k.startswith("kappa")], m.predict(t).shape
    (('channel_coupling',), ['kappa_B', 'kappaq_B'], (400,))
    """
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
    """Least-squares kappas on the calibrated residual (the effect is linear in them).

    Parameters
    ----------
    model : Model
        The model with the coupling (:func:`with_coupling`).
    base : Fit
        Calibration without it.
    t, y : ndarray
        Sample times and samples.
    G : ndarray or None
        Disturbance columns.
    regressors : dict
        ``{name: (c, q)}``.

    Returns
    -------
    dict
        Starting values: the calibrated parameters plus the least-squares gains.

    Examples
    --------
    >>> import numpy as np
    >>> t = np.arange(400) / 200.0   # 2 s at 200 Hz
    >>> b = np.sin(2 * np.pi * 50 * t) + 0.5 * np.sin(2 * np.pi * 7 * t)   # hum + its own 7 Hz content
    >>> from odnn_sep.mismatch.fitting import fit
    >>> from odnn_sep.mismatch.model import make_model
    >>> regs = coupling_regressors(t, {"B": b}, f0=50.0, harmonics=1)
    >>> m = make_model("hum", {"a1": 1.0})
    >>> y = np.cos(2 * np.pi * 50 * t) + 0.1 * regs["B"][0]   # 10 % crosstalk from B
    >>> s = coupling_start(with_coupling(m, regs), fit(m, t, y), t, y, None, regs)
    >>> round(s["kappa_B"], 3), round(s["kappaq_B"], 3)
    (0.1, 0.0)
    """
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
