"""A hum level shared by the harmonics that changes within a block: a load that varies, a device
switched on or off, a level that steps.

The block fit gives each line one complex amplitude per 8-16 s block (steadypath.py smooths them
further), so hum whose level moves within a block is left in part: a 40 % modulation at 0.5 Hz
leaves about -11 dB. The level of mains hum is set by what draws the current, and every harmonic
of the same source follows it: the change is one real gain ``g(t)`` common to the lines, as the
fundamental's phase is common to them (finetrack.py). Here, from pass 1's chunk sums:

1. per line, the tracked baseband ``u_k(t)`` (10 ms chunks) and the hum the blocks will subtract
   there, ``T_k(t)``: the blocks' amplitudes (the smoothed paths, else the window mean of the
   block), cross-faded by the blocks' sin^2 windows as the fit's output is;
2. the pooled ratio ``G(t) = sum_k conj(T_k) u_k / q_k / sum_k |T_k|^2 / q_k`` (``q_k`` the
   content power beside line ``k``, :func:`nearpower.near_power`), smoothed by a Hann of width
   ``s`` with the same weights: a moving mean or, for a level without steps, a local quadratic
   (a moving mean of a level modulated at 0.5 Hz is biased by its curvature; both smoothers are
   tried at every width and the benefit below chooses);
3. a change of level is shared and real: at least ``MIN_LINES`` lines are needed, and the
   change is ``Re G - 1``. Content under the lines (a note partial beside a harmonic, speech, a
   tracking error) moves ``Re G`` and ``Im G`` alike, so the smoothed ``Im G`` measures what the
   content alone puts into the estimate. The gain is used only where its real part holds
   ``KAPPA`` times the energy of its imaginary part, at the width used and at twice it, and the
   width and smoother chosen are those with the largest expected benefit ``E_re - 2 E_im`` (what is
   followed, less the content the correction would then remove with it). Steady hum, and content
   that merely sits near the lines,
   leave the output as it was;
4. a level that steps (a switch) would be blurred over the smoothing's width: the steps are found
   first (:func:`level_steps`: a cubic plus a step fitted on each side of every boundary) and the
   gain is smoothed between them, never across one.

Pass 2 (blockfit.py) then scales the tracked comb it subtracts by ``g(t)`` (interpolated to the
samples), per channel.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.audio import track as _track
from odnn_sep.audio.blockplan import BlockPlan, sin2_window
from odnn_sep.audio.finetrack import PhaseTrack, phase_turn

WIDTHS_S = (0.1, 0.2, 0.5, 1.0, 2.0)   # Hann widths of the gain tried (s)
STEP_WINDOW_S = 0.5                    # each side's span of the step test (s)
STEP_Z = 6.0                           # a step's size over its standard error, at least,
STEP_IM_MAX = 2.5                      # ... and this many times the largest the test gives on Im G
                                       # (1.5 before the leak was averaged out: the leak's flips
                                       # had raised that largest value as much as the content)
STEP_IM = 4.0                          # ... and this many times the test on Im G at the same place
STEP_DECIM = 5                         # chunks pooled for finding the steps in long inputs ...
STEP_FULL_CHUNKS = 60_000              # ... longer than this (10 min of 10 ms chunks)
KAPPA = 4.0                            # real-part energy over imaginary-part energy needed
DEGREES = (0, 2)                       # smoothers of the gain tried: the moving mean, the local quadratic
QUADRATIC_MIN_S = 0.5                  # ... the latter from this width up: narrower, a moving mean keeps
                                       # 98 % of a 0.5 Hz modulation, and the quadratic's wider passband lets
                                       # the chunk-rate flips of the neighbouring harmonics' leak through
MIN_LINES = 2                          # a level shared by the harmonics needs two of them to show it
                                       # (one line's level and a click in phase with it look alike)


@dataclass(frozen=True)
class Envelope:
    """The shared hum gain of each channel at the chunk centres: ``gain[j, c]`` at sample
    ``t[j]`` (``None`` columns are never built: a channel without a change keeps gain 1), and the
    Hann width (s) it was smoothed with.

    Examples
    --------
    >>> env = Envelope(t=np.array([0.0, 100.0]), gain=np.array([[1.0], [0.5]]), width_s=0.2)
    >>> env.at(0, 4, 0).tolist()       # samples 0..3, channel 0
    [1.0, 0.995, 0.99, 0.985]
    """

    t: np.ndarray          # (J,) chunk centres, samples
    gain: np.ndarray       # (J, C)
    width_s: float
    steps_s: tuple = ()    # times (s) where the level steps (level_steps), any channel, in order

    def at(self, i0: int, n: int, c: int) -> np.ndarray:
        """The gain of channel ``c`` at samples ``i0 .. i0 + n``."""
        return np.interp(np.arange(i0, i0 + n, dtype=np.float64), self.t, self.gain[:, c])


def _smooth(x: np.ndarray, w: np.ndarray, n: int, cuts=(), degree: int = 0) -> np.ndarray:
    """Weighted Hann moving mean of ``x`` (weights ``w``), ``n`` chunks wide, never across a
    step of the level (``cuts``: the first chunk after each); ``degree=2``: the weighted local
    quadratic under the same Hann instead (:func:`_local_quadratic`). Both are linear in ``x``:
    a complex ``x`` smooths its real and imaginary parts in one pass."""
    h = np.hanning(n + 2)[1:-1]
    out = np.empty(len(x), dtype=np.result_type(x, float))
    edges = [0, *cuts, len(x)]
    lo = (n - 1) // 2             # where np.convolve's "same" starts in the full convolution
    for a, b in zip(edges[:-1], edges[1:]):
        num = np.convolve(x[a:b] * w[a:b], h)[lo: lo + b - a]
        den = np.convolve(w[a:b], h)[lo: lo + b - a]
        out[a:b] = num / np.maximum(den, 1e-300)
        if degree == 2:
            out[a:b] = _local_quadratic(x[a:b], w[a:b], h, lo, out[a:b])
    return out


def _local_quadratic(x: np.ndarray, w: np.ndarray, h: np.ndarray, lo: int, mean: np.ndarray) -> np.ndarray:
    """At every chunk, the value at its centre of the quadratic fitted to ``x`` under the Hann ``h``
    times the weights ``w`` (``mean``, the moving mean, where that fit is singular, and, blended
    in, within half a window of either end).

    A moving mean of a level modulated at 0.5 Hz is biased by its curvature: a 0.5 s Hann keeps
    about 90 % of a 40 % modulation, and the 4 % left is -28 dB of the hum, so the narrowest
    widths were chosen and their noise stayed instead. The local quadratic follows the curvature
    and lets a width twice as wide or more be chosen.

    Examples
    --------
    >>> t = np.arange(400) / 100.0
    >>> x = 1 + 0.4 * np.sin(np.pi * t)
    >>> h = np.hanning(53)[1:-1]
    >>> m = _smooth(x, np.ones(400), 51)
    >>> q = _local_quadratic(x, np.ones(400), h, 25, m)
    >>> bool(np.abs(q - x)[30:-30].max() < 0.1 * np.abs(m - x)[30:-30].max())
    True
    """
    n = len(h)
    d = (lo - np.arange(n)) / max(n / 2.0, 1.0)      # offsets, scaled: the sums stay of one order
    N = len(x)
    kernels = [h * d ** p for p in range(5)]
    S = _convolve_same(w, kernels, lo, N)
    T = _convolve_same(w * x, kernels[:3], lo, N)
    # the normal equations' first unknown by Cramer's rule (the matrix is a Hankel one of S)
    c0 = S[2] * S[4] - S[3] ** 2
    det = S[0] * c0 - S[1] * (S[1] * S[4] - S[2] * S[3]) + S[2] * (S[1] * S[3] - S[2] ** 2)
    num = T[0] * c0 - S[1] * (T[1] * S[4] - S[3] * T[2]) + S[2] * (T[1] * S[3] - S[2] * T[2])
    ok = np.abs(det) > 1e-9 * np.maximum(S[0], 1e-300) ** 3
    sol = np.where(ok, num / np.where(ok, det, 1.0), mean)
    # within half a window of the stretch's ends the quadratic extrapolates (its variance there
    # is several times the mean's): handed over linearly to the moving mean, all of it at the end
    i = np.arange(N)
    lam = np.clip(np.minimum(i, N - 1 - i) / max(lo, 1), 0.0, 1.0)
    return lam * sol + (1 - lam) * mean


def _convolve_same(a: np.ndarray, kernels, lo: int, N: int) -> list[np.ndarray]:
    """``np.convolve(a, k)[lo: lo + N]`` for each of ``kernels`` (of one length), on the FFT: an
    hour has 360 000 chunks and the kernels up to 200 taps, which direct sums take seconds for."""
    from scipy import fft as _fft

    n = len(kernels[0])
    if np.iscomplexobj(a):
        nf = _fft.next_fast_len(len(a) + n - 1)
        A = _fft.fft(a, nf)
        return [_fft.ifft(A * _fft.fft(k, nf), nf)[lo: lo + N] for k in kernels]
    nf = _fft.next_fast_len(len(a) + n - 1, real=True)
    A = _fft.rfft(a, nf)
    return [_fft.irfft(A * _fft.rfft(k, nf), nf)[lo: lo + N] for k in kernels]


def _step_fits(ys, w: np.ndarray, L: int):
    """At every boundary ``j`` (between chunks ``j - 1`` and ``j``, for ``j = L .. len(w) - L``) a
    weighted fit over the ``2 L`` chunks around it of a cubic plus a step at ``j``: for each
    array of ``ys``, the step's size; and the step's variance over the noise's (``sigma^2 / w``
    per chunk). A cubic takes up a level that moves smoothly (a load modulated at 0.5 Hz bends
    within a second), so only a jump shows as a step."""
    x = (np.arange(-L, L) + 0.5) / L                        # the window's chunks, scaled to [-1, 1]
    right = (x > 0).astype(float)
    cols = [x ** p for p in range(4)] + [right]

    def window_sums(v, kern):
        # sum over the window starting at j - L of v * kern, for every boundary j
        return np.convolve(v, kern[::-1], "valid")

    n = len(cols)
    A = np.empty((len(w) - 2 * L + 1, n, n))
    for i in range(n):
        for k in range(i, n):
            A[:, i, k] = A[:, k, i] = window_sums(w, cols[i] * cols[k])
    # the step's row of the inverse: its variance, and its weights on the right-hand sides
    good = np.abs(np.linalg.det(A)) > 1e-12 * np.prod(np.diagonal(A, axis1=1, axis2=2), axis=1)
    A[~good] = np.eye(n)
    inv_last = np.linalg.solve(A, np.broadcast_to(np.eye(n)[-1], (A.shape[0], n))[..., None])[..., 0]
    var = np.where(good, inv_last[:, -1], np.inf)
    steps = []
    for y in ys:
        rhs = np.stack([window_sums(w * y, c) for c in cols], axis=1)
        steps.append(np.where(good, np.einsum("ji,ji->j", inv_last, rhs), 0.0))
    return steps, var


def level_steps(G: np.ndarray, W: np.ndarray, fs: float, n_leak: int = 1) -> list[int]:
    """Chunks where the shared level steps (a load switched, a device turned on or off): the
    first chunk after each step.

    Around every boundary a weighted cubic plus a step there is fitted to ``Re G`` over
    ``STEP_WINDOW_S`` on each side: a level that moves smoothly (a load modulated at 0.5 Hz) is
    the cubic's, and only a jump shows as a step.
    The noise of ``G`` is what the content puts into it: measured on ``Im G`` (a change of level is
    real). A step must be ``STEP_Z`` standard errors, ``STEP_IM_MAX`` times the largest value the
    same test reaches on ``Im G`` anywhere, and ``STEP_IM`` times its value there. Local maxima at
    least a window apart.

    The search runs on ``G`` averaged over ``n_leak`` chunks (:func:`leak_chunks`); each step
    is then placed on ``G`` itself. Each line's chunk sums hold a leak of the neighbouring
    harmonics that turns by part of a cycle from one chunk to the next (half a cycle for 50 Hz
    hum in 10 ms chunks) and flips ``G`` at the chunk rate: on a clean recording by more than the
    level itself, and a level that changes then flips with it; the test read the flips as steps
    (every 0.5-2 s on a 0.5 Hz load modulation with the content 40 dB down: 32 dB instead of 44).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> G = 1 + 0.05 * (rng.standard_normal(1000) + 1j * rng.standard_normal(1000))
    >>> G[400:] *= 0.4
    >>> level_steps(G, np.ones(1000), 100.0)
    [400]
    >>> t = np.arange(1000) / 100.0
    >>> level_steps(1 + 0.4 * np.sin(np.pi * t) + 0.05j * rng.standard_normal(1000), np.ones(1000), 100.0)
    []
    """
    L = max(5, int(round(STEP_WINDOW_S * fs)))
    if len(G) < 4 * L:
        return []
    G0, W0 = G, W
    if n_leak > 1:
        box = np.ones(n_leak)
        den = np.convolve(W, box, "same")
        G = np.convolve(G * W, box, "same") / np.maximum(den, 1e-300)
        W = den / n_leak          # neighbours now share data: the weight of one chunk's worth
        W[: n_leak - 1] = 0.0     # means cut by the ends hold part of a turn of the leak
        W[len(W) - n_leak + 1:] = 0.0
    # G's noise per chunk is sigma^2 / W: sigma^2 from the imaginary part, robustly (speech bursts)
    sigma2 = float(np.median(W * G.imag ** 2)) / 0.4549
    if not sigma2 > 0:
        return []
    # beyond STEP_FULL_CHUNKS found on means over STEP_DECIM chunks (the fits cost the same per
    # boundary, and an hour has 360 000 of them), then placed to the chunk; the bar set by Im G's
    # largest value is then that of the means (fewer, smoother values: a lower bar)
    dec = STEP_DECIM if L >= 4 * STEP_DECIM and len(G) > STEP_FULL_CHUNKS else 1
    n = len(G) // dec
    Wd = W[: n * dec].reshape(n, dec).sum(axis=1)
    Gd = (G[: n * dec] * W[: n * dec]).reshape(n, dec).sum(axis=1) / np.maximum(Wd, 1e-300)
    z, z_im = _step_z(Gd, Wd, L // dec, sigma2)
    # what the content alone gives the test (Im G has no change of level) sets the bar: speech
    # bursts near the lines are heavy-tailed, and their largest values reach far beyond a
    # Gaussian's
    ok = (z > max(STEP_Z, STEP_IM_MAX * float(z_im.max()))) & (z > STEP_IM * z_im)
    found = []
    for i in np.argsort(-z):
        if not ok[i]:
            break
        j = (int(i) + L // dec) * dec
        if all(abs(j - q) >= L for q in found):
            found.append(j)
    out = []
    for j in found:
        lo, hi = max(0, j - dec - L), min(len(G), j + dec + L)
        zj, _ = _step_z(G0[lo:hi], W0[lo:hi], L, sigma2)
        out.append(lo + L + int(np.argmax(zj)) if len(zj) else j)
    return sorted(out)


def leak_chunks(f_ref: float, sr: int) -> int:
    """Chunks over which the leak of the neighbouring harmonics (``f_ref`` apart) into a line's
    chunk sums turns by a whole number of cycles (within 0.05): 2 for 50 Hz, 5 for 60 Hz in
    10 ms chunks; 1 when no count up to 10 does.

    Examples
    --------
    >>> leak_chunks(50.0, 44100), leak_chunks(60.0, 8000), leak_chunks(59.97, 16000)
    (2, 5, 5)
    """
    turn = f_ref * _track.chunk_length(sr) / sr
    for n in range(1, 11):
        if n * turn >= 0.5 and abs(n * turn - round(n * turn)) < 0.05:
            return n
    return 1


def _step_z(G: np.ndarray, W: np.ndarray, L: int, sigma2: float):
    """The step test of :func:`level_steps` on ``Re G`` and on ``Im G`` at every boundary
    ``L .. len(G) - L``: each step's size over its standard error."""
    (d_re, d_im), var = _step_fits((G.real, G.imag), W, L)
    sd = np.sqrt(sigma2 * var)
    return np.abs(d_re) / sd, np.abs(d_im) / sd


