"""Tracking the instantaneous hum fundamental, one estimate per block, shared by all harmonics.

Pass 1 demodulates the input at k * f_ref (every harmonic to remove) and sums over 10 ms chunks.
Both steps are one matrix product per read, so the pass costs little more than reading the file.
The chunk sums are a low-rate complex baseband of every hum line; per block the fundamental offset
``delta`` maximises the floor-normalised harmonic energy

    E(delta) = sum_{c,k} w_ck | sum_j win_j D_jck exp(-2 pi i k delta (t_j - t_b)) |^2

(an SNR-weighted harmonic-sum periodogram). The chunk length is sr/100, so the chunk-sum kernel has
its zeros on every alias of the baseband and host energy far from the lines cannot fold onto them.
"""
from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np
from scipy import fft as sp_fft

from odnn_sep.audio.blockplan import sin2_window

log = logging.getLogger(__name__)
MAX_DRIFT_HZ = 1.6    # farthest the fundamental is followed from where the spectrum puts it (+ 1 %)
BASELINE_CHUNKS = 100  # the input's baseline, taken out of the chunk sums: a mean over 100 chunks, ~1 s (_remove_baseline)
BASELINE_MIN = 10.0    # ... when it is this many times what the input's own fluctuation gives


@dataclass
class Track:
    """Per-block estimates of the hum fundamental (from :func:`track_fundamental`).

    Attributes
    ----------
    t : (B,) array
        Block centres (s).
    f0 : (B,) array
        Fundamental (Hz).
    rate, curv : (B,) arrays
        Its first and second time derivatives (Hz/s, Hz/s^2).
    confident : (B,) bool array
        Hum clearly present in the block.
    strength : (B,) array
        Peak harmonic energy over its noise-only value.
    phase : finetrack.PhaseTrack or None
        The fundamental's phase at every sample, when refined.

    Examples
    --------
    >>> z = np.zeros(3)
    >>> trk = Track(t=np.arange(3.0), f0=np.array([50.0, 50.02, 49.9]), rate=z, curv=z,
    ...             confident=np.array([True, True, False]), strength=z)
    >>> round(trk.median_f0(50.0), 2)
    50.01
    """

    t: np.ndarray          # (B,) block centres (s)
    f0: np.ndarray         # (B,) fundamental (Hz)
    rate: np.ndarray       # (B,) df/dt (Hz/s)
    curv: np.ndarray       # (B,) d2f/dt2 (Hz/s^2)
    confident: np.ndarray  # (B,) bool: hum clearly present in the block
    strength: np.ndarray   # (B,) peak harmonic energy over its noise-only value
    phase: object = None   # finetrack.PhaseTrack: the fundamental's phase at every sample, when refined

    def median_f0(self, default: float) -> float:
        """Median fundamental over the confident blocks, ``default`` when there are none."""
        return float(np.median(self.f0[self.confident])) if self.confident.any() else default


NOISE_OFFSETS = np.array([-0.45, -0.35, -0.25, 0.25, 0.35, 0.45])


def chunk_length(sr: int) -> int:
    """Samples per 10 ms chunk of the demodulated chunk sums (at least 1).

    Parameters
    ----------
    sr : int
        Sample rate (Hz).

    Returns
    -------
    int

    Examples
    --------
    >>> chunk_length(8000), chunk_length(44100), chunk_length(50)
    (80, 441, 1)
    """
    return max(1, int(round(sr / 100.0)))


