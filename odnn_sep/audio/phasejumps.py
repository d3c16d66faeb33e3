"""Large steps of the hum's phase, estimated jointly over the harmonics (a splice, a source switched).

A splice moves the hum's waveform in time: the fundamental's phase jumps by ``delta`` cycles and
harmonic ``k``'s by ``k delta``. The fine track (finetrack.py, phasesteps.py) averages the
harmonics' wrapped phase errors; once ``k delta`` passes half a cycle for some of them that
average means nothing (at ``delta = 0.5`` the odd harmonics flip sign and the even ones do not
move), no step is found, and the odd harmonics then fail the lock tests: about a third of random
splices kept nearly all their hum.

Here the jump is estimated from every harmonic at once, before the fine track. On the decimated
baseband (turned by the block track's phase) the complex means of ``w`` samples before (``B``)
and after (``A``) each instant are compared: a jump ``delta`` with a common level ratio ``g``
predicts ``A_k = g B_k exp(2 pi i k delta)`` for every harmonic and channel. With weights
``omega`` (the inverse variance of ``A - B`` from the line's local scatter), the best ``delta``
maximises ``S(delta) = sum omega Re(A conj(B) exp(-2 pi i k delta))``, and the likelihood-ratio
statistic of the jump against none is ``(S(delta)^2 - S(0)^2) / sum omega |B|^2``. A jump is
taken where that exceeds ``LR_JUMP``, also without the harmonic that gains most from it (else it
is that line's own phase change: a note partial), the prediction explains at least ``EXPLAINED``
of the change's weighted energy, and ``delta`` is at least ``MIN_JUMP`` cycles from a whole
cycle: smaller jumps are followed by the fine track's own step search, which was tuned on them.
Fewer than ``MIN_LINES`` harmonics are not searched.

Each jump is then placed at the 10 ms chunk where the chunk sums before and after it agree best
with the phases on either side (phasesteps.place_steps, over the whole test window: the largest
change can lie some samples off the jump under a loud host) and added to the starting phase, so
the lock tests and the fine track start from a phase without it. At the end every step the phase
then holds, these and the fine track's smaller ones, is placed to the sample (phaseplace.py).

Cost: the change statistic at every instant is one pass of cumulative sums; the search over
``delta`` runs only at its local maxima that already show a large change (at most
``MAX_CANDIDATES``).
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

LR_JUMP = 100.0        # likelihood ratio a jump needs (a z-score of 10, as phasesteps.Z_STEP)
EXPLAINED = 0.8        # share of the change's weighted energy the jump must explain
MIN_JUMP = 0.2         # cycles: smaller steps are left to phasesteps.find_steps
MAX_CANDIDATES = 256   # instants searched over delta (the largest changes), plus one per 5 s
LOCAL = 2              # a candidate is the largest change within this many samples (0.2 s)
MIN_LINES = 2          # harmonics a jump is estimated on (one can match any phase change)
EDGE_FRACTION = 0.25   # instants nearer an end than this share of the window are not searched
MAX_JUMPS = 64         # as phasesteps.MAX_STEPS
GRID_PER_K = 16        # delta grid points per cycle of the highest harmonic


def _local_noise(v: np.ndarray, span: int) -> np.ndarray:
    """Each line's local noise variance (nd, C, K): from successive differences (blind to the
    line's slow changes and to one step), the median over blocks of ``span`` samples (blind to a
    few loud instants; blocks rather than a running median, which costs ``span`` times more on
    an hour of input)."""
    d2 = np.abs(np.diff(v, axis=0)) ** 2 / (2 * np.log(2.0))      # median of |d|^2 is 2 var ln 2
    d2 = np.concatenate([d2[:1], d2], axis=0)
    n = len(d2)
    nb = -(-n // span)
    pad = np.concatenate([d2, np.repeat(d2[-1:], nb * span - n, axis=0)], axis=0)
    med = np.median(pad.reshape(nb, span, *d2.shape[1:]), axis=1)
    floor = 1e-12 * np.median(d2) + 1e-300
    return np.maximum(np.repeat(med, span, axis=0)[:n], floor)


def _delta_grid(ks: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The coarse grid of ``delta`` and its phasors ``exp(-2 pi i k delta)`` (G, K), made once
    per search (an hour of music can have a thousand candidates)."""
    grid = np.arange(int(GRID_PER_K * ks.max()) + 1) / (GRID_PER_K * ks.max())
    return grid, np.exp(-2j * np.pi * np.outer(grid, ks))