def _subtracted(u: np.ndarray, tj: np.ndarray, plan: BlockPlan, path: np.ndarray | None) -> np.ndarray:
    """The hum the blocks subtract at each chunk, in the baseband's reference: block amplitudes
    (``path`` where given, else the block's weighted mean of ``u`` under the fit's window)
    cross-faded by the windows.

    A block cut by the input's start or end is fitted under a sin^2 over its visible part
    (fullblock.window), not under its own window, and its mean here is taken the same way: the
    gain is the ratio of the data to what pass 2 will subtract, so both must hold the same
    amplitude (with the block's own window the last second of a 40 % level modulation was
    over-subtracted by 4-13 %)."""
    nb, hop, L = plan.count, plan.hop, plan.length
    T = np.zeros(u.shape[0], complex)
    wsum = np.zeros(u.shape[0])
    lo = np.searchsorted(tj, np.arange(nb) * hop - hop)
    hi = np.searchsorted(tj, np.arange(nb) * hop + hop)
    for b in np.flatnonzero(hi > lo):
        sl = slice(lo[b], hi[b])
        s0 = b * hop - hop
        win = sin2_window(tj[sl] - s0, L)
        i0, i1 = max(s0, 0), min(s0 + L, plan.n_frames)
        w_fit = win if i1 - i0 >= L else sin2_window(tj[sl] - i0, i1 - i0)
        a = path[b] if path is not None and np.isfinite(path[b]) else np.sum(w_fit * u[sl]) / max(w_fit.sum(), 1e-300)
        T[sl] += win * a
        wsum[sl] += win
    return T / np.maximum(wsum, 1e-12)


