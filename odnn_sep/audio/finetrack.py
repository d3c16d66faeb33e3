"""The instantaneous hum fundamental at 0.1 s resolution, shared by all harmonics, from their phases.

The block tracker (track.py) gives one fundamental per block; it cannot follow a grid frequency that
swings within a block (sinusoidal FM with a 5 s period) and leaves that error to the block fit. Here
every harmonic's complex baseband (pass 1's chunk sums, turned by the block track's phase) is
low-passed to 10 Hz; its phase against its complex mean over the whole input is ``k`` times the
error of the track's phase at that instant (hum keeps one phase against the fundamental). The harmonics' phase errors are combined with weights
``k^2 |mean|^2 / noise`` (each harmonic's SNR: the minimum-variance combination of the ``k``-scaled
estimates) times how present the hum is at that instant (:func:`hum_present`: 0 where a switched
hum is off), low-passed to ``SMOOTH_HZ`` (zero phase) and added to the track's phase; three rounds,
the first on the low harmonics only (a phase error that is small at ``k = 1`` can wrap at ``k = 20``).

The result is one unwrapped phase of the fundamental ``psi(t)`` (cycles, relative to ``f_ref * t``)
at every chunk centre (100 per second); the block fit evaluates ``k (f_ref t + psi(t))`` at every
sample (linear interpolation: the error is below 1e-6 cycle for the drifts of real grids).
A step of the phase (a splice) would be spread over a second by that low-pass; with ``steps`` each
round's correction is smoothed piece by piece between the steps it finds (phasesteps.py).
Memory: the chunk sums are already held (J x C x K complex64); this adds a few arrays of J / 10.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

from odnn_sep.audio import lonebridge as _bridge
from odnn_sep.audio import ownwander as _own
from odnn_sep.audio import phasesteps as _steps
from odnn_sep.audio import track as _track

DECIM = 10            # chunks (10 ms) per sample of the low-passed baseband: 10 Hz
SMOOTH_HZ = 0.6       # bandwidth of the phase correction (resolution ~0.5 s)
K_CAPS = (2, 4, 8, 16, None)  # harmonics used in each round
PHASE_NOISE_DB = -50.0  # hum left by the track's phase noise, at most (weak lines: longer smoothing)
MAX_SMOOTH_S = 24.0   # longest phase-correction kernel (s)


def chunk_times(J: int, sr: int) -> np.ndarray:
    """Centres (s) of the first ``J`` 10 ms chunks of the chunk sums.

    Parameters
    ----------
    J : int
        Number of chunks.
    sr : int
        Sample rate (Hz).

    Returns
    -------
    (J,) float array

    Examples
    --------
    >>> chunk_times(3, 1000).tolist()
    [0.0045, 0.0145, 0.0245]
    """
    m = _track.chunk_length(sr)
    return (np.arange(J) * m + (m - 1) / 2) / sr


def block_track_phase(trk, tc: np.ndarray, f_ref: float, sr: int) -> np.ndarray:
    """Phase (cycles, relative to ``f_ref t``) of the block track at chunk centres ``tc``.

    Parameters
    ----------
    trk : track.Track
        The block track.
    tc : (J,) array
        Chunk centres (s), from :func:`chunk_times`.
    f_ref : float
        Reference fundamental (Hz).
    sr : int
        Sample rate (Hz).

    Returns
    -------
    (J,) float array

    Examples
    --------
    >>> from odnn_sep.audio.track import Track
    >>> z = np.zeros(2)
    >>> trk = Track(t=np.array([0.0, 4.0]), f0=np.full(2, 50.25), rate=z, curv=z,
    ...             confident=np.ones(2, bool), strength=z)
    >>> round(float(block_track_phase(trk, chunk_times(400, 1000), 50.0, 1000)[-1]), 3)
    1.0
    """
    m = _track.chunk_length(sr)
    dfreq = np.interp(tc, trk.t, trk.f0) - f_ref
    return np.cumsum(dfreq) * (m / sr)


def refine_phase(D, sr: int, f_ref: float, ks, weights, psi0: np.ndarray, *, steps: bool = False,
                 cuts: dict | None = None) -> np.ndarray:
    """Refined phase ``psi`` (cycles, at the chunk centres) of the fundamental; see the module text.

    ``D`` (J, C, K) chunk sums at ``k f_ref``; ``weights`` (C, K) inverse floor PSDs (only relative
    weights between channels of one harmonic matter: the SNR comes from the data); ``psi0`` the
    starting phase (the block track's).

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref`` (:func:`track.demodulate`).
    sr : int
        Sample rate (Hz).
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    weights : (C, K) array
        Inverse floor PSDs.
    psi0 : (J,) array
        Starting phase (cycles).
    steps : bool, default False
        Keep steps of the phase whole (a splice, a source switched over; ``phasesteps.py``):
        each round's correction is smoothed piece by piece between the steps found in it.
    cuts : dict, optional
        Steps already in ``psi0`` (phasejumps.follow: decimated index -> first chunk), kept as
        cuts in every round when ``steps``.

    Returns
    -------
    (J,) float array
        ``psi0`` itself for inputs under 16 decimated samples (1.6 s).

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1])
    >>> psi = refine_phase(D, sr, 50.0, [1], np.ones((1, 1)), np.zeros(len(D)))
    >>> round(float(psi[-1] - psi[0]), 1)                     # 0.1 Hz over 8 s
    0.8
    """
    J, C, K = D.shape
    ks = np.asarray(ks, float)
    if J // DECIM < 16:
        return psi0
    psi, known, v, err, use, w = _rounds(D, sr, ks, psi0, steps, cuts)
    tc, td = _times(J, sr)
    if K == 1:
        # a louder tone near the lone line: its phase bridged across the tone (lonebridge.py)
        return _bridge.bridged_phase(psi, w, lambda gate: _rounds(D, sr, ks, psi0, False, None, gate),
                                     tc, shortest_kernel(sr), decimated_rate(sr), steps=sorted(known))
    # the last round's baseband (every harmonic) turned by its own correction: the check for
    # wandering harmonics costs no new pass over the chunk sums where none wanders
    last = v * np.exp(-2j * np.pi * err[:, None, None] * ks[use]) if use.all() else None
    return _own_wander_rounds(D, psi, ks, tc, td, known, shortest_kernel(sr), decimated_rate(sr), last)


def decimated_rate(sr: int) -> float:
    """Sample rate (Hz) of the low-passed baseband: ``DECIM`` chunks per sample.

    Examples
    --------
    >>> decimated_rate(8000), decimated_rate(48000)
    (10.0, 10.0)
    """
    return sr / _track.chunk_length(sr) / DECIM


def _times(J: int, sr: int) -> tuple[np.ndarray, np.ndarray]:
    """(chunk centres (J,), decimated sample times (J // DECIM,)) in seconds."""
    nd = J // DECIM
    tc = chunk_times(J, sr)
    return tc, tc[: nd * DECIM].reshape(nd, DECIM).mean(axis=1)


def _rounds(D, sr: int, ks: np.ndarray, psi0: np.ndarray, steps: bool, cuts, gate=None):
    """The rounds of :func:`refine_phase` (one per ``K_CAPS``): ``(psi, steps found, last round's
    baseband, its correction, the harmonics it used, its weights (nd, C, Ku))``. ``gate(w)`` (nd,)
    multiplies each round's weights ``w`` (lonebridge.py: zero where a louder tone holds a lone
    line)."""
    J, C, K = D.shape
    nd = J // DECIM
    fs_d = decimated_rate(sr)
    tc, td = _times(J, sr)
    psi = psi0.copy()
    known: dict[int, int] = dict(cuts or {}) if steps else {}   # steps: decimated index -> first chunk after it
    n_min = shortest_kernel(sr)
    prec = harmonic_precision(_sampled_baseband(D, psi, ks, nd), ks)
    for cap in K_CAPS:
        use = np.ones(K, bool) if cap is None else ks <= cap
        if not use.any():
            use = ks == ks.min()
        use = carrying(use, ks, prec)
        v = decimated_baseband(D, psi, ks, use, nd)                                      # (nd, C, Ku)
        # each harmonic's complex amplitude over the whole input: hum keeps one phase against
        # the fundamental, so every slow or fast phase error of the track shows against it
        c = v.mean(axis=0, keepdims=True)
        noise = _own.local_scatter(v, c, fs_d)
        theta = np.angle(v * np.conj(c))                                                # rad, k x error
        w = (np.abs(c) ** 2 / noise) * ks[use] ** 2                                     # (nd, C, Ku)
        w = np.minimum(w, 1e8) * hum_present(v, fs_d)[:, None, None]
        if gate is not None:
            w = w * gate(w)[:, None, None]
        num = (w * theta / ks[use]).sum(axis=(1, 2)) / (2 * np.pi)                     # cycles x weight
        den = w.sum(axis=(1, 2))
        power = np.abs(c[0]) ** 2
        # steps found in earlier rounds stay cuts (at the chunk they were placed at): the later
        # rounds' corrections must not smooth across them either
        found = _steps.find_steps(num / np.maximum(den, 1e-300), den, 2 * n_min) if steps else []
        new = [q for q in found if all(abs(q - p) > 2 * n_min for p in known)]
        cuts = sorted([*known, *new])
        err = _steps.piecewise(lambda a, b, p=power, k=ks[use]: smoothed_correction(a, b, p, k, n_min, fs_d), num, den, cuts)
        if K == 1:
            # judged on the whole correction so far: a later round sees only what is left of a beat
            done = (psi - psi0)[: nd * DECIM].reshape(nd, DECIM).mean(axis=1)
            err = lone_line_correction(done + err, v * np.exp(2j * np.pi * done * ks[0])[:, None, None],
                                       n_min, fs_d) - done
        if new:
            known.update(zip(new, _steps.place_steps(D[:, :, use], psi, ks[use], c[0], err, new, DECIM)))
        psi = psi + _at_chunks(tc, td, err, cuts, [known[q] for q in cuts])
    return psi, known, v, err, use, w


def _own_wander_rounds(D, psi, ks, tc, td, known: dict, n_min: int, fs_d: float, v=None) -> np.ndarray:
    """Rounds of the shared phase with each harmonic's own wander counted in its weight
    (ownwander.py); ``psi`` itself where no harmonic wanders. ``v``: the decimated baseband
    of every harmonic along ``psi``, where the caller has it."""
    K = D.shape[2]
    cuts = sorted(known)
    kern = _hann(n_min)
    for _ in range(_own.ROUNDS):
        if v is None:
            v = decimated_baseband(D, psi, ks, np.ones(K, bool), len(td))
        present = hum_present(v, fs_d)
        V = _own.own_wander(v, ks, kern, present)
        if not V.any():
            break
        w = _own.wander_weights(v, ks, V, n_min, fs_d) * present[:, None, None]
        c = v.mean(axis=0, keepdims=True)
        theta = np.angle(v * np.conj(c))
        num = (w * theta / ks).sum(axis=(1, 2)) / (2 * np.pi)
        den = w.sum(axis=(1, 2))
        power = np.abs(c[0]) ** 2
        err = _steps.piecewise(lambda a, b, p=power: smoothed_correction(a, b, p, ks, n_min, fs_d), num, den, cuts)
        psi = psi + _at_chunks(tc, td, err, cuts, [known[q] for q in cuts])
        v = None
    return psi


LONE_SLOW_S = 8.0    # a lone line's correction: its part faster than this (s) is gated (lone_line_correction)
LONE_NOISE = 2.0     # magnitude scatter up to this many times its median counts as noise, not a beat


def lone_line_correction(total, v, n_min: int, fs_d: float) -> np.ndarray:
    """A lone line's phase correction (cycles, per decimated sample), with the fast part kept only
    where its phase moves more than its magnitude does.

    With one line there is no other harmonic to carry the phase: a tone 0.3-1.5 Hz from it (a bass
    note, a sweep passing) beats with it, and the 0.5 s track followed the beat while the tone
    sounded (13 dB of gain in those seconds, 40-50 dB between notes). A beat moves the line's
    magnitude and phase alike (two phasors adding); a drifting fundamental moves the phase only.
    So the correction is split at ``LONE_SLOW_S`` into a slow part, kept, and a fast part, scaled by
    ``1 - R / T``: ``T`` and ``R`` the local powers (over twice the shortest kernel) of the fast
    parts of the line's phase and of its log-magnitude, each smoothed as the correction is. ``R``
    counts only above ``LONE_NOISE`` times its median over the input: the content's ordinary
    scatter, which moves both by the same small amount everywhere, leaves the correction whole.

    Parameters
    ----------
    total : (nd,) array
        The whole correction so far (cycles): earlier rounds' and this round's.
    v : (nd, C, 1) complex array
        The line's decimated baseband along the phase before any correction (the block track's).
    n_min : int
        Shortest kernel (decimated samples).
    fs_d : float
        Decimated sample rate (Hz).

    Returns
    -------
    (nd,) float array

    Examples
    --------
    >>> rng = np.random.default_rng(0); t = np.arange(600) / 10.0
    >>> wander = 0.05 * np.sin(2 * np.pi * t / 6)                       # the fundamental moves
    >>> noise = 0.01 * (rng.standard_normal(600) + 1j * rng.standard_normal(600))
    >>> v = (np.exp(2j * np.pi * wander) + noise)[:, None, None]
    >>> bool(np.abs(lone_line_correction(wander, v, 12, 10.0) - wander).max() < 0.005)
    True
    >>> on = (t > 25) & (t < 40)                                         # a tone beats with it
    >>> beat = 0.05 * np.sin(2 * np.pi * 0.4 * t) * on
    >>> v = (1 + 0.3 * np.exp(2j * np.pi * 0.4 * t) * on + noise)[:, None, None]
    >>> bool(np.abs(lone_line_correction(beat, v, 12, 10.0)[270:380]).max() < 0.005)
    True
    """
    one = np.ones(len(total))
    k_slow = _hann(max(n_min + 1, int(round(LONE_SLOW_S * fs_d))))

    def slow(x):
        return ndimage.convolve1d(x, k_slow, axis=0, mode="constant") / \
            ndimage.convolve1d(one, k_slow, mode="constant").reshape((-1,) + (1,) * (x.ndim - 1))

    c = v.mean(axis=0)[:, 0]                                    # (C,)
    u = v[:, :, 0] / np.where(np.abs(c) > 0, c, 1.0)
    logmag = np.log(np.maximum(np.abs(u), 1e-12))
    phase = np.unwrap(np.angle(u), axis=0)
    k_min, k_loc = (k / k.sum() for k in (_hann(n_min), _hann(2 * n_min)))
    power = np.abs(c) ** 2                                      # channels weighted by their line's power
    T, R = (ndimage.convolve1d(((ndimage.convolve1d(x - slow(x), k_min, axis=0, mode="nearest")) ** 2
                                * power).sum(axis=1), k_loc, mode="nearest") for x in (phase, logmag))
    R = np.maximum(R - LONE_NOISE * np.median(R), 0.0)
    gain = np.clip(1.0 - R / np.maximum(T, 1e-300), 0.0, 1.0)
    base = slow(total)
    return base + gain * (total - base)


MIN_SHARE = 0.05     # the harmonics of a round hold at least this share of the phase's precision


def harmonic_precision(v: np.ndarray, ks: np.ndarray) -> np.ndarray:
    """Each harmonic's share of information about the fundamental's phase over the whole input:
    ``k^2 |mean|^2 / noise`` summed over channels (the weights of :func:`refine_phase`, with the
    median scatter for the noise).

    Parameters
    ----------
    v : (nd, C, K) complex array
        Decimated tracked baseband of the lines (:func:`decimated_baseband`).
    ks : (K,) array
        Harmonic numbers.

    Returns
    -------
    (K,) float array

    Examples
    --------
    >>> v = np.ones((20, 1, 2), complex); v[::2, 0, 1] += 0.5; v[1::2, 0, 1] -= 0.5
    >>> v[::2, 0, 0] += 0.1; v[1::2, 0, 0] -= 0.1
    >>> harmonic_precision(v, np.array([1.0, 3.0])).round(1).tolist()
    [100.0, 36.0]
    """
    c = v.mean(axis=0)
    noise = np.maximum(np.median(np.abs(v - c) ** 2, axis=0), 1e-300)
    return (np.abs(c) ** 2 / noise * ks ** 2).sum(axis=0)


SHARE_STRETCHES = 12      # stretches of SHARE_STRETCH_S that measure the harmonics' shares of a long input
SHARE_STRETCH_S = 10.0


def _sampled_baseband(D, psi: np.ndarray, ks: np.ndarray, nd: int) -> np.ndarray:
    """Every harmonic's decimated baseband (:func:`decimated_baseband`) over the whole input, or,
    beyond ``SHARE_STRETCHES`` x ``SHARE_STRETCH_S``, over that many evenly spaced stretches: the
    shares of :func:`harmonic_precision` need no more, and the hour's analysis is not made slower."""
    K = D.shape[2]
    width = int(round(SHARE_STRETCH_S * 100 / DECIM))      # decimated samples per stretch (10 ms chunks)
    if nd <= SHARE_STRETCHES * width:
        return decimated_baseband(D, psi, ks, np.ones(K, bool), nd)
    starts = np.linspace(0, nd - width, SHARE_STRETCHES).astype(int) * DECIM
    idx = (starts[:, None] + np.arange(width * DECIM)[None, :]).ravel()
    return decimated_baseband(D[idx], psi[idx], ks, np.ones(K, bool), len(idx) // DECIM)


def carrying(use: np.ndarray, ks: np.ndarray, prec: np.ndarray) -> np.ndarray:
    """``use`` extended, harmonic by harmonic upwards, until it holds ``MIN_SHARE`` of ``prec``.

    The first rounds of :func:`refine_phase` use the low harmonics only, so that a track's phase
    error does not wrap at a high one. Where the fundamental is weak (a rectifier's odd-dominant
    hum: the fundamental at 0.3 of the third harmonic, under 1 % of the information), that round's
    correction was the fundamental's noise: a sweep passing 50-60 Hz bent the phase of every
    harmonic by a sixth of a cycle for two seconds (0 dB of gain there), and the later rounds could
    not undo it (it wraps at the third harmonic).

    Parameters
    ----------
    use : (K,) bool array
        The harmonics a round would use.
    ks : (K,) array
        Harmonic numbers (ascending).
    prec : (K,) array
        :func:`harmonic_precision`.

    Returns
    -------
    (K,) bool array

    Examples
    --------
    >>> ks = np.array([1.0, 3.0, 5.0])
    >>> carrying(ks <= 2, ks, np.array([0.01, 9.0, 9.0])).tolist()
    [True, True, False]
    >>> carrying(ks <= 2, ks, np.array([1.0, 9.0, 9.0])).tolist()
    [True, False, False]
    """
    total = float(prec.sum())
    out = use.copy()
    for j in np.argsort(ks):
        if total <= 0 or float(prec[out].sum()) >= MIN_SHARE * total:
            break
        out[j] = True
    return out


LEVEL_ON = 0.25      # hum at this share of its on-level or more counts as fully present


def hum_present(v: np.ndarray, fs_d: float) -> np.ndarray:
    """How present the hum is at each decimated sample, 0-1: the lines' coherent power over
    1 s (less what their scatter puts in it) against the level of the hum where it is on.

    The weights of the phase estimates measure each line's noise as its scatter about the
    whole input's mean; where the hum is switched off, that scatter is the missing hum itself,
    as large as where it is on, so the content's phase (a held note's steady slope) was
    weighted as if it were the hum's and bent the track for a second around each switch.
    Where the hum is at least ``LEVEL_ON`` of its on-level (any steady hum) this is 1 and
    changes nothing.

    Parameters
    ----------
    v : (nd, C, K) complex array
        Decimated tracked baseband of the lines (:func:`decimated_baseband`).
    fs_d : float
        Its sample rate (Hz).

    Returns
    -------
    (nd,) float array

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> v = 0.05 * (rng.standard_normal((300, 1, 2)) + 1j * rng.standard_normal((300, 1, 2)))
    >>> on = (np.arange(300) >= 100) & (np.arange(300) < 200)
    >>> g = hum_present(v + on[:, None, None], 10.0)
    >>> float(g[:90].max()) < 0.05, float(g[110:190].min())
    (True, 1.0)
    >>> float(hum_present(v + 1.0, 10.0).min())
    1.0
    """
    size = max(2, int(round(fs_d)))
    loc = (ndimage.uniform_filter1d(v.real, size, axis=0, mode="nearest")
           + 1j * ndimage.uniform_filter1d(v.imag, size, axis=0, mode="nearest"))
    scatter = ndimage.uniform_filter1d(np.abs(v - loc) ** 2, size, axis=0, mode="nearest")
    of_mean = scatter / (size - 1)          # the scatter's share in the 1 s mean's power
    noise = of_mean.sum(axis=(1, 2))
    power = np.maximum(np.abs(loc) ** 2 - of_mean, 0.0).sum(axis=(1, 2))
    on_level = float(np.median(power[power >= np.quantile(power, 0.5)])) if len(power) else 0.0
    if on_level <= 0:
        return np.ones(len(power))
    # the hum is taken for off only where even its power plus twice the estimate's noise is
    # below the bar: weak lines (ECG, EEG), whose 1 s power scatters, keep their weights
    return np.minimum((power + 2.0 * noise) / (LEVEL_ON * on_level), 1.0)


def shortest_kernel(sr: int) -> int:
    """Decimated samples of the shortest phase-correction kernel (``SMOOTH_HZ`` bandwidth); twice
    it is the half-window of the step searches (phasesteps.py, phasejumps.py).

    Parameters
    ----------
    sr : int
        Sample rate (Hz).

    Returns
    -------
    int

    Examples
    --------
    >>> shortest_kernel(44100), shortest_kernel(8000)
    (12, 12)
    """
    return max(3, int(round(0.72 / SMOOTH_HZ * decimated_rate(sr))))


def _at_chunks(tc: np.ndarray, td: np.ndarray, err: np.ndarray, cuts, starts) -> np.ndarray:
    """The correction ``err`` (at the decimated times ``td``) at the chunk centres ``tc``: linear
    between samples, except across a step, which is kept sharp at its first chunk ``starts``."""
    if not cuts:
        return np.interp(tc, td, err)
    out = np.empty(len(tc))
    edges = [0, *cuts, len(td)]
    bounds = [-np.inf] + [tc[j] - 1e-9 for j in starts] + [np.inf]
    for i, (a, b) in enumerate(zip(edges[:-1], edges[1:])):
        sel = (tc >= bounds[i]) & (tc < bounds[i + 1])
        out[sel] = np.interp(tc[sel], td[a:b], err[a:b])
    return out


def phase_turn(psi: np.ndarray, k: float) -> np.ndarray:
    """``exp(-2 pi i k psi)`` in single precision: the fraction of ``k psi`` (cycles) taken in
    double precision, its cosine and sine in single. The turned chunk sums are single precision
    already, so this rounds no more than they do, at a fraction of a double complex exponential's
    cost (the analysis turns every line's chunk sums many times).

    Parameters
    ----------
    psi : (J,) float array
        Phase (cycles).
    k : float
        Harmonic number.

    Returns
    -------
    (J,) complex64 array

    Examples
    --------
    >>> psi = np.array([0.0, 0.1, 12.3456789])
    >>> bool(np.abs(phase_turn(psi, 3) - np.exp(-2j * np.pi * 3 * psi)).max() < 1e-6)
    True
    """
    cyc = psi * float(k)
    cyc -= np.rint(cyc)
    ang = (cyc * (-2 * np.pi)).astype(np.float32)
    out = np.empty(ang.shape, np.complex64)
    np.cos(ang, out=out.real)
    np.sin(ang, out=out.imag)
    return out


def decimated_baseband(D, psi: np.ndarray, ks: np.ndarray, use: np.ndarray, nd: int) -> np.ndarray:
    """The chunk sums of the harmonics ``ks[use]`` turned by ``exp(-2 pi i k psi)`` and averaged
    over DECIM chunks: (nd, C, Ku) complex128. A stretch of chunks at a time, so that the rotated
    copy of the chunk sums never exists for the whole input at once.

    Parameters
    ----------
    D : (J, C, K) complex64 array
        Chunk sums.
    psi : (J,) array
        Phase of the fundamental (cycles).
    ks : (K,) array
        Harmonic numbers of ``D``'s columns.
    use : (K,) bool array
        The columns taken.
    nd : int
        Decimated samples (``nd * DECIM <= J``).

    Returns
    -------
    (nd, C, Ku) complex128 array

    Examples
    --------
    >>> D = np.ones((40, 1, 2), np.complex64)
    >>> v = decimated_baseband(D, np.zeros(40), np.array([1.0, 2.0]), np.array([True, False]), 4)
    >>> v.shape, bool(np.allclose(v, 1.0))
    ((4, 1, 1), True)
    """
    C = D.shape[1]
    v = np.empty((nd, C, int(use.sum())), np.complex128)
    step = DECIM * (1 << 12)
    for a in range(0, nd * DECIM, step):
        b = min(a + step, nd * DECIM)
        rot = np.stack([phase_turn(psi[a:b], k) for k in ks[use]], axis=1)                # (b - a, Ku)
        vc = D[a:b][:, :, use] * rot[:, None, :]
        v[a // DECIM: b // DECIM] = vc.reshape((b - a) // DECIM, DECIM, C, -1).mean(axis=1)
    return v


def smoothed_correction(num, den, power, ks, n_min: int, fs_d: float) -> np.ndarray:
    """The phase correction (cycles, per decimated sample): the weighted estimates ``num / den``
    smoothed by a Hann kernel (:func:`local_linear`) as long as the data allow.

    The shortest kernel (``n_min`` samples: SMOOTH_HZ, so frequency modulation down to 5 s
    periods is followed) suits strong lines. Weak lines (ECG, EEG) need a longer one: the phase
    noise it passes must leave at most PHASE_NOISE_DB of the hum. A longer kernel is taken only
    while what it smooths away, compared with the shortest one, is what the phase noise alone
    predicts (within a factor 2): real modulation (FM with a 7 s period) shows as more, and then
    the shorter kernel stays. At most MAX_SMOOTH_S; the block fit's own amplitude and phase take
    up what a long kernel leaves over a block.

    ``den`` (nd,): precision of the fundamental's phase (a phase estimate's variance is
    1 / (2 den) rad^2); ``power`` (C, K): the lines' powers. A Hann kernel of n samples passes
    1.5 / n of a white phase noise's variance; harmonic k carries k times the fundamental's
    phase error.

    Parameters
    ----------
    num, den : (nd,) arrays
        Weighted phase estimates (cycles) times their precision, and the precision.
    power : (C, K) array
        The lines' powers.
    ks : (K,) array
        Harmonic numbers.
    n_min : int
        Shortest kernel (decimated samples).
    fs_d : float
        Decimated sample rate (Hz).

    Returns
    -------
    (nd,) float array

    Examples
    --------
    >>> den = np.ones(50); num = 0.01 * np.arange(50.0)       # a phase ramp, equal precision
    >>> out = smoothed_correction(num, den, np.ones((1, 1)), np.array([1.0]), 5, 10.0)
    >>> out.shape, bool(np.allclose(out, num))
    ((50,), True)
    """
    short = local_linear(num, den, _hann(n_min))
    prec = float(np.median(den)) if len(den) else 0.0
    if prec <= 0:
        return short
    g = float((power * ks[None, :] ** 2).sum() / max(power.sum(), 1e-300))
    var = 1.0 / (2 * prec) / (2 * np.pi) ** 2                       # cycles^2 per sample
    n_req = 1.5 * g / max(2 * prec * 10 ** (PHASE_NOISE_DB / 10), 1e-300)
    n_max = int(min(n_req, MAX_SMOOTH_S * fs_d, len(num) / 2))
    best, n = short, 2 * n_min
    while n <= n_max:
        cand = local_linear(num, den, _hann(n))
        expect = (1.5 / n_min - 1.5 / n) * var
        if np.mean((short - cand) ** 2) > 2 * expect:
            break
        best, n = cand, 2 * n
    return best


def _hann(n: int) -> np.ndarray:
    """Hann kernel of ``n`` samples (half-power frequency 0.72 / length)."""
    return np.hanning(n + 2)[1:-1]


def local_linear(num: np.ndarray, den: np.ndarray, kern: np.ndarray) -> np.ndarray:
    """Kernel-weighted local linear fit of the estimates ``num / den`` (weights ``den``) at every
    sample: normalised convolution of order one. Instants with little hum evidence borrow from
    their neighbours. In the interior it equals the kernel-weighted mean (a symmetric kernel
    over even weights); at the ends, where the kernel is one-sided, the local slope keeps a
    phase error that grows towards the end (a fast ramp that the block track extrapolates) from
    being pulled back towards the interior, which a weighted mean does (its lag does not shrink
    from round to round).

    Parameters
    ----------
    num, den : (n,) arrays
        Estimates times their weights, and the weights.
    kern : (w,) array
        Symmetric smoothing kernel.

    Returns
    -------
    (n,) float array

    Examples
    --------
    >>> local_linear(np.array([1.0, 2, 3, 4, 5]), np.ones(5), np.ones(3)).round(6).tolist()
    [1.0, 2.0, 3.0, 4.0, 5.0]
    """
    x = np.arange(len(num), dtype=float)
    x -= x.mean()
    conv = [ndimage.convolve1d(v, kern, mode="constant") for v in (den, den * x, den * x * x, num, num * x)]
    s0, s1, s2, b0, b1 = conv
    # the fit about each sample i: a + c (x - x_i); moments shifted to the sample
    m1 = s1 - x * s0
    m2 = s2 - 2 * x * s1 + x * x * s0
    r1 = b1 - x * b0
    det = s0 * m2 - m1 * m1
    mean = b0 / np.maximum(s0, 1e-300)
    ok = det > 1e-9 * np.maximum(s0 * m2, 1e-300)
    lin = np.where(ok, (m2 * b0 - m1 * r1) / np.where(ok, det, 1.0), mean)
    return lin


def block_params(psi: np.ndarray, tc: np.ndarray, f_ref: float, t_blocks: np.ndarray, h: float = 0.25):
    """Fundamental, rate and curvature at the block centres from the phase ``psi`` (for the parts
    of the pipeline that work per block: reports, the block-length choice, pooling).

    Parameters
    ----------
    psi : (J,) array
        Phase of the fundamental (cycles, relative to ``f_ref t``).
    tc : (J,) array
        Its times (s).
    f_ref : float
        Reference fundamental (Hz).
    t_blocks : (B,) array
        Block centres (s).
    h : float
        Half-span (s) of the phase slope.

    Returns
    -------
    f0, rate, curv : (B,) arrays
        Hz, Hz/s and Hz/s^2.

    Examples
    --------
    >>> tc = chunk_times(400, 1000)
    >>> f0, rate, curv = block_params(0.1 * tc, tc, 50.0, np.array([1.0, 2.0, 3.0]))
    >>> f0.round(3).tolist(), bool(np.allclose(rate, 0)), bool(np.allclose(curv, 0))
    ([50.1, 50.1, 50.1], True, True)
    """
    # the phase's slope over +-h (default 0.25 s, the track's resolution), not chunk to chunk
    lo, hi = np.clip(t_blocks - h, tc[0], tc[-1]), np.clip(t_blocks + h, tc[0], tc[-1])
    f_b = f_ref + (np.interp(hi, tc, psi) - np.interp(lo, tc, psi)) / np.maximum(hi - lo, 1e-9)
    h = np.diff(t_blocks).mean() if len(t_blocks) > 1 else 1.0
    rate = np.gradient(f_b, h) if len(f_b) > 1 else np.zeros_like(f_b)
    curv = np.gradient(rate, h) if len(f_b) > 2 else np.zeros_like(f_b)
    return f_b, rate, curv


class PhaseTrack:
    """Evaluates the tracked phase ``f_ref t + psi(t)`` (cycles) at sample indices.

    Parameters
    ----------
    psi : (J,) array
        Phase offset (cycles) at the chunk centres.
    sr : int
        Sample rate (Hz).
    f_ref : float
        Reference fundamental (Hz).
    jumps : sequence of (int, float), optional
        Steps of ``psi`` placed to the sample (phaseplace.to_the_sample): ``(first sample after,
        cycles)``. ``psi`` holds them between two chunk centres; they are taken out of the
        interpolation and added back sharp at their sample.

    Examples
    --------
    >>> sr = 1000; tc = chunk_times(100, sr)
    >>> ph = PhaseTrack(0.1 * tc, sr, 50.0)                 # 50.1 Hz
    >>> ph.offset_cycles(np.array([4.5, 504.5])).round(4).tolist()
    [0.0004, 0.0504]
    >>> ph.cycles(0, 3, 0).round(4).tolist(), ph.cycles_at(np.array([10.0]), 0.0).round(3).tolist()
    ([0.0, 0.05, 0.1], [0.501])
    >>> step = PhaseTrack(0.5 * (np.arange(100) >= 51), sr, 50.0, jumps=[(507, 0.5)])
    >>> step.offset_cycles(np.array([505.0, 506.0, 507.0, 508.0])).tolist()
    [0.0, 0.0, 0.5, 0.5]
    """

    def __init__(self, psi: np.ndarray, sr: int, f_ref: float, jumps=()):
        self.sr, self.f_ref = sr, float(f_ref)
        self.m = _track.chunk_length(sr)
        self.x0 = (self.m - 1) / 2                            # first chunk centre (samples)
        self.psi = np.asarray(psi, float)
        if len(self.psi) < 2:
            self.psi = np.r_[self.psi, self.psi][:2] if len(self.psi) else np.zeros(2)
        self.jumps = [(int(a), float(d)) for a, d in jumps]
        # ``psi`` stays the phase at the chunk centres, steps included (callers read it);
        # the interpolation runs on ``_smooth``, the phase with the steps taken out
        self._smooth = self.psi
        if self.jumps:
            centres = self.x0 + self.m * np.arange(len(self.psi))
            self._smooth = self.psi - sum(d * (centres >= a) for a, d in self.jumps)
        self.slope = np.diff(self._smooth)

    def _add_jumps(self, cyc: np.ndarray, i0: int) -> np.ndarray:
        """``cyc`` (contiguous samples from ``i0``) with the sharp steps added where they fall."""
        for a, d in self.jumps:
            if a - i0 < len(cyc):
                cyc[max(a - i0, 0):] += d
        return cyc

    def offset_cycles(self, idx: np.ndarray) -> np.ndarray:
        """``psi`` at sample indices (linear interpolation, held flat beyond the ends). The chunk
        centres are uniform, so the interval of each index is found by division (no search)."""
        m = self.m
        x = (np.asarray(idx, float) - self.x0) * (1.0 / m)
        np.clip(x, 0.0, len(self._smooth) - 1.0, out=x)
        j = x.astype(np.int64)
        np.minimum(j, len(self._smooth) - 2, out=j)
        x -= j
        out = self.slope[j]
        out *= x
        out += self._smooth[j]
        for a, d in self.jumps:
            out += d * (np.asarray(idx) >= a)
        return out

    def cycles(self, i0: int, n: int, centre: int, step: int = 1, scratch=None) -> np.ndarray:
        """Phase in cycles at samples ``i0, i0 + step, ...`` (n samples) relative to the phase at
        ``centre``: ``f_ref (i - centre) / sr + psi(i) - psi(centre)``. ``scratch`` (a key, e.g.
        0 or 1): the result may be a view of a work array kept by the track under that key,
        valid until the next call with the same key (the same values, without fresh arrays of
        the block's length; two threads use two keys)."""
        if scratch is not None and step == 1:
            cyc = self._cycles_scratch(i0, n, centre, scratch)
            if cyc is not None:
                return cyc
        if step != 1:
            return self.cycles_at(np.arange(i0, i0 + n, step, dtype=float), centre)
        # contiguous samples: on the grid of chunk centres x0 + j m the interpolant is
        # psi_j + slope_j r / m for the r-th sample after centre j: one broadcast add per block
        m, x0 = self.m, self.x0
        first = int(np.floor((i0 - x0) / m))
        last = int(np.floor((i0 + n - 1 - x0) / m)) + 1
        lo, hi = max(first, 0), min(last, len(self._smooth) - 1)
        if hi - lo < 2 or first < 0 or last > len(self._smooth) - 1:
            return self.cycles_at(np.arange(i0, i0 + n, dtype=float), centre)
        c0 = int(np.ceil(x0))              # first sample at or after a chunk centre
        r = (np.arange(m) + (c0 - x0)) * (1.0 / m)
        grid = self._smooth[lo:hi, None] + self.slope[lo:hi, None] * r[None, :]
        start = i0 - (c0 + lo * m)
        psi_s = grid.reshape(-1)[start: start + n] if start >= 0 else grid[:0].reshape(-1)
        if psi_s.shape[0] != n:
            return self.cycles_at(np.arange(i0, i0 + n, dtype=float), centre)
        cyc = np.arange(i0 - centre, i0 - centre + n, dtype=float)
        cyc *= self.f_ref / self.sr
        cyc += psi_s
        cyc -= float(self.offset_cycles(np.array([float(centre)]))[0])
        return self._add_jumps(cyc, i0)

    def _cycles_scratch(self, i0: int, n: int, centre: int, key):
        """:meth:`cycles` for contiguous samples inside the track, operation for operation, in a
        work array kept between calls; the time ramp ``(i - centre) f_ref / sr`` is kept too
        (every full block has the same offsets). None where :meth:`cycles` takes another path."""
        m, x0 = self.m, self.x0
        first = int(np.floor((i0 - x0) / m))
        last = int(np.floor((i0 + n - 1 - x0) / m)) + 1
        lo, hi = max(first, 0), min(last, len(self._smooth) - 1)
        c0 = int(np.ceil(x0))
        start = i0 - (c0 + lo * m)
        if hi - lo < 2 or first < 0 or last > len(self._smooth) - 1 or start < 0 or start + n > (hi - lo) * m:
            return None
        r = (np.arange(m) + (c0 - x0)) * (1.0 / m)
        scratch = self.__dict__.setdefault("_scratch", {})       # (atomic: two threads may call)
        work = scratch.get(key)
        if work is None or work.size < (hi - lo) * m:
            work = scratch[key] = np.empty((hi - lo) * m)
        grid = work[: (hi - lo) * m].reshape(hi - lo, m)
        np.multiply(self.slope[lo:hi, None], r[None, :], out=grid)
        np.add(self._smooth[lo:hi, None], grid, out=grid)
        ramp_key, ramp = scratch.get("ramp", (None, None))      # shared by the keys: read as one pair
        if ramp_key != (i0 - centre, n):
            ramp_key = (i0 - centre, n)
            ramp = np.arange(i0 - centre, i0 - centre + n, dtype=float)
            ramp *= self.f_ref / self.sr
            scratch["ramp"] = (ramp_key, ramp)
        cyc = grid.reshape(-1)[start: start + n]
        cyc += ramp                 # (i - centre) f_ref / sr + psi(i): the sum of cycles(), in place
        cyc -= float(self.offset_cycles(np.array([float(centre)]))[0])
        return self._add_jumps(cyc, i0)

    def cycles_at(self, idx: np.ndarray, centre: float) -> np.ndarray:
        """As :meth:`cycles` at (possibly fractional) sample positions ``idx``."""
        cyc = (idx - centre) * (self.f_ref / self.sr)
        cyc += self.offset_cycles(idx) - float(self.offset_cycles(np.array([float(centre)]))[0])
        return cyc


def track_from_phase(psi: np.ndarray, f_ref: float, plan, jumps=()):
    """A :class:`track.Track` for the blocks of ``plan`` (a blockplan.BlockPlan) whose phase is
    ``psi`` (the per-block fundamental, rate and curvature follow from it).

    Parameters
    ----------
    psi : (J,) array
        Phase of the fundamental (cycles, relative to ``f_ref t``) at the chunk centres.
    f_ref : float
        Reference fundamental (Hz).
    plan : BlockPlan
        The blocks.
    jumps : sequence of (int, float), optional
        Steps of ``psi`` placed to the sample (:class:`PhaseTrack`).

    Returns
    -------
    track.Track
        Every block confident, with ``phase`` a :class:`PhaseTrack`.

    Examples
    --------
    >>> from odnn_sep.audio.blockplan import BlockPlan
    >>> plan = BlockPlan.from_block_s(4.0, 1000, 8000)
    >>> trk = track_from_phase(0.1 * chunk_times(800, 1000), 50.0, plan)
    >>> trk.t.tolist(), trk.f0.round(3).tolist(), trk.phase.f_ref
    ([0.0, 2.0, 4.0, 6.0, 8.0], [50.1, 50.1, 50.1, 50.1, 50.1], 50.0)
    """
    sr, hop, nb = plan.sr, plan.hop, plan.count
    t = plan.centres_s
    tc = chunk_times(len(psi), sr)
    # per block: the mean frequency over the middle half of the block (reports, comb masks)
    f0, rate, curv = block_params(psi, tc, f_ref, t, h=max(0.25, 0.5 * hop / sr))
    ones = np.ones(nb)
    return _track.Track(t=t, f0=f0, rate=rate, curv=curv, confident=np.ones(nb, bool), strength=ones,
                        phase=PhaseTrack(psi, sr, f_ref, jumps))
