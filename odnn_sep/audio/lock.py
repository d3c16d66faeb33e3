"""Is a line hum? Only when it is phase-locked to ``k`` times the tracked fundamental and persists.

On the tracked baseband (pass 1's chunk sums turned by ``exp(-2 pi i k psi)``, ``psi`` the tracked
phase, finetrack.py) a hum harmonic is a steady phasor for the whole recording. The test cuts it
into 4 s Hann segments (50 % overlap) and asks whether the segments' complex means share one
non-zero mean: ``X = |mean|^2 / (scatter / S)``, F-distributed with (2, 2 (S - 1)) degrees of freedom
when the segments are independent circular noise (overlap: S counted as S / 1.33).

A note partial near a harmonic fails on both counts: it starts and stops (most segments hold none
of it) and it does not follow the drift, so its phase against the track turns from segment to
segment; a 4 s Hann segment also suppresses a partial 0.5-3 Hz away (2-12 window bins) by 30 dB
or more. Music that happens to repeat a pitch near a harmonic therefore scatters around zero.
"""
from __future__ import annotations

import numpy as np
from scipy import special

from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import track as _track

SEG_S = 4.0
SHORT_SEG_S = 0.1       # shortest segment of the lock test (inputs under ~2 s; 0.6 s and up)
OVERLAP_VAR = 1.33      # variance of the mean of 50 %-overlapped Hann segments over iid segments


