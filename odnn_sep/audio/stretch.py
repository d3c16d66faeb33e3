"""The tracked comb's phasor powers, evaluated once per hop-long stretch of the input.

Fit blocks are ``2 hop`` long and overlap by half, so every sample lies in two blocks. Along a
refined phase track (finetrack.PhaseTrack) the phasors of block ``b`` in its own reference (its
centre ``c_b``) are ``exp(2 pi i k (Phi(t) - Phi(c_b)))``; over the block's first half they are
those of the stretch before, in that stretch's reference (the previous block's centre), times
the constant ``exp(-2 pi i k (Phi(c_b) - Phi(c_{b-1})))``. So each stretch's powers are evaluated
once, in the reference of the block centred at its start, and a block's sums and synthesis take
the two stretches with that constant folded into the few coefficients: half the phase and
power evaluations of evaluating every block's own powers, and half the memory.
"""
from __future__ import annotations

import numpy as np

WHOLE_CHUNK = 1 << 16   # samples per step of the phase's rounding to whole cycles (a small work array)
SLOTS = 3               # stretches kept: the two of the current block and the next one (worker thread)


def phasor_powers(cyc: np.ndarray, ks, Z: np.ndarray, r32: np.ndarray, whole: np.ndarray):
    """``Z[i] = exp(2 pi i ks[i] cyc)`` in single precision: the fraction of the phase ``cyc``
    (cycles, float64) rounded to float32, one phasor by cosine and sine, its powers by repeated
    multiplication (as :func:`fit.block_basis`).

    Parameters
    ----------
    cyc : (n,) float64 array
        Phase in cycles.
    ks : sequence of int
        Increasing harmonic numbers (>= 1).
    Z : (K, >= n) complex64 array
        Receives the powers in ``Z[:, :n]``.
    r32 : (>= n,) float32 array
        Work array.
    whole : (WHOLE_CHUNK,) float64 array
        Work array.

    Examples
    --------
    >>> cyc = np.array([0.0, 0.25, 1.5]); Z = np.empty((2, 3), np.complex64)
    >>> phasor_powers(cyc, [1, 2], Z, np.empty(3, np.float32), np.empty(WHOLE_CHUNK))
    >>> want = np.exp(2j * np.pi * np.outer([1, 2], cyc))
    >>> bool(np.abs(Z - want).max() < 1e-6)
    True
    """
    n = cyc.shape[0]
    r32 = r32[:n]
    for a in range(0, n, WHOLE_CHUNK):          # (elementwise: the chunking changes no value)
        b = min(a + WHOLE_CHUNK, n)
        np.rint(cyc[a:b], out=whole[: b - a])
        np.subtract(cyc[a:b], whole[: b - a], out=r32[a:b], casting="same_kind")
    Zn = Z[:, :n]
    z = Zn[0] if ks[0] == 1 else np.empty(n, np.complex64)
    r32 *= np.float32(2 * np.pi)
    np.cos(r32, out=z.real)
    np.sin(r32, out=z.imag)
    kprev, src = 1, z
    for i, k in enumerate(ks):
        if k == 1:
            continue
        np.multiply(src, z, out=Zn[i])
        for _ in range(k - kprev - 1):
            np.multiply(Zn[i], z, out=Zn[i])
        kprev, src = k, Zn[i]


class StretchPowers:
    """Powers of the tracked phasor per stretch ``s`` (samples ``s hop .. (s + 1) hop``, in the
    reference of the phase at ``s hop``), kept in :data:`SLOTS` slots. :meth:`compute` of one
    stretch may run in a worker thread while the two other slots are read.

    Parameters
    ----------
    ks : sequence of int
        Tracked harmonics.
    hop : int
        Stretch length (half a block).
    n_frames : int
        Input length (the last stretch may be shorter).
    phase : finetrack.PhaseTrack
        The phase ``Phi``.

    Examples
    --------
    >>> from odnn_sep.audio.finetrack import PhaseTrack, chunk_times
    >>> sr = 1000; ph = PhaseTrack(0.1 * chunk_times(100, sr), sr, 50.0)     # 50.1 Hz
    >>> sp = StretchPowers([1, 3], 200, 1000, ph)
    >>> parts = sp.parts(200, 400, 400)           # the block centred at sample 400
    >>> [(a, m) for _, a, m, _ in parts]
    [(0, 200), (200, 200)]
    >>> Z = np.hstack([P * (1 if rho is None else rho[:, None]) for P, _, _, rho in parts])
    >>> want = np.exp(2j * np.pi * np.outer([1, 3], ph.cycles(200, 400, 400)))
    >>> bool(np.abs(Z - want).max() < 1e-5)
    True
    """

    def __init__(self, ks, hop: int, n_frames: int, phase):
        self.ks, self.hop, self.n_frames, self.phase = list(ks), int(hop), int(n_frames), phase
        self._P = [None] * SLOTS
        self._work = [None] * SLOTS
        self._held = [None] * SLOTS       # slot -> the stretch it holds

    def length(self, s: int) -> int:
        """Samples in stretch ``s``."""
        return max(0, min(self.hop, self.n_frames - s * self.hop))

    def compute(self, s: int):
        """Evaluate stretch ``s`` into its slot (nothing for an empty stretch)."""
        m = self.length(s)
        if m <= 0:
            return
        slot = s % SLOTS
        self._held[slot] = None
        if self._P[slot] is None:
            self._P[slot] = np.empty((len(self.ks), self.hop), np.complex64)
            self._work[slot] = (np.empty(self.hop, np.float32), np.empty(WHOLE_CHUNK))
        c = s * self.hop
        cyc = self.phase.cycles(c, m, c, scratch=("stretch", slot))
        phasor_powers(cyc, self.ks, self._P[slot], *self._work[slot])
        self._held[slot] = s

    def stretch(self, s: int) -> np.ndarray:
        """Stretch ``s``'s powers (K, length), evaluated here when its slot does not hold them."""
        slot = s % SLOTS
        if self._held[slot] != s:
            self.compute(s)
        return self._P[slot][:, : self.length(s)]

    def parts(self, i0: int, n: int, centre: int):
        """The block of samples ``i0 .. i0 + n`` centred at ``centre`` (a multiple of ``hop``) as
        ``[(P, a, m, rho)]``: powers ``P`` (K, m) of its samples ``a .. a + m`` and the factor
        ``rho`` (K,) complex (None: one) that turns them to the block's reference."""
        hop = self.hop
        b = centre // hop
        out = []
        end = min(centre, i0 + n)
        if i0 < end:                        # the first half: the previous stretch, turned
            s = b - 1
            dc = self.phase.cycles_at(np.array([float(centre)]), float(s * hop))[0]
            rho = np.exp(-2j * np.pi * np.mod(np.asarray(self.ks, float) * dc, 1.0))
            out.append((self.stretch(s)[:, i0 - s * hop: end - s * hop], 0, end - i0, rho))
        if i0 + n > centre:                 # the second half: this block's own stretch
            out.append((self.stretch(b)[:, : i0 + n - centre], centre - i0, i0 + n - centre, None))
        return out