def demodulate(source, f_ref: float, ks, *, read_frames: int = 1 << 20, progress=None) -> np.ndarray:
    """Chunk sums ``D[j, c, k] = sum_{t in chunk j} y_c(t) exp(-2 pi i k f_ref t)``, complex64.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input (read in blocks of ``read_frames``).
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers (the last axis of ``D``).
    read_frames : int
        Frames per read.
    progress : callable, optional
        Called with the frames of each read.

    Returns
    -------
    (J, channels, K) complex64 array
        ``J`` 10 ms chunks (:func:`chunk_length`); a line of peak amplitude ``A`` at ``k f_ref``
        has chunk sums of modulus about ``m A / 2``.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.0 * t) + 0.5 * np.cos(2 * np.pi * 100.0 * t + 1)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> D.shape, D.dtype, np.abs(D[100:700, 0].mean(axis=0)).round(2).tolist()
    ((800, 1, 2), dtype('complex64'), [5.0, 2.5])
    """
    sr, n, C = source.sr, source.frames, source.channels
    m = chunk_length(sr)
    kf = f_ref * np.asarray(ks, dtype=float)
    J = -(-n // m)
    D = np.empty((J, C, len(kf)), dtype=np.complex64)
    K = len(kf)
    tau = np.arange(m) / sr
    ang = 2 * np.pi * np.outer(tau, kf)
    # cos and -sin side by side: one single-precision product per read (the chunk sums feed the
    # tracker and the line tests, where 1e-7 relative rounding is far below the noise)
    E = np.hstack([np.cos(ang), -np.sin(ang)]).astype(np.float32)      # (m, 2K)
    per = max(1, read_frames // m) * m
    for start in range(0, n, per):
        x = source.read(start, per)
        nx = x.shape[0]
        nj = -(-nx // m)
        nfull = nx // m
        # chunks as rows, channel by channel, in float32; a short last chunk is zero-padded here
        # (no padded copy of the whole read)
        X = np.empty((nj, C, m), np.float32)
        X[:nfull] = x[: nfull * m].reshape(nfull, m, C).transpose(0, 2, 1)
        if nfull < nj:
            X[nfull] = 0.0
            X[nfull, :, : nx - nfull * m] = x[nfull * m:].T
        S = np.dot(X.reshape(nj * C, m), E).reshape(nj, C, 2 * K)
        _remove_baseline(S, X, E, nx - nfull * m)
        j = np.arange(start // m, start // m + nj, dtype=float)
        # reference phase at each chunk start, reduced modulo one cycle before scaling (precision)
        cyc = np.outer(j * (m / sr), kf)
        if kf.min() >= 0:
            cyc -= np.floor(cyc)            # = np.mod(cyc, 1.0) for cyc >= 0, exactly, and faster
        else:
            cyc = np.mod(cyc, 1.0)
        # exp(-2 pi i cyc) rounded to single precision, by its real and imaginary parts
        th = np.multiply(cyc, -2 * np.pi, out=cyc)
        rot = np.empty(th.shape, np.complex64)
        rot.real = np.cos(th)
        rot.imag = np.sin(th)
        rot = rot[:, None, :]
        Dj = D[start // m: start // m + nj]
        Dj.real = S[:, :, :K]
        Dj.imag = S[:, :, K:]
        Dj *= rot
        if progress is not None:
            progress(nx)
    return D


def _remove_baseline(S, X, E, short):
    """Take the input's baseline (its mean over ``BASELINE_CHUNKS`` chunks around each chunk) out of
    the chunk sums ``S`` (chunks, channels, 2K), in place; ``short``: samples in a short last chunk.

    A constant ``a`` gives every chunk the sum ``a sum_tau E[tau]``, which is not zero unless the
    chunk holds whole periods of ``k f_ref``: in the baseband it is a line at ``-k f_ref`` aliased by
    the 100 Hz chunk rate, perfectly steady and locked to the comb. A DC offset of six times the
    noise made a comb of 36 even harmonics at 49.83 Hz pass every lock test (evidence 162 against
    the true hum's 24). The baseline averages over (nearly) whole periods of 50 and 60 Hz, so the
    hum adds next to nothing to it.
    """
    nj = S.shape[0]
    m = X.shape[2]
    counts = np.full(nj, float(m))
    if short:
        counts[-1] = short
    mean = X.sum(axis=2, dtype=np.float64) / counts[:, None]           # (chunks, channels)
    c = np.vstack([np.zeros((1, mean.shape[1])), np.cumsum(mean, axis=0)])
    # a hundred chunks, half a chunk off centre: 1 s at rates that are multiples of 100 Hz, whole
    # periods of 50 and 60 Hz and their harmonics (0.8 s at 250 Hz, whole too); at other rates a chunk
    # is sr/100 samples rounded and the window is off whole periods by a fraction of one (1.11 s at
    # 360 Hz: a window of exactly 1 s changed no line of the ECG record there)
    h = BASELINE_CHUNKS // 2
    lo, hi = np.maximum(np.arange(nj) - h, 0), np.minimum(np.arange(nj) + h, nj)
    base = (c[hi] - c[lo]) / (hi - lo)[:, None]
    # only a baseline the read's own fluctuation cannot make: a noise of the same spread gives 1-s
    # means of about sd / sqrt(1 s of samples); below BASELINE_MIN times that the chunk sums are
    # left exactly as they are (the correction would only move them within their noise)
    sd = np.sqrt(np.maximum(np.mean(np.square(X, dtype=np.float64), axis=(0, 2)) - np.mean(mean, axis=0) ** 2, 0.0))
    real = np.sqrt(np.mean(base ** 2, axis=0)) > BASELINE_MIN * sd / np.sqrt(BASELINE_CHUNKS * m)
    if not real.any():
        return
    base[:, ~real] = 0.0
    G = np.broadcast_to(E.sum(axis=0, dtype=np.float64), (nj, E.shape[1])).copy()
    if short:
        G[-1] = E[:short].sum(axis=0, dtype=np.float64)
    S -= (base[:, :, None] * G[:, None, :]).astype(np.float32)


def _energy(A, tau, ks, grid):
    """E(delta) for each delta in grid; A = win_j * D_jck * w_ck^(1/2) (J, C, K)."""
    grid = np.asarray(grid, float)
    dt = np.diff(tau)
    dg = np.diff(grid)
    if len(grid) > 6 and np.ptp(dg) <= 1e-9 * abs(dg[0]) and len(tau) > 1 and np.ptp(dt) <= 1e-9 * abs(dt[0]):
        # uniform grid and chunk times: for each harmonic the sums over j at the G offsets are
        # a chirp-z transform of the baseband turned to the first offset (Bluestein: three FFTs
        # for every line at once instead of G passes over the baseband); the phase factor a
        # common time shift adds has modulus one
        J, C, K = A.shape
        G = len(grid)
        n = sp_fft.next_fast_len(J + G - 1)
        th = 2 * np.pi * dg[0] * dt[0]                       # chirp rate per unit harmonic number
        t2 = np.zeros(n)
        t2[:G] = np.arange(G, dtype=float) ** 2
        t2[n - J + 1:] = np.arange(-(J - 1), 0, dtype=float) ** 2
        q1 = -2 * np.pi * grid[0] * tau - 0.5 * th * np.arange(J, dtype=float) ** 2
        if np.all(ks == np.round(ks)) and ks.min() >= 1:
            # integer harmonics: powers of the fundamental's phasors (no exponential per line)
            q, h = _int_powers(np.exp(1j * q1), ks), _int_powers(np.exp(0.5j * th * t2), ks)
        else:
            q, h = np.exp(1j * np.outer(ks, q1)), np.exp(0.5j * th * np.outer(ks, t2))
        y = np.zeros((C, K, n), complex)
        np.multiply(A.transpose(1, 2, 0), q[None], out=y[:, :, :J])
        Y = sp_fft.fft(y, axis=2, overwrite_x=True)
        Y *= sp_fft.fft(h, axis=1)[None]
        X = sp_fft.ifft(Y, axis=2, overwrite_x=True)[:, :, :G]
        return (X.real ** 2 + X.imag ** 2).sum(axis=(0, 1))
    kt = tau[:, None] * ks[None, :]                                   # (J, K)
    ph = np.exp(-2j * np.pi * grid[:, None, None] * kt[None, :, :])   # (G, J, K)
    X = np.einsum("jck,gjk->gck", A, ph)
    return (np.abs(X) ** 2).sum(axis=(1, 2))


def _int_powers(z: np.ndarray, ks) -> np.ndarray:
    """``z ** k`` for the (positive integer) ``ks`` by repeated multiplication: (len(ks), len(z))."""
    out = np.empty((len(ks), len(z)), complex)
    order = np.argsort(ks, kind="stable")
    zk, kp = np.ones_like(z), 0
    for i in order:
        for _ in range(int(ks[i]) - kp):
            zk = zk * z
        kp = max(kp, int(ks[i]))
        out[i] = zk
    return out


def _energy_rel(A, tau, ks, centre: float, offsets, cache: dict) -> np.ndarray:
    """E(centre + d) for each d in ``offsets`` (see :func:`_energy`), as one batched matrix product.

    E depends on the chunk times only through their differences (a common shift of tau changes
    every sum by a phase factor of modulus one), so the (K, G, J) matrix of
    ``exp(-2 pi i k d tau_j)`` is the same for every full block and is built once per call of the
    tracker; each block then only rotates its baseband by ``exp(-2 pi i k centre tau_j)``.
    """
    offsets = np.asarray(offsets, float)
    J = A.shape[0]
    key = (J, offsets.tobytes(), ks.tobytes())
    M = cache.get(key)
    if M is None:
        rel = (np.arange(J) - (J - 1) / 2) * (tau[1] - tau[0]) if J > 1 else np.zeros(1)
        kr = ks[:, None] * rel[None, :]                                    # (K, J)
        # single precision for the products: E is compared between nearby offsets (differences
        # of ~1 % at the peak) and against the floor; rounding sits ~140 dB under the peak.
        # Built in double precision row by row, rounded as each row is written.
        M = np.empty((len(ks), len(offsets), J), np.complex64)
        d = np.diff(offsets)
        if len(offsets) > 2 and np.allclose(d, d[0]):
            # uniform offsets: one complex multiply per entry instead of an exponential
            m = np.exp(-2j * np.pi * offsets[0] * kr)
            r = np.exp(-2j * np.pi * d[0] * kr)
            M[:, 0] = m
            for g in range(1, len(offsets)):
                np.multiply(m, r, out=m)
                M[:, g] = m
        elif np.all(ks == np.round(ks)) and ks.min() >= 1:
            # integer harmonics: powers of the fundamental's phasors, one exponential per chunk
            for g, dg in enumerate(offsets):
                M[:, g] = _int_powers(np.exp(-2j * np.pi * dg * rel), ks)
        else:
            for g, dg in enumerate(offsets):
                M[:, g] = np.exp(-2j * np.pi * dg * kr)
        if len(cache) > 32:
            cache.clear()
        cache[key] = M
    if np.all(ks == np.round(ks)) and ks.min() >= 1:
        # integer harmonics: the rotation's phasors are powers of the fundamental's (one
        # exponential per chunk, not per chunk and line; they agree to ~1e-15)
        rot = _int_powers(np.exp(-2j * np.pi * centre * tau), ks)                      # (K, J)
    else:
        rot = np.exp(-2j * np.pi * centre * (tau[:, None] * ks[None, :])).T
    # rotated in double precision, rounded to single as it is written, laid out (K, C, J)
    B = np.empty((len(ks), A.shape[1], J), np.complex64)
    np.multiply(A.transpose(2, 1, 0), rot[:, None, :], out=B, casting="same_kind")
    E = np.zeros(len(offsets))
    for k in range(len(ks)):
        # np.dot per harmonic with a Fortran-ordered right factor: one BLAS gemm (a C-ordered
        # (J, C) factor with C = 1 or 2 takes a path 10x slower)
        X = np.dot(M[k], B[k].T)                                                     # (G, C)
        E += (X.real ** 2 + X.imag ** 2).sum(axis=1, dtype=np.float64)
    return E


def _parabolic(grid, E, i):
    if 0 < i < len(grid) - 1:
        a, b, c = np.log(E[i - 1: i + 2] + 1e-300)
        den = a - 2 * b + c
        if den < 0:
            return float(grid[i] + 0.5 * (a - c) / den * (grid[1] - grid[0]))
    return float(grid[i])


def track_fundamental(D, f_ref: float, ks, weights, plan, *, max_offset_hz: float | None = None,
                      min_strength: float = 10.0, progress=None) -> Track:
    """Per-block fundamental estimates from the chunk sums (see module docstring), for the blocks
    of ``plan`` (a blockplan.BlockPlan).

    ``weights`` (C, K): inverse noise-floor PSD per channel and harmonic (SNR weighting).

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums of :func:`demodulate` at ``k f_ref``.
    f_ref : float
        Their reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    weights : (C, K) array
        Inverse noise-floor PSD per channel and harmonic.
    plan : BlockPlan
        The blocks.
    max_offset_hz : float, optional
        Farthest the fundamental is followed from ``f_ref`` (default :data:`MAX_DRIFT_HZ` + 1 %).
    min_strength : float
        Strength above which a block counts as confident.
    progress : callable, optional
        Progress callback.

    Returns
    -------
    Track

    Examples
    --------
    >>> from odnn_sep.audio.blockplan import BlockPlan
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> x += 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> trk = track_fundamental(D, 50.0, [1, 2], np.ones((1, 2)), BlockPlan.from_block_s(4.0, sr, t.size))
    >>> trk.t.tolist(), trk.f0.round(2).tolist(), trk.confident.tolist()
    ([0.0, 2.0, 4.0, 6.0, 8.0], [50.1, 50.1, 50.1, 50.1, 50.1], [False, True, True, True, False])
    """
    sr, n_frames, hop, nb = plan.sr, plan.n_frames, plan.hop, plan.count
    m = chunk_length(sr)
    J = D.shape[0]
    ks = np.asarray(ks, dtype=float)
    if max_offset_hz is None:
        # ramps of 50 mHz/s reach +-1.5 Hz over a minute, and the spectrum's reference can sit
        # up to 1 % off the mean of a line smeared that far
        max_offset_hz = MAX_DRIFT_HZ + 0.01 * f_ref
    est = _BlockEstimator(D, sr, f_ref, ks, weights, plan.length, max_offset_hz)
    f = np.full(nb, np.nan)
    strength = np.zeros(nb)
    coverage = np.zeros(nb)
    t_eff = np.arange(nb) * hop / sr
    t_chunk = (np.arange(J) * m + (m - 1) / 2) / sr

    def visit(b, prev, wide):
        s0, s1 = (b - 1) * hop, (b + 1) * hop
        j0, j1 = max(0, s0 // m), min(J, -(-s1 // m))
        if j1 - j0 < 3:
            return
        tc = t_chunk[j0:j1]
        # Hann over the part of the block inside the signal: at the ends a one-sided window
        # would leak the host's energy onto the lines
        a0, a1 = max(s0, 0), min(s1, n_frames)
        win = sin2_window(np.clip((tc * sr - a0) / max(a1 - a0, 1), 0, 1), 1)
        # a block cut by the start/end of the signal sees one side of its window only: its
        # estimate is the frequency at the window's centroid, not at the block centre
        coverage[b] = win.sum() / (plan.length / m / 2)
        t_eff[b] = float((win * tc).sum() / max(win.sum(), 1e-300))
        # between neighbouring blocks the grid moves by a few mHz: a narrow search around the
        # prediction (re-centred when the peak sits on its edge)
        half = max(0.15, 0.0025 * f_ref) if wide else 0.03
        f[b], strength[b] = est(j0, j1, win, tc - b * hop / sr, prev, half)
        if progress is not None:
            progress(1)

    _outwards(nb, f, strength, min_strength, 0.1 * hop / sr, visit)
    ok = np.isfinite(f) & (strength >= min_strength)
    ok &= coverage >= 0.25
    f0 = f_ref + _offsets(plan.centres_s, t_eff, f, ok, max_offset_hz, f_ref)
    hop_s = hop / sr
    rate = np.gradient(f0, hop_s) if nb > 1 else np.zeros(nb)
    curv = np.gradient(rate, hop_s) if nb > 2 else np.zeros(nb)
    return Track(t=plan.centres_s, f0=f0, rate=rate, curv=curv, confident=ok, strength=strength)


def _outwards(nb, f, strength, min_strength, max_step_hz, visit) -> None:
    """Visit blocks from the middle of the input outwards, each searched around the value the
    last two trusted ones predict (``visit(b, predicted offset, wide)`` fills ``f[b]`` and
    ``strength[b]``). The spectrum's reference is the mean frequency, which a ramp or a slow
    wander passes in the middle, not at the start (a +-1.5 Hz ramp starts farther away than a
    search can reach). ``max_step_hz``: largest predicted change per block (100 mHz/s, twice the
    fastest grid ramp)."""
    mid = (nb - 1) // 2
    for order in (range(mid, nb), range(mid - 1, -1, -1)):
        trusted = [b for b in ((mid + 1, mid) if order.start != mid else ()) if b < nb and strength[b] >= min_strength]
        for b in order:
            prev = 0.0
            if trusted:
                prev = f[trusted[-1]]
                if len(trusted) > 1:
                    b1, b2 = trusted[-1], trusted[-2]
                    prev += float(np.clip((f[b1] - f[b2]) / (b1 - b2), -max_step_hz, max_step_hz)) * (b - b1)
            visit(b, prev, wide=not trusted or abs(b - trusted[-1]) > 1)
            if np.isfinite(f[b]) and strength[b] >= min_strength:
                trusted.append(b)


class _BlockEstimator:
    """One block's fundamental offset and line strength from the chunk sums: a coarse grid on the
    low harmonics, then a fine grid and a noise reference on all of them."""

    def __init__(self, D, sr, f_ref, ks, weights, L, max_offset_hz):
        self.D, self.f_ref, self.ks, self.max_offset_hz = D, f_ref, ks, max_offset_hz
        self.sqw = np.sqrt(np.asarray(weights, dtype=float))[None, :, :]
        L_s = L / sr
        self.k_coarse = float(min(ks.max(), 8.0))
        self.coarse_ks = ks <= max(self.k_coarse, ks.min())
        self.step = 0.25 / (L_s * self.k_coarse)
        self.cache = {}

    def __call__(self, j0, j1, win, tau, prev, half):
        """``(offset Hz, strength)`` of the block over chunks ``j0 .. j1`` (window ``win``, times
        ``tau`` from the block centre), searched around ``prev`` within ``half``."""
        ks, step, cache = self.ks, self.step, self.cache
        A = self.D[j0:j1] * (win[:, None, None] * self.sqw).astype(np.float32)
        # E is used only through ratios and log differences: normalise so the single-precision
        # products cannot overflow whatever the sample units and floor weights
        amax = float(np.abs(A).max()) if A.size else 0.0
        if amax > 0 and np.isfinite(amax):
            A *= np.float32(1.0 / amax)
        centre = prev
        rel = np.arange(-half, half + step / 2, step)
        Ac = A[:, :, self.coarse_ks]
        ks_c = ks[self.coarse_ks]
        for _ in range(6):
            grid = centre + rel
            E = _energy_rel(Ac, tau, ks_c, centre, rel, cache)
            i = int(np.argmax(E))
            if 0 < i < len(grid) - 1 or abs(grid[i]) >= self.max_offset_hz:
                break
            centre = grid[i]
        fine_rel = np.linspace(-step, step, 11)
        fine = grid[i] + fine_rel
        # fine grid and noise reference in one product: E for pure noise is about
        # sum_j win_j^2 |D|^2, for a pure line (sum win)^2 |d|^2; the noise reference is the same
        # harmonic energy a little way off the peak (0.25-0.45 Hz per unit of harmonic number),
        # i.e. the local floor around every line
        E2 = _energy_rel(A, tau, ks, float(grid[i]), np.concatenate([fine_rel, NOISE_OFFSETS]), cache)
        Ef = E2[: len(fine_rel)]
        i2 = int(np.argmax(Ef))
        est = _parabolic(fine, Ef, i2)
        noise = float(np.median(E2[len(fine_rel):]))
        strength = float(Ef[i2]) / max(noise, 1e-300)
        if abs(est) > self.max_offset_hz:
            est = float(np.clip(est, -self.max_offset_hz, self.max_offset_hz))
            strength = 0.0
        return est, strength


def _offsets(t, t_eff, f, ok, max_offset_hz, f_ref) -> np.ndarray:
    """Offsets at the block centres ``t`` from the trusted estimates ``f[ok]`` (taken at their
    window centroids ``t_eff``): interpolated, extrapolated linearly beyond the ends, clipped."""
    nb = len(t)
    if ok.sum() == 0:
        log.info("hum too weak in every block to track its frequency; using the fixed fundamental %.4f Hz",
                 f_ref)
        return np.zeros(nb)
    if ok.sum() == 1 or np.ptp(t_eff[ok]) == 0:
        return np.full(nb, f[ok][0])
    ti, fi = t_eff[ok], f[ok]
    off = np.interp(t, ti, fi)
    # linear extrapolation beyond the first/last trusted estimate (not a flat hold)
    lo, hi = t < ti[0], t > ti[-1]
    off[lo] = fi[0] + (t[lo] - ti[0]) * (fi[1] - fi[0]) / (ti[1] - ti[0])
    off[hi] = fi[-1] + (t[hi] - ti[-1]) * (fi[-1] - fi[-2]) / (ti[-1] - ti[-2])
    return np.clip(off, -max_offset_hz, max_offset_hz)


def refine_fixed_comb(D, sr: int, f_ref: float, ks, weights, *, half_hz: float, max_seconds: float = 300.0) -> float:
    """Fundamental of a steady (untracked) comb: maximise the harmonic energy E(delta) over one long
    Hann window (a central stretch of at most ``max_seconds``), searching +-``half_hz`` around
    ``f_ref``. Far finer than a Welch peak: a fixed-frequency line fitted over 16 s blocks needs
    its frequency to about 1e-3 Hz at the tenth harmonic.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums of :func:`demodulate` at ``k f_ref``.
    sr : int
        Sample rate (Hz).
    f_ref : float
        Reference fundamental (Hz).
    ks : sequence of int
        Harmonic numbers of ``D``'s columns.
    weights : (C, K) array
        Inverse noise-floor PSD per channel and harmonic.
    half_hz : float
        Search half-range (Hz).
    max_seconds : float
        Longest central stretch used (s).

    Returns
    -------
    float
        ``f_ref`` itself when the input is too short (under 4 baseband samples).

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(8 * sr) / sr
    >>> x = np.cos(2 * np.pi * 50.1 * t) + 0.5 * np.cos(2 * np.pi * 100.2 * t + 1)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> round(refine_fixed_comb(D, sr, 50.0, [1, 2], np.ones((1, 2)), half_hz=0.5), 3)
    50.1
    """
    m = chunk_length(sr)
    J = D.shape[0]
    jmax = int(max_seconds * sr / m)
    j0 = max(0, (J - jmax) // 2)
    Dc = D[j0: j0 + min(J, jmax)].astype(np.complex128)
    g = 5   # 20 Hz baseband rate: enough for k * half_hz offsets, 5x fewer terms
    Jd = Dc.shape[0] // g
    if Jd < 4:
        return f_ref
    Dd = Dc[: Jd * g].reshape(Jd, g, *Dc.shape[1:]).sum(axis=1)
    t = ((j0 + np.arange(Jd) * g + (g - 1) / 2) * m + (m - 1) / 2) / sr
    tau = t - t.mean()
    win = sin2_window(np.arange(Jd) + 0.5, Jd)
    ks = np.asarray(ks, dtype=float)
    A = Dd * win[:, None, None] * np.sqrt(np.asarray(weights, float))[None, :, :]
    span = tau[-1] - tau[0]
    centre, step = 0.0, 0.25 / (span * ks.max())
    width = half_hz
    for _ in range(8):
        grid = centre + np.arange(-width, width + step / 2, max(step, 2 * width / 60))
        E = _energy(A, tau, ks, grid)
        i = int(np.argmax(E))
        centre = _parabolic(grid, E, i)
        if i in (0, len(grid) - 1) and width == half_hz:
            return f_ref    # the peak is not inside the search range: keep the spectral estimate
        if grid[1] - grid[0] <= step:
            break
        width = 3 * (grid[1] - grid[0])
    return float(f_ref + centre)