def _delta_search(A: np.ndarray, B: np.ndarray, om: np.ndarray, ks: np.ndarray,
                  coarse: tuple[np.ndarray, np.ndarray] | None = None) -> tuple[float, float, float]:
    """(delta, likelihood ratio, share explained) at one instant; ``A``, ``B``, ``om`` (C, K);
    ``coarse`` from :func:`_delta_grid` (made here when not given)."""
    cross = (om * A * np.conj(B)).sum(axis=0)                     # (K,)
    Q = float((om * np.abs(B) ** 2).sum())
    R0 = float((om * np.abs(A - B) ** 2).sum())
    if Q <= 0 or R0 <= 0:
        return 0.0, 0.0, 0.0
    grid, phasors = coarse if coarse is not None else _delta_grid(ks)
    S = np.real(phasors @ cross)                                    # (G,)
    j = int(np.argmax(S))
    # a finer look around the best grid point (the grid is 1/16 cycle of the highest harmonic)
    fine = grid[j] + np.linspace(-1, 1, 33) / (GRID_PER_K * ks.max())
    Sf = np.real(np.exp(-2j * np.pi * np.outer(fine, ks)) @ cross)
    i = int(np.argmax(Sf))
    delta, s_best = float(fine[i]) % 1.0, float(Sf[i])
    s0 = max(float(np.real(cross.sum())), 0.0)
    lr = (max(s_best, 0.0) ** 2 - s0 ** 2) / Q
    # weighted misfit left with the jump and the best common level: sum omega |A|^2 - S^2 / Q
    energy = float((om * np.abs(A) ** 2).sum())
    r_best = energy - max(s_best, 0.0) ** 2 / Q
    r_none = energy - s0 ** 2 / Q
    explained = 1.0 - max(r_best, 0.0) / r_none if r_none > 0 else 0.0
    # a jump is the comb's: it must stand (the same delta, the same test) without the line that
    # gains most from it, or it is that line's own phase change (a note partial), which some
    # delta always matches
    turned = np.real(cross * np.exp(-2j * np.pi * ks * delta))
    top = int(np.argmax(turned - np.real(cross)))
    keep = np.arange(len(ks)) != top
    q_rest = float((om[:, keep] * np.abs(B[:, keep]) ** 2).sum())
    s_rest, s0_rest = max(float(turned[keep].sum()), 0.0), max(float(np.real(cross[keep]).sum()), 0.0)
    if q_rest <= 0 or (s_rest ** 2 - s0_rest ** 2) / q_rest <= LR_JUMP:
        return delta, lr, 0.0
    return delta, lr, explained


