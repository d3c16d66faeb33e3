"""Harmonics whose phase against the fundamental wanders on its own, and the shared phase beside them.

The shared phase (finetrack.refine_phase) combines every harmonic's phase error ``theta_k / k``
with weights ``k^2 |mean|^2 / noise``: right where each harmonic keeps one phase against the
fundamental. A harmonic whose own phase also wanders (a load that shifts its current's harmonic
phases over tens of seconds) then passes its wander, divided by ``k``, into the shared phase,
and every other harmonic ``j`` sees it multiplied by ``j``: in a comb whose harmonics each wander
by 0.1 rad, the seventh was left with more error than its own wander.

Here, after the rounds of the shared phase, each harmonic's slow phase against it (smoothed as
the correction is) is compared with the common part of the other harmonics alone (``k`` times one
fundamental error, weighted by their precision with their own wander counted: against a common
part it dominates, a strong fundamental would never show its wander and would pass it to every
other harmonic). What remains beyond the content under the line is that harmonic's own wander, of
variance ``V_k`` (rad^2). The content is measured by the slow scatter of the line's magnitude: a
voiced partial beating with a line moves its magnitude as much as its phase, a wander its phase
only. Medians over time throughout: a sweep or a loud note passing a line spins its phase for a
moment, which says nothing about a wander that lasts. A wandering harmonic then counts for
``k^2 / (noise + V_k)`` in the shared phase (a random effect per harmonic), so the shared phase
follows the harmonics that hold still and, among wandering ones, the higher (whose wander is a
smaller share of a fundamental cycle). Where no harmonic wanders by ``MIN_RAD`` and ``SIGNIF``
times what its content predicts, nothing changes.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

SIGNIF = 4.0     # own slow phase scatter this many times what noise predicts counts as wander
ROUNDS = 2       # re-estimates of the wander and the shared phase
MIN_RAD = 0.02   # RMS wander (rad) below this is left to the block fit (hum left at -34 dB of the line)
MEDIAN_CHI2 = 0.455  # median of a chi-square variable of one degree of freedom (its mean is 1)
FIXED_POINT = 8  # at most this many passes of the wander-weighted common part


def _smooth(x: np.ndarray, kern: np.ndarray) -> np.ndarray:
    """Normalised convolution along axis 0 (``nearest`` ends)."""
    return ndimage.convolve1d(x, kern / kern.sum(), axis=0, mode="nearest")


def line_noise(v: np.ndarray) -> np.ndarray:
    """Per-sample noise power of each line's decimated baseband, from successive differences
    (a slow wander adds nothing to them): the median over time, as an exponential variable's.

    Parameters
    ----------
    v : (nd, C, K) complex array
        Decimated tracked baseband (finetrack.decimated_baseband).

    Returns
    -------
    (C, K) float array

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> v = np.exp(1j * np.linspace(0, 3, 4000))[:, None, None] + 0.1 * (
    ...     rng.standard_normal((4000, 1, 1)) + 1j * rng.standard_normal((4000, 1, 1)))
    >>> round(float(line_noise(v)[0, 0]), 3)                   # 2 x 0.1^2
    0.02
    """
    d = np.abs(np.diff(v, axis=0)) ** 2
    return np.maximum(np.median(d, axis=0) / (2 * np.log(2.0)), 1e-300)


def own_wander(v: np.ndarray, ks: np.ndarray, kern: np.ndarray, present: np.ndarray) -> np.ndarray:
    """Each harmonic's own slow phase variance against the shared phase (rad^2), 0 where it is
    within ``SIGNIF`` times what the noise predicts.

    Parameters
    ----------
    v : (nd, C, K) complex array
        Decimated baseband of the harmonics ``ks`` turned by the shared phase.
    ks : (K,) array
        Harmonic numbers.
    kern : (n,) array
        The shortest smoothing kernel of the shared phase's correction.
    present : (nd,) array
        Where the hum is present (finetrack.hum_present), 0-1.

    Returns
    -------
    (C, K) float array

    Examples
    --------
    >>> rng = np.random.default_rng(1); t = np.arange(3000) / 10.0
    >>> v = np.ones((3000, 1, 3), complex)
    >>> v[:, 0, 1] = np.exp(0.3j * np.sin(2 * np.pi * t / 40))     # the second one wanders
    >>> v += 0.05 * (rng.standard_normal(v.shape) + 1j * rng.standard_normal(v.shape))
    >>> V = own_wander(v, np.array([1.0, 2.0, 3.0]), np.hanning(14)[1:-1], np.ones(3000))
    >>> bool(V[0, 0] == 0 and V[0, 2] == 0), round(float(V[0, 1]), 2)
    (True, 0.09)

    (A sinusoid's variance is 0.3^2 / 2 = 0.045; the median of its square, read as a Gaussian's,
    puts it at twice that, which only makes its weight the more cautious.)
    """
    c = v.mean(axis=0)
    noise = line_noise(v)
    turned = v * (np.conj(c) / (np.abs(c) + 1e-300))
    slow = _smooth(turned.real, kern) + 1j * _smooth(turned.imag, kern)
    on = present >= 1.0
    if on.sum() < 2 * len(kern):
        return np.zeros(c.shape)
    slow = slow[on]
    theta = np.angle(slow)                                                # rad, slow part
    # content under a line (a voiced partial beating with it) moves its magnitude as much as its
    # phase; a wander moves the phase only: the magnitude's slow scatter is the content's share
    # (medians over time, as a Gaussian's variance: a sweep or a loud note passing a line spins
    # its phase for a moment, which says nothing about a wander that lasts)
    logmag = np.log(np.maximum(np.abs(slow), 1e-300))
    radial = np.median((logmag - np.median(logmag, axis=0)) ** 2, axis=0) / MEDIAN_CHI2
    expect = float((kern ** 2).sum() / kern.sum() ** 2) * noise / (2 * np.abs(c) ** 2 + 1e-300)
    # never under 1e-12 rad^2 (a line 120 dB over its noise): a synthetic line with no noise at
    # all would get an infinite precision
    floor = np.maximum(np.maximum(expect, radial), 1e-12)
    V = np.zeros(c.shape)
    for _ in range(FIXED_POINT):
        # the part common to all harmonics (k x one fundamental error), each harmonic measured
        # against the others' common part alone, weighted by their precision with their wander
        # as estimated so far: against a common part it dominates, a harmonic never shows its
        # own wander (a strong fundamental would pass its wander to every other harmonic)
        w = ks ** 2 / (floor + V)                          # precision of theta / k (rad^-2)
        S = (w * theta / ks).sum(axis=(1, 2))
        W = float(w.sum())
        others = np.maximum(W - w, 1e-300)
        common = (S[:, None, None] - w * theta / ks) / others
        ms = np.median((theta - common * ks) ** 2, axis=0) / MEDIAN_CHI2 - ks ** 2 / others
        V_new = np.where((ms > SIGNIF * floor) & (ms - floor > MIN_RAD ** 2), ms - floor, 0.0)
        if np.array_equal(V_new > 0, V > 0) and np.allclose(V_new, V, rtol=0.05):
            return V_new
        V = V_new
    return V


def local_scatter(v: np.ndarray, c: np.ndarray, fs_d: float) -> np.ndarray:
    """Each line's scatter about its whole-input mean ``c``, averaged over 1 s: the local noise
    of the shared phase's weights (a loud note on a harmonic makes its phase worthless for a
    while, and its weight drops for that while only).

    Examples
    --------
    >>> v = np.ones((40, 1, 1), complex); v[20:] += 1.0
    >>> s = local_scatter(v, v.mean(axis=0, keepdims=True), 10.0)
    >>> s.shape, float(s[0, 0, 0]), float(s[-1, 0, 0])
    ((40, 1, 1), 0.25, 0.25)
    """
    r2 = np.abs(v - c) ** 2
    noise = ndimage.uniform_filter1d(r2, size=max(1, int(round(fs_d))), axis=0, mode="nearest")
    return np.maximum(noise, 1e-12 * np.median(r2) + 1e-300)


def wander_weights(v: np.ndarray, ks: np.ndarray, V: np.ndarray, n_min: int, fs_d: float) -> np.ndarray:
    """Per-sample weights of each harmonic's phase estimate in the shared phase, with its own
    wander counted: ``k^2 |mean|^2 / (noise + 2 |mean|^2 V n / 1.5)``. The wander does not
    average out over the ``n``-sample kernel as the noise does, hence its ``n / 1.5``.

    Parameters
    ----------
    v : (nd, C, K) complex array
        Decimated tracked baseband.
    ks : (K,) array
        Harmonic numbers.
    V : (C, K) array
        :func:`own_wander`.
    n_min : int
        Shortest kernel (decimated samples).
    fs_d : float
        Decimated sample rate (Hz).

    Returns
    -------
    (nd, C, K) float array

    Examples
    --------
    >>> v = np.ones((100, 1, 2), complex) + 0.1 * np.random.default_rng(0).standard_normal((100, 1, 2))
    >>> w = wander_weights(v, np.array([1.0, 2.0]), np.array([[0.0, 0.05]]), 12, 10.0)
    >>> bool(w[:, 0, 0].mean() > 10 * w[:, 0, 1].mean())
    True
    """
    c = v.mean(axis=0, keepdims=True)
    # the local noise as the rounds before measure it, so that a harmonic with a small wander
    # keeps nearly the weight it had there
    noise = local_scatter(v, c, fs_d)
    p = np.abs(c) ** 2
    return np.minimum(p * ks ** 2 / (noise + 2 * p * V[None] * n_min / 1.5), 1e8)