def shared_envelope(D: np.ndarray, sr: int, f_ref: float, ks, psi: np.ndarray, plan: BlockPlan,
                    main_amps: np.ndarray | None, near: np.ndarray, jumps=()) -> Envelope | None:
    """The shared hum gain (see the module text), or None where no channel's level changes
    within the blocks more than the content under the lines explains.

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
    psi : (J,) array
        Tracked phase (cycles, relative to ``f_ref t``) at the chunk centres.
    plan : BlockPlan
        The fit blocks.
    main_amps : (blocks, C, K) complex array or None
        The amplitude paths in each block's reference
        (:func:`steadypath.comb_block_amplitudes`; NaN: the block fit's own).
    near : (J, C, K) float array
        Content power beside each line (:func:`steadypath.block_means` with ``keep_power``).
    jumps : sequence of (int, float), optional
        Steps of ``psi`` placed to the sample (finetrack.PhaseTrack), as the block fit's phase.

    Returns
    -------
    Envelope or None

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.steadypath import block_means
    >>> sr = 2000; t = np.arange(60 * sr) / sr
    >>> rng = np.random.default_rng(0)
    >>> hum = np.cos(2 * np.pi * 50 * t) + 0.5 * np.cos(2 * np.pi * 100 * t + 1)
    >>> x = hum * (1 + 0.4 * np.sin(2 * np.pi * 0.5 * t)) + 0.05 * rng.standard_normal(t.size)
    >>> D = _track.demodulate(ArraySource(x, sr), 50.0, [1, 2])
    >>> plan = BlockPlan.from_block_s(8.0, sr, t.size); psi = np.zeros(len(D))
    >>> near = block_means(D, sr, [1, 2], psi, plan, keep_power=True)[4]
    >>> env = shared_envelope(D, sr, 50.0, [1, 2], psi, plan, None, near)
    >>> g = env.at(0, t.size, 0)
    >>> bool(np.abs(g - (1 + 0.4 * np.sin(2 * np.pi * 0.5 * t)))[5 * sr:-5 * sr].max() < 0.1)
    True
    >>> steady = hum + 0.05 * rng.standard_normal(t.size)
    >>> D = _track.demodulate(ArraySource(steady, sr), 50.0, [1, 2])
    >>> shared_envelope(D, sr, 50.0, [1, 2], psi, plan, None, block_means(D, sr, [1, 2], psi, plan, keep_power=True)[4]) is None
    True
    """
    J, C, K = D.shape
    if J < 3 or K < MIN_LINES:
        return None
    m = _track.chunk_length(sr)
    fs = sr / m
    tj = np.arange(J) * m + (m - 1) / 2
    cyc_b = None
    if main_amps is not None:
        centres = np.arange(plan.count) * float(plan.hop)
        cyc_b = np.mod(centres * (f_ref / sr), 1.0) + PhaseTrack(psi, sr, f_ref, jumps).offset_cycles(centres)
    gains, width, steps = np.ones((J, C)), None, set()
    for c in range(C):
        num = np.zeros(J, complex)
        W = np.zeros(J)
        # the same ratio with each line's content power taken as its median: the step test's
        # (a step of the hum itself raises the power measured beside the line for a while, and
        # with it the step would weight itself out of its own test)
        num_s = np.zeros(J, complex)
        W_s = np.zeros(J)
        for i, k in enumerate(ks):
            u = D[:, c, i].astype(np.complex128) * phase_turn(psi, k)
            path = None
            if main_amps is not None:
                # the paths are in each block's own reference: back to the baseband's, as a baseband sum
                path = main_amps[:, c, i] * np.exp(-2j * np.pi * np.mod(k * cyc_b, 1.0)) * (m / 2.0)
            T = _subtracted(u, tj, plan, path)
            q = np.maximum(near[:, c, i].astype(np.float64), 1e-300)
            num += np.conj(T) * u / q
            W += np.abs(T) ** 2 / q
            q_med = float(np.median(q))
            num_s += np.conj(T) * u / q_med
            W_s += np.abs(T) ** 2 / q_med
        G = num / np.maximum(W, 1e-300)
        cuts = level_steps(num_s / np.maximum(W_s, 1e-300), W_s, fs, leak_chunks(f_ref, sr))
        best, degree = _choose_width(G, W, fs, cuts)
        if best is not None:
            gains[:, c] = _smooth(G.real, W, max(3, int(round(best * fs))), cuts, degree)
            width = best if width is None else min(width, best)
            # a step lies between chunks j - 1 and j: at the first sample of chunk j
            steps.update(round(j * m / sr, 2) for j in cuts)
    return Envelope(t=tj, gain=gains, width_s=width, steps_s=tuple(sorted(steps))) if width is not None else None