def segment_phasors(u: np.ndarray, sr: int, seg_s: float = SEG_S) -> np.ndarray:
    """Hann-weighted complex means of ``u`` (J, ...) over segments of ``seg_s`` (50 % overlap):
    (S, ...). The segments are two interleaved sets of back-to-back ones (one product each).

    Parameters
    ----------
    u : (J, ...) complex array
        A baseband at the chunk rate (100 per second).
    sr : int
        Sample rate of the audio it came from (Hz).
    seg_s : float
        Segment length (s); at most the whole input.

    Returns
    -------
    (S, ...) complex array
        In time order.

    Examples
    --------
    >>> u = np.ones((1000, 2), complex)                     # 10 s of a steady phasor
    >>> a = segment_phasors(u, 8000)
    >>> a.shape, np.allclose(a, 1.0)
    ((4, 2), True)
    """
    fs = sr / _track.chunk_length(sr)
    n = int(round(seg_s * fs))
    J = u.shape[0]
    n = max(2, min(n, J))
    w = np.hanning(n + 2)[1:-1]
    w = (w / w.sum()).astype(np.float32 if u.dtype == np.complex64 else float)
    out = []
    for off in (0, n // 2):
        S = (J - off) // n
        if S < 1:
            continue
        seg = u[off: off + S * n].reshape((S, n) + u.shape[1:])
        out.append((off, np.tensordot(w, seg, axes=(0, 1))))          # (S, ...)
    # in time order: the two sets interleave
    starts = sorted((off + i * n, a[i]) for off, a in out for i in range(a.shape[0]))
    return np.stack([a for _, a in starts])


def lock_p_values(u: np.ndarray, sr: int) -> tuple[np.ndarray, np.ndarray]:
    """P-value (per column of ``u`` (J, C, K), channels pooled) that the tracked baseband has a
    steady non-zero mean, and the phase-lock index ``|mean| / rms`` of the segment phasors (1 for
    a perfectly locked line, ~1/sqrt(S) for noise).

    Parameters
    ----------
    u : (J, C, K) complex array
        Tracked baseband (chunk sums turned by the tracked phase).
    sr : int
        Sample rate of the audio (Hz).

    Returns
    -------
    p : (K,) array
    index : (K,) array

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> noise = rng.standard_normal((2000, 1, 2)) + 1j * rng.standard_normal((2000, 1, 2))
    >>> u = noise + np.array([3.0, 0.0])                  # column 0 holds a steady line
    >>> p, index = lock_p_values(u, 8000)
    >>> bool(p[0] < 1e-6), bool(p[1] > 1e-3), bool(index[0] > 0.9)
    (True, True, True)
    """
    # 4 s segments; shorter on short inputs, so that there are at least ~11 of them
    dur = u.shape[0] * _track.chunk_length(sr) / sr
    a = segment_phasors(u, sr, seg_s=float(np.clip(dur / 6, 1.0, SEG_S)))          # (S, C, K)
    if a.shape[0] < 3 and dur / 6 >= SHORT_SEG_S:
        # under about 2 s, 1 s segments leave too few to test: shorter ones. What tells a
        # steady line from a note partial beside it is the input's length (a partial 1/dur Hz
        # off turns a full cycle), not the segments', so the test keeps its meaning
        a = segment_phasors(u, sr, seg_s=dur / 6)
    S = a.shape[0]
    if S < 3:
        lock_p_values.last_amp = np.zeros(u.shape[2])
        return np.ones(u.shape[2]), np.zeros(u.shape[2])
    mean = a.mean(axis=0)                                        # (C, K)
    scat = (np.abs(a - mean) ** 2).sum(axis=0) / (S - 1)         # (C, K)
    s_eff = max(2.0, S / OVERLAP_VAR)
    # single-precision phasors: 1e-300 is 0 there, so a line with no scatter at all (a synthetic
    # tone without noise) divides by zero; its statistic is infinite (p = 0), as it should be
    with np.errstate(divide="ignore", invalid="ignore"):
        x = (np.abs(mean) ** 2 / np.maximum(scat / s_eff, 1e-300))   # per channel
    # a silent channel (a flat EEG electrode: zero mean and zero scatter) shows no line
    x = np.where(np.isnan(x), 0.0, x)
    # channels pooled: mean of the per-channel statistics, F(2C, 2 C (S_eff - 1)) approximately for
    # independent channels; channels that carry the same content are one piece of evidence
    # (C counted as the effective number of independent channels)
    xf = x.mean(axis=0)
    C = effective_channels(u).astype(xf.dtype)     # in the statistic's precision (float32 phasors stay so)
    d1, d2 = 2.0 * C, 2.0 * C * (s_eff - 1)
    p = special.fdtrc(d1, d2, xf)
    rms = np.sqrt((np.abs(a) ** 2).mean(axis=0)).mean(axis=0)
    lock_p_values.last_amp = np.abs(mean).mean(axis=0)
    index = np.abs(mean).mean(axis=0) / np.maximum(rms, 1e-300)
    return p, index


def locked(D, sr: int, ks, psi: np.ndarray, *, alpha: float):
    """Harmonics of ``ks`` (columns of the chunk sums ``D``) whose tracked baseband is phase-locked
    at level ``alpha`` (one test per line: it tells hum from a note partial on a line already
    shown to be significant), and per harmonic ``(p, lock_index, amplitude)`` (amplitude: modulus
    of the mean tracked baseband, in chunk-sum units).

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref`` (:func:`track.demodulate`).
    sr : int
        Sample rate (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    psi : (J,) float array
        Tracked phase of the fundamental (cycles, relative to ``f_ref t``).
    alpha : float
        Significance level of each test.

    Returns
    -------
    keep : list of int
    info : dict
        Harmonic -> ``(p, lock_index, amplitude)``.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> psi = 0.1 * (np.arange(len(D)) * 10 + 4.5) / sr     # the 0.1 Hz offset, in cycles
    >>> keep, info = locked(D, sr, [1, 2], psi, alpha=1e-3)
    >>> keep, round(info[1][1], 2)
    ([1], 1.0)
    """
    ks_a = np.asarray(ks, float)
    p, idx, amp = np.ones(len(ks)), np.zeros(len(ks)), np.zeros(len(ks))
    for i, k in enumerate(ks_a):
        # one harmonic at a time: a few arrays of the baseband's length, whatever the count
        rot = _finetrack.phase_turn(psi, k)
        p[i: i + 1], idx[i: i + 1] = lock_p_values(D[:, :, i: i + 1] * rot[:, None, None], sr)
        amp[i] = lock_p_values.last_amp[0]
    keep = [int(k) for k, pv in zip(ks, p, strict=True) if pv < alpha]
    return keep, {int(k): (float(pv), float(ix), float(am)) for k, pv, ix, am in zip(ks, p, idx, amp, strict=True)}


WEIGHTED_SEG_S = 1.0    # units of the weighted test (s): short, so speech pauses and rests between notes count


# The chunks are summed with their weights over 1 s units; the test is the same F test on the units'
# weighted sums (|sum|^2 over their scatter about the weighted mean, which is its own calibration: the
# weights only set the relative precision of the units). The weights depend on the content's power
# only, never on its phase, so circular content still has mean zero.
def weighted_lock_p_values(u: np.ndarray, sr: int, presence: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Like :func:`lock_p_values`, with every chunk weighted by the inverse of the content power near
    the line at that moment, whatever its offset (:func:`odnn_sep.audio.nearpower.near_power`): the generalised
    least-squares mean of the tracked baseband, which takes the pauses of speech and the rests
    between notes at their worth. A weak harmonic under bursty content is then clear where the
    equal-weight test (whose 4 s segments each hold some of the bursts) sees nothing.

    Parameters
    ----------
    u : (J, C, K) complex array
        Tracked baseband (chunk sums turned by the tracked phase).
    sr : int
        Sample rate of the audio (Hz).
    presence : (J,) array, optional
        Where the hum is on (1) and off (0), from other lines (:func:`presence`): a further
        factor of the weights, so a hum switched off for half the input is tested where it is.
        It must not depend on the tested line's phase (the test then stays calibrated).

    Returns
    -------
    p : (K,) array
        P-values (channels pooled).
    amp : (K,) array
        Modulus of the weighted mean (chunk-sum units), mean over channels.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> noise = rng.standard_normal((3000, 1, 2)) + 1j * rng.standard_normal((3000, 1, 2))
    >>> loud = (np.arange(3000) // 200) % 2 == 0           # bursts: 2 s on, 2 s off, 30 times louder
    >>> noise[loud] *= 30.0
    >>> p, amp = weighted_lock_p_values(noise + np.array([0.5, 0.0]), 8000)
    >>> bool(p[0] < 1e-6), bool(p[1] > 1e-3), round(float(amp[0]), 1)
    (True, True, 0.5)
    >>> bool(lock_p_values(noise + np.array([0.5, 0.0]), 8000)[0][0] > 1e-3)   # equal weights: not seen
    True
    """
    from odnn_sep.audio.nearpower import near_power

    J, C, K = u.shape
    fs = sr / _track.chunk_length(sr)
    n = max(2, int(round(WEIGHTED_SEG_S * fs)))
    B = J // n
    if B < 6:
        return np.ones(K), np.zeros(K)
    x = np.zeros(K)
    amp = np.zeros(K)
    for c in range(C):
        for i in range(K):
            v = u[: B * n, c, i].astype(np.complex128)
            w = 1.0 / near_power(v, fs)
            if presence is not None:
                w = w * presence[: B * n]
            Y = (w * v).reshape(B, n).sum(axis=1)
            W = w.reshape(B, n).sum(axis=1)
            if presence is not None:
                Y, W = Y[W > 0], W[W > 0]             # units where the hum is off carry nothing
                if len(Y) < 6:
                    continue
            m = Y.sum() / W.sum()
            Bu = len(Y)
            scat = (np.abs(Y - W * m) ** 2).sum() / (Bu - 1)
            # Var(sum Y) is B times a unit's variance; the weighted sum's |.|^2 over that
            x[i] += np.abs(Y.sum()) ** 2 / max(Bu * scat, 1e-300) / C
            amp[i] += np.abs(m) / C
    if presence is not None:
        B = int((presence[: B * n].reshape(B, n).sum(axis=1) > 0).sum())
        if B < 6:
            return np.ones(K), np.zeros(K)
    Ce = effective_channels(u)
    p = special.fdtrc(2.0 * Ce, 2.0 * Ce * (B - 1), x)
    return p, amp


def effective_channels(u: np.ndarray) -> np.ndarray:
    """How many independent channels the baseband ``u`` (J, C, K) holds, per column: ``C^2 / sum_ij
    |r_ij|^2`` of the channels' complex correlations ``r`` about their means (Bretherton et al. 1999);
    C for uncorrelated channels, 1 for identical ones.

    The pooled lock tests add the channels' statistics as independent evidence. Four or eight
    copies of one channel (a mono source on every channel of a multitrack file) multiplied the
    degrees of freedom by four or eight with no new information, and a note partial's chance
    steadiness passed for hum (harmonics 1, 22 and 30 of a bass line, none on one channel).
    A channel with no content counts as independent (it shows no line).

    Parameters
    ----------
    u : (J, C, K) complex array
        Tracked baseband (or any chunk-rate signal per channel and column).

    Returns
    -------
    (K,) float array
        In [1, C].

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> a = rng.standard_normal((4000, 1, 1)) + 1j * rng.standard_normal((4000, 1, 1))
    >>> b = rng.standard_normal((4000, 3, 1)) + 1j * rng.standard_normal((4000, 3, 1))
    >>> float(effective_channels(np.repeat(a, 4, axis=1))[0])                 # four copies
    1.0
    >>> round(float(effective_channels(np.concatenate([a, b], axis=1))[0]), 1)   # four independent
    4.0
    """
    J, C, K = u.shape
    if C == 1:
        return np.ones(K)
    out = np.empty(K)
    for i in range(K):
        d = u[:, :, i].astype(np.complex128)
        d = d - d.mean(axis=0)
        G = d.conj().T @ d                                   # (C, C)
        pw = np.real(np.diag(G))
        live = pw > 1e-300 * max(float(pw.max()), 1e-300) if pw.max() > 0 else np.zeros(C, bool)
        r2 = np.zeros((C, C))
        s = np.sqrt(np.where(live, pw, 1.0))
        r2[np.ix_(live, live)] = (np.abs(G) / np.outer(s, s))[np.ix_(live, live)] ** 2
        r2[np.diag_indices(C)] = 1.0
        out[i] = C * C / r2.sum()
    return np.clip(out, 1.0, C)


PRESENCE_OFF = 0.05     # a unit whose comb power is below this share of the on units' is "off"
PRESENCE_MIN = 0.2      # the hum must be off (and on) for at least this share of the input


def presence(lines, sr: int) -> np.ndarray | None:
    """Where a hum that is switched on and off is on: 1 for the chunks of the 1 s units where
    the comb's locked lines hold their power, 0 where it falls below ``PRESENCE_OFF`` of it; None
    for a hum that stays (off for less than ``PRESENCE_MIN`` of the input, or on for less), so a
    steady hum's tests are untouched.

    Parameters
    ----------
    lines : iterable of (J, C) complex arrays
        Tracked baseband of each locked line (one at a time: an hour of chunk sums of every line
        at once would be the run's largest array).
    sr : int
        Sample rate of the audio (Hz).

    Returns
    -------
    (J,) float array or None

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> u = 0.1 * (rng.standard_normal((3000, 1, 2)) + 1j * rng.standard_normal((3000, 1, 2)))
    >>> on = (np.arange(3000) >= 800) & (np.arange(3000) < 2200)         # on from 8 s to 22 s
    >>> g = presence((u + 2.0 * on[:, None, None]).transpose(2, 0, 1), 8000)
    >>> int(g[:800].sum()), int(g[800:2200].sum()), presence((u + 2.0).transpose(2, 0, 1), 8000) is None
    (0, 1400, True)
    """
    power, J = None, 0
    for u in lines:
        J = u.shape[0]
        fs = sr / _track.chunk_length(sr)
        n = max(2, int(round(WEIGHTED_SEG_S * fs)))
        B = J // n
        if B < 12:
            return None
        U = u[: B * n].astype(np.complex128).reshape(B, n, -1)
        # coherent power of each unit (the lines keep their phase within a second), less what
        # the unit's own scatter puts in it, summed over the lines
        m = U.mean(axis=1)
        noise = (np.abs(U - m[:, None]) ** 2).sum(axis=1) / (n * (n - 1))
        p = np.maximum(np.abs(m) ** 2 - noise, 0.0).sum(axis=1)
        power = p if power is None else power + p
    if power is None:
        return None
    on_level = np.median(power[power >= np.quantile(power, 0.5)])
    off = power < PRESENCE_OFF * on_level
    if not (PRESENCE_MIN <= off.mean() <= 1 - PRESENCE_MIN):
        return None
    g = np.repeat((~off).astype(float), n)
    return np.concatenate([g, np.zeros(J - len(g))])


def weighted_locked(D, sr: int, ks, psi: np.ndarray, presence: np.ndarray | None = None) -> dict:
    """Per harmonic of ``ks`` (columns of the chunk sums ``D``), ``(p, amplitude)`` of
    :func:`weighted_lock_p_values` on its baseband tracked by ``psi`` (as :func:`locked`).

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums at ``k f_ref``.
    sr : int
        Sample rate (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    psi : (J,) float array
        Tracked phase of the fundamental (cycles, relative to ``f_ref t``).
    presence : (J,) array, optional
        As :func:`weighted_lock_p_values`.

    Returns
    -------
    dict
        Harmonic -> ``(p, amplitude)``.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 1000; t = np.arange(10 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> info = weighted_locked(D, sr, [1, 2], 0.1 * (np.arange(len(D)) * 10 + 4.5) / sr)
    >>> bool(info[1][0] < 1e-6), bool(info[2][0] > 1e-3)
    (True, True)
    """
    out = {}
    for i, k in enumerate(ks):
        rot = _finetrack.phase_turn(psi, k)
        p, amp = weighted_lock_p_values(D[:, :, i: i + 1] * rot[:, None, None], sr, presence)
        out[int(k)] = (float(p[0]), float(amp[0]))
    return out