def find_jumps(v: np.ndarray, ks, w: int) -> list[tuple[int, float]]:
    """Jumps of the fundamental's phase in the decimated baseband ``v``.

    Parameters
    ----------
    v : (nd, C, K) complex array
        The harmonics' baseband, turned by a starting phase and decimated (finetrack.py).
    ks : (K,) array
        Harmonic numbers.
    w : int
        Samples averaged on each side of an instant.

    Returns
    -------
    list of (int, float)
        ``(i, delta)``: the phase steps by ``delta`` cycles (in [0, 1)) between samples ``i - 1``
        and ``i``; sorted by ``i``, at least ``w`` apart. An input shorter than ``4 w`` is
        searched with windows of a quarter of its length (none under 4 samples: 0.4 s).

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> ks = np.arange(1.0, 6.0)
    >>> v = np.ones((300, 1, 5), complex) + 0.05 * rng.standard_normal((300, 1, 5))
    >>> v[170:] *= np.exp(2j * np.pi * ks * 0.5)               # odd harmonics flip, even ones do not move
    >>> [(i, round(d, 2)) for i, d in find_jumps(v, ks, 24)]
    [(170, 0.5)]
    >>> find_jumps(v[:150], ks, 24)
    []
    """
    v = np.asarray(v)
    ks = np.asarray(ks, dtype=np.float64)
    nd = len(v)
    w = min(w, nd // 4)                    # a short input: shorter windows (the same test)
    if w < 4:
        return []
    var = _local_noise(v, 2 * w)
    cs = np.concatenate([np.zeros((1, *v.shape[1:]), v.dtype), np.cumsum(v, axis=0)], axis=0)
    # every instant at least EDGE_FRACTION w from the ends: near an end the side that reaches it
    # is shorter (a splice half a second from the start still moves the phase of that half second)
    edge = max(4, int(EDGE_FRACTION * w))
    idx = np.arange(edge, nd - edge + 1)
    na = np.minimum(w, nd - idx)[:, None, None]
    nb = np.minimum(w, idx)[:, None, None]
    A = (cs[idx + na[:, 0, 0]] - cs[idx]) / na                       # (m, C, K): means after
    B = (cs[idx] - cs[idx - nb[:, 0, 0]]) / nb                       # means before
    om = (2 * na * nb / (na + nb)) / (2.0 * var[idx])                # inverse variance of A - B
    R0 = (om * np.abs(A - B) ** 2).sum(axis=(1, 2))
    dof = 2 * v.shape[1] * v.shape[2]
    # candidates: local maxima of the change that could pass the test at all (a jump's likelihood
    # ratio is at most the change's weighted energy beyond what noise gives). Only the nearest
    # samples are compared: a note's onset on one harmonic a second from a splice changes more
    # than the splice does, and must not hide it
    big = np.flatnonzero((R0 - dof > LR_JUMP) & (R0 == ndimage.maximum_filter1d(R0, 2 * LOCAL + 1)))
    big = big[np.argsort(-R0[big])][:MAX_CANDIDATES + nd // 50]
    found = []
    coarse = _delta_grid(ks) if len(big) else None
    for j in big:
        delta, lr, explained = _delta_search(A[j], B[j], om[j], ks, coarse)
        dist = min(delta, 1.0 - delta)
        if lr > LR_JUMP and explained >= EXPLAINED and dist >= MIN_JUMP:
            found.append((lr, int(idx[j]), delta))
    out = []
    for _lr, i, delta in sorted(found, reverse=True):
        if len(out) >= MAX_JUMPS:
            break
        if all(abs(i - q) > w for q, _ in out):
            out.append((i, delta))
    return sorted(out)


def window(sr: int) -> int:
    """Samples averaged on each side of an instant: 2.4 s of the decimated baseband, the window
    of the fine track's own step search (twice finetrack.shortest_kernel).

    Parameters
    ----------
    sr : int
        Sample rate (Hz).

    Returns
    -------
    int

    Examples
    --------
    >>> window(44100), window(8000)
    (24, 24)
    """
    from odnn_sep.audio import finetrack as _ft

    return 2 * _ft.shortest_kernel(sr)


def follow(D, sr: int, ks, psi0: np.ndarray, w: int) -> tuple[np.ndarray, dict[int, int]]:
    """``psi0`` with the jumps :func:`find_jumps` finds in the chunk sums ``D`` added, each at
    the chunk where it starts (phasesteps.place_steps), and those jumps as cuts for the fine track.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums of the harmonics ``ks`` (track.demodulate).
    sr : int
        Sample rate (Hz).
    ks : (K,) array
        Harmonic numbers.
    psi0 : (J,) array
        Starting phase (cycles at the chunk centres): the block track's.
    w : int
        Samples (decimated) averaged on each side of an instant.

    Returns
    -------
    psi : (J,) array
        ``psi0`` plus the jumps.
    cuts : dict
        Decimated index of each jump -> its first chunk (``finetrack.refine_phase(cuts=...)``).

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> from odnn_sep.audio.track import demodulate
    >>> sr = 2000; t = np.arange(30 * sr) / sr
    >>> ph = 2 * np.pi * 50 * t + np.pi * (t >= 14.0)               # half a cycle at 14 s
    >>> x = sum(np.cos(k * ph) for k in (1, 2, 3)) + 0.1 * np.random.default_rng(0).standard_normal(t.size)
    >>> D = demodulate(ArraySource(x, sr), 50.0, [1, 2, 3])
    >>> psi, cuts = follow(D, sr, np.array([1.0, 2, 3]), np.zeros(len(D)), 24)
    >>> cuts, round(float(psi[-1] - psi[0]), 2)
    ({140: 1400}, 0.5)
    """
    from odnn_sep.audio import finetrack as _ft
    from odnn_sep.audio import phasesteps as _steps

    ks = np.asarray(ks, dtype=np.float64)
    nd = D.shape[0] // _ft.DECIM
    if len(ks) < MIN_LINES:
        return psi0, {}
    v = _ft.decimated_baseband(D, psi0, ks, np.ones(len(ks), bool), nd)
    jumps = find_jumps(v, ks, w)
    if not jumps:
        return psi0, {}
    psi = psi0.copy()
    cuts = {}
    for q, delta in jumps:
        # the jump nearest zero of the equivalent ones (delta and delta - 1 move every harmonic alike)
        d = delta - 1.0 if delta > 0.5 else delta
        c = v[max(q - w, 0): q].mean(axis=0)                     # the lines' amplitudes just before
        err = np.zeros(nd)
        err[q:] = d
        start = _steps.place_steps(D, psi0, ks, c, err, [q], _ft.DECIM, span=w)[0]
        psi[start:] += d
        cuts[int(round(start / _ft.DECIM))] = start     # the decimated sample where it now lies
    return psi, cuts


__all__ = ["find_jumps", "follow", "window", "LR_JUMP", "EXPLAINED", "MIN_JUMP", "MAX_CANDIDATES",
           "MAX_JUMPS", "MIN_LINES", "EDGE_FRACTION"]
