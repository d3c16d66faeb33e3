"""Long hum recordings seen through the audio engine: the lines as low-rate complex basebands.

The hum model and its effects live in narrow bands around the harmonics ``k f0``. The audio
front-end (``odnn_sep.audio``: the 50/60 Hz decision, the phase-locked harmonics, the tracked
fundamental phase) gives a reference phase ``Phi(t) = 2 pi (f_ref t + psi(t))`` that every hum line
follows. Each harmonic ``k`` is demodulated with ``exp(-i k Phi)``, low-passed and decimated to a
few tens of Hz: a hum line becomes a nearly constant phasor, and the hum model
``a_k cos(2 pi k phi(t)) + b_k sin(...)`` becomes, exactly, ``(a_k - i b_k) exp(i k (2 pi phi(t) -
Phi(t)))`` on that grid. The fit then runs on ``2 K`` real values per low-rate time step instead
of every audio sample.

Layout of the stacked vector: value ``j`` is time step ``j // (2K)``, harmonic ``ks[(j // 2) % K]``,
real (even j) or imaginary (odd j) part, divided by that band's noise level (every band then has
unit noise, so the evidence of the selection is measured against each band's own floor). Its
"time" is ``tau0 + j * step / (2K)``: strictly increasing, within one step of the true time, so the
selection machinery (blocks for cross-validation, localisation) works unchanged.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

BASEBAND_HZ = 20.0       # low rate of each demodulated band (its usable half-width is about 8 Hz)
EXTRA_HARMONICS = 6      # the missing_harmonic effect tests harmonics H+1 .. H+6
EDGE_STEPS = 10          # low-rate steps dropped at each end (the decimation filter's transient)


@dataclass
class MainsTrack:
    """The audio engine's view of the mains: family, reference, locked harmonics, phase track.

    Examples
    --------
    >>> import numpy as np
    >>> m = MainsTrack(nominal_hz=50.0, f_ref=50.0, harmonics=[1], tc=np.array([0.0, 1.0]),
    ...                psi=np.array([0.0, 0.1]))
    >>> round(m.mean_f0(), 3), m.psi_at(np.array([0.5])).tolist()
    (50.1, [0.05])
    """

    nominal_hz: float
    f_ref: float
    harmonics: list
    tc: np.ndarray = field(repr=False)     # chunk centres (s, from the first sample)
    psi: np.ndarray = field(repr=False)    # phase of the fundamental relative to f_ref t (cycles)

    def psi_at(self, tau):
        """Tracked phase offset (cycles) at times ``tau`` (s from the first sample)."""
        return np.interp(tau, self.tc, self.psi)

    def mean_f0(self) -> float:
        """Average tracked fundamental (Hz): the reference plus the mean slope of the phase offset."""
        span = float(self.tc[-1] - self.tc[0]) if len(self.tc) > 1 else 0.0
        return float(self.f_ref + ((self.psi[-1] - self.psi[0]) / span if span > 0 else 0.0))


def track_mains(y, sr):
    """Detect and track the mains hum with the audio front-end; None when no locked hum is found.

    Parameters
    ----------
    y : ndarray (n,)
        Samples.
    sr : int
        Sample rate (Hz).

    Returns
    -------
    MainsTrack or None

    Examples
    --------
    >>> import numpy as np
    >>> sr = 2000; t = np.arange(6 * sr) / sr
    >>> y = 0.02 * np.cos(2 * np.pi * 60 * t) + np.cos(2 * np.pi * 120 * t) + 0.01 * np.random.default_rng(0).normal(size=len(t))
    >>> m = track_mains(y, sr)
    >>> m.nominal_hz, round(m.mean_f0(), 2), m.harmonics[:2]
    (60.0, 60.0, [1, 2])
    """
    from odnn_sep.audio import detect, lockcomb
    from odnn_sep.audio.finetrack import chunk_times
    from odnn_sep.audio.io import ArraySource

    src = ArraySource(y, sr)
    top = min(0.95 * sr / 2, (detect.MAX_HARMONICS + 1) * 65.0)
    spec = detect.excerpt_spectrum(src, keep_segments_hz=top + 2 * detect.FLOOR_WIDTH_HZ)
    det = detect.detect_hum(spec, sr, mains="auto", harmonics="auto")
    if not det.harmonics:
        return None
    comb = lockcomb.choose(src, spec, det, mains="auto", harmonics="auto", alpha=det.alpha, max_hz=None,
                           tones=det.tones)
    if comb is None or comb.psi is None or not comb.harmonics:
        return None
    psi = np.asarray(comb.psi, float)
    return MainsTrack(nominal_hz=float(comb.nominal_hz), f_ref=float(comb.f_ref), harmonics=list(comb.harmonics),
                      tc=chunk_times(len(psi), sr), psi=psi)


@dataclass
class Bands:
    """Demodulated, decimated harmonics: ``z[k_index, step]`` complex, on the grid ``tau`` (s).

    Examples
    --------
    >>> import numpy as np
    >>> b = Bands(ks=[1, 2], tau=np.arange(3) * 0.1, step=0.1, z=np.zeros((2, 3), complex))
    >>> b.z.shape, b.ks
    ((2, 3), [1, 2])
    """

    ks: list
    tau: np.ndarray      # low-rate times (s, absolute, as the record's t)
    step: float          # low-rate step (s)
    z: np.ndarray        # (K, M) complex basebands (2 x the low-passed demodulated samples)


def demodulate_bands(x, t0, sr, ks, mains, rate_hz=BASEBAND_HZ):
    """Each harmonic ``k`` of ``x`` at baseband: ``2 LPF[x exp(-i k Phi)]`` decimated to about ``rate_hz``.

    Parameters
    ----------
    x : ndarray (n,)
        Samples (uniform, first one at time ``t0``).
    t0 : float
        Time of the first sample (s).
    sr : int
        Sample rate (Hz).
    ks : list of int
        Harmonics to demodulate.
    mains : MainsTrack
        Reference phase.
    rate_hz : float
        Low rate (Hz).

    Returns
    -------
    Bands

    Examples
    --------
    >>> import numpy as np
    >>> sr = 1000; t = np.arange(20 * sr) / sr
    >>> mains = MainsTrack(50.0, 50.0, [1], np.array([0.0, 20.0]), np.zeros(2))
    >>> b = demodulate_bands(np.cos(2 * np.pi * 100 * t + 0.3), 0.0, sr, [1, 2], mains)
    >>> np.round(np.abs(b.z[:, 5]), 3).tolist(), round(float(np.angle(b.z[1, 5])), 3), round(1 / b.step, 1)
    ([0.0, 1.0], 0.3, 20.0)
    """
    from scipy.signal import resample_poly  # on use: the package is imported by every subcommand

    q = max(1, int(round(sr / rate_hz)))
    s = np.arange(len(x)) / sr
    # the reference phase in cycles, split so that no large number is multiplied by k then wrapped
    cyc_int = np.floor(mains.f_ref * s)
    cyc = (mains.f_ref * s - cyc_int) + mains.psi_at(s)
    out = []
    for k in ks:
        ph = 2 * np.pi * np.mod(k * cyc, 1.0)
        re = resample_poly(x * np.cos(ph), 1, q)
        im = resample_poly(-x * np.sin(ph), 1, q)
        out.append(2.0 * (re + 1j * im))
    z = np.array(out)
    m = z.shape[1]
    keep = slice(EDGE_STEPS, max(EDGE_STEPS + 1, m - EDGE_STEPS))
    tau = t0 + np.arange(m) * (q / sr)
    return Bands(ks=list(ks), tau=tau[keep], step=q / sr, z=z[:, keep])


def band_noise(z):
    """Noise level of each band's real (or imaginary) part: MAD of first differences / sqrt 2.

    Differences remove the slowly moving hum phasor, so this reads the floor under the line.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> z = 5 + 0.1 * (rng.normal(size=(1, 4000)) + 1j * rng.normal(size=(1, 4000)))
    >>> round(float(band_noise(z)[0]), 2)
    0.1
    """
    d = np.diff(z, axis=1)
    parts = np.concatenate([d.real, d.imag], axis=1)
    med = np.median(parts, axis=1, keepdims=True)
    mad = 1.4826 * np.median(np.abs(parts - med), axis=1) / np.sqrt(2.0)
    return np.maximum(mad, 1e-300)


def stack(z, sigma):
    """(K, M) complex -> (2 K M,) real: time step major, then harmonic, then real/imaginary; / sigma_k.

    Examples
    --------
    >>> import numpy as np
    >>> stack(np.array([[1 + 2j, 3 + 4j], [5 + 6j, 7 + 8j]]), np.array([1.0, 2.0])).tolist()
    [1.0, 2.0, 2.5, 3.0, 3.0, 4.0, 3.5, 4.0]
    """
    w = z / np.asarray(sigma)[:, None]
    out = np.empty((z.shape[1], z.shape[0], 2))
    out[:, :, 0] = w.real.T
    out[:, :, 1] = w.imag.T
    return out.ravel()


def hilbert_stack(z, sigma):
    """The stacked baseband of the Hilbert transform of a signal whose bands are ``z``: ``-i z``.

    Every band lies at positive frequencies, where the Hilbert transform multiplies by ``-i``.

    Examples
    --------
    >>> import numpy as np
    >>> hilbert_stack(np.array([[1 + 2j]]), np.array([1.0])).tolist()
    [2.0, -1.0]
    """
    return stack(-1j * np.asarray(z), sigma)


def notch_lines(z, step, half_hz):
    """Each band with its content within ``half_hz`` of the line (0 Hz at baseband) removed.

    The baseband counterpart of :func:`odnn_sep.mismatch.coupling.hum_free`: what is left is a
    channel's non-hum content near the harmonics.

    Examples
    --------
    >>> import numpy as np
    >>> tau = np.arange(400) * 0.05
    >>> z = (3.0 + np.exp(2j * np.pi * 4.0 * tau))[None, :]
    >>> out = notch_lines(z, 0.05, 1.0)
    >>> round(float(np.abs(out).mean()), 3)
    1.0
    """
    m = z.shape[1]
    spec = np.fft.fft(z, axis=1)
    f = np.fft.fftfreq(m, step)
    spec[:, np.abs(f) <= half_hz] = 0.0
    return np.fft.ifft(spec, axis=1)