def _choose_width(G: np.ndarray, W: np.ndarray, fs: float, cuts=()) -> tuple[float | None, int]:
    """The Hann width and smoother (``DEGREES``: the moving mean, the local quadratic) with the
    largest expected benefit ``E_re - 2 E_im`` among those whose real part holds ``KAPPA`` times
    the imaginary part's energy there and at the next wider width (a change of level that shows
    at one width shows at twice it; content moves the real part at one width only now and then);
    ``(None, 0)`` when none does. The local quadratic passes more of the content's noise at a
    width (``E_im`` is larger) and less of a curved level's bias: the benefit weighs the two."""
    best, best_b = None, 0.0
    # a level that steps is flat between its steps: there the local quadratic only adds the
    # noise of its ends beside each step (and the real part of a switch's ramp, which its
    # benefit counted as level: 0.1-1.6 dB lost on switched hum)
    for degree in (DEGREES if not len(cuts) else (0,)):
        if degree and best is None:
            # the quadratic only where the moving mean shows a change of level: a steady hum (an
            # hour of it) is not smoothed again, at several times the cost
            break
        energies = []
        for s in WIDTHS_S:
            n = max(3, int(round(s * fs)))
            if degree and s < QUADRATIC_MIN_S:
                energies.append((0.0, np.inf))
                continue
            sm = _smooth(G - 1.0, W, n, cuts, degree)        # both parts in one pass
            energies.append((float(np.sum(W * sm.real ** 2)), float(np.sum(W * sm.imag ** 2))))
        real = [e_re > KAPPA * e_im for e_re, e_im in energies]
        for i, s in enumerate(WIDTHS_S):
            benefit = energies[i][0] - 2.0 * energies[i][1]
            if real[i] and real[min(i + 1, len(real) - 1)] and benefit > best_b:
                best, best_b = (s, degree), benefit
    return best if best is not None else (None, 0)
