"""Steps in the hum's phase: a recording spliced or a source switched over.

Cut a recording and join it elsewhere, or switch the hum's source to another phase of the mains,
and every harmonic's phase jumps at one instant: by ``k`` times the fundamental's jump (a splice
moves the waveform in time). The fine track (finetrack.py) low-passes its phase correction to
about 0.5 s, so it spreads such a jump over a second or two, and the hum there is left nearly
whole (about -8 dB for two seconds, where the rest of the recording is at -50 dB).

Here the weighted phase estimates of one round (``e``, cycles, at 10 Hz, with their precision) are
tested for a step at every instant: a weighted least-squares fit of a quadratic plus a step over a
window of ``2 w`` samples centred there, its step's z-score against the fit's own scatter (never
less than ``MIN_SCATTER`` of the estimates' stated noise). A step is taken where ``|z|`` exceeds ``Z_STEP``, is the
largest within ``w`` on either side and moves the phase by at least ``MIN_STEP`` cycles. The
correction is then smoothed piece by piece between the steps, so it keeps each step whole.

Smooth frequency modulation is taken up by the quadratic and inflates the scatter, so it does not
make steps; a step where there is none costs little, as each piece is still smoothed as before.
"""
from __future__ import annotations

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

Z_STEP = 10.0      # z-score a step needs (the quadratic's misfit included in its scatter)
MIN_STEP = 0.01    # cycles of the fundamental (3.6 deg): smaller jumps leave hum below -30 dB at k <= 5
# The estimates' stated noise comes from each line's scatter about its mean over the whole input,
# which a phase error of the track inflates (before a jump is followed, by 10x in variance and
# more); the window's own scatter is used, but never below this share of the stated noise.
MIN_SCATTER = 0.1
MAX_STEPS = 64     # a recording with more jumps than this is not spliced: it has no steady phase


def find_steps(e: np.ndarray, prec: np.ndarray, w: int) -> list[int]:
    """Indices ``i`` where the estimates ``e`` step between samples ``i - 1`` and ``i``.

    Parameters
    ----------
    e : (n,) array
        Phase estimates (cycles).
    prec : (n,) array
        Their precision (``den`` of ``finetrack.refine_phase``: the variance of an estimate is
        ``1 / (2 prec)`` rad^2); 0 where there is no evidence.
    w : int
        Half-width of the test window (samples).

    Returns
    -------
    list of int
        Sorted step positions; empty when ``e`` is shorter than ``4 w``.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> t = np.arange(300) / 10.0
    >>> e = 0.002 * np.sin(2 * np.pi * t / 20) + 1e-3 * rng.standard_normal(300)
    >>> prec = np.full(300, 1 / (2 * (2 * np.pi * 1e-3) ** 2))
    >>> find_steps(e, prec, 24), find_steps(e + 0.1 * (t >= 15), prec, 24)
    ([], [150])
    """
    e = np.asarray(e, dtype=np.float64)
    n = len(e)
    if w < 4 or n < 4 * w:
        return []
    omega = 2.0 * (2 * np.pi) ** 2 * np.maximum(np.asarray(prec, dtype=np.float64), 0.0)   # 1 / var (cycles^-2)
    s = (np.arange(2 * w) - w + 0.5) / w
    X = np.stack([np.ones(2 * w), s, s * s, (s > 0).astype(float)], axis=1)             # (2w, 4)
    E = sliding_window_view(e, 2 * w)                                                    # (m, 2w), window j: j..j+2w
    Om = sliding_window_view(omega, 2 * w)
    # the normal equations of every window as matrix products (no (m, 2w, 4, 4) intermediate: an
    # hour of input has 36000 windows)
    G = (Om @ (X[:, :, None] * X[:, None, :]).reshape(2 * w, 16)).reshape(-1, 4, 4)
    b = np.einsum("mi,mi,ia->ma", Om, E, X)
    # (the 1-norm condition number: a third of the cost of the 2-norm one's SVDs on an hour of
    # windows, within a factor 4 of it for a 4 x 4 matrix)
    with np.errstate(all="ignore"):
        ok = np.linalg.cond(G, 1) < 1e10
    z = np.zeros(len(E))
    delta = np.zeros(len(E))
    if ok.any():
        Ginv = np.linalg.inv(G[ok])
        beta = np.einsum("mab,mb->ma", Ginv, b[ok])
        # weighted residual sum of squares of the fit: sum(omega e^2) - beta . b
        rss = np.einsum("mi,mi,mi->m", Om, E, E)[ok] - np.einsum("ma,ma->m", beta, b[ok])
        s2 = np.maximum(np.maximum(rss, 0.0) / (2 * w - 4), MIN_SCATTER)               # the window's own scatter
        delta[ok] = beta[:, 3]
        z[ok] = beta[:, 3] / np.sqrt(np.maximum(Ginv[:, 3, 3] * s2, 1e-300))
    az = np.where(np.abs(delta) >= MIN_STEP, np.abs(z), 0.0)
    steps = []
    for j in np.argsort(-az):
        if az[j] <= Z_STEP or len(steps) >= MAX_STEPS:
            break
        if all(abs(j - q) > w for q in steps):
            steps.append(int(j))
    return sorted(q + w for q in steps)


def piecewise(fn, num: np.ndarray, den: np.ndarray, steps: list[int]) -> np.ndarray:
    """``fn(num, den)`` applied to each piece between ``steps`` and joined (a smoother that must
    not carry a step across).

    Parameters
    ----------
    fn : callable
        ``fn(num_piece, den_piece) -> piece`` (same length).
    num, den : (n,) arrays
        Weighted estimates and their precision.
    steps : list of int
        Piece boundaries (:func:`find_steps`).

    Returns
    -------
    (n,) float array

    Examples
    --------
    >>> piecewise(lambda a, b: np.full(len(a), a.mean()), np.array([1.0, 1, 3, 3]), np.ones(4), [2]).tolist()
    [1.0, 1.0, 3.0, 3.0]
    """
    out = np.empty(len(num))
    edges = [0, *steps, len(num)]
    for a, b in zip(edges[:-1], edges[1:]):
        if b > a:
            out[a:b] = fn(num[a:b], den[a:b])
    return out


def place_steps(D, psi: np.ndarray, ks, c: np.ndarray, err: np.ndarray, steps: list[int], decim: int,
                span: int = 1) -> list[int]:
    """The chunk at which each step starts, to the chunk (10 ms) rather than the decimated sample.

    A step found between decimated samples ``q - 1`` and ``q`` lies in their ``2 decim`` chunks.
    Each chunk is scored against the harmonics' mean amplitudes ``c`` with the phase before the
    step (``psi + err[q - 1]``) and after it (``psi + err[q]``); the boundary taken makes the chunks
    before it agree with the first and those after with the second best.

    Parameters
    ----------
    D : (J, C, K) complex array
        Chunk sums of the harmonics ``ks``.
    psi : (J,) array
        The phase (cycles) the correction ``err`` applies to.
    ks : (K,) array
        Harmonic numbers.
    c : (C, K) complex array
        The harmonics' mean turned amplitudes (per decimated sample).
    err : (nd,) array
        The correction at the decimated samples.
    steps : list of int
        Decimated indices of the steps (:func:`find_steps`).
    decim : int
        Chunks per decimated sample.
    span : int, default 1
        Decimated samples searched on each side of ``q``.

    Returns
    -------
    list of int
        Chunk index of each step's first chunk after it.

    Examples
    --------
    >>> J = 60; psi = np.zeros(J); D = np.ones((J, 1, 1), complex)
    >>> D[37:, 0, 0] = np.exp(2j * np.pi * 0.2)               # the phase moves by 0.2 cycle at chunk 37
    >>> place_steps(D, psi, np.array([1.0]), np.ones((1, 1)), np.array([0.0] * 3 + [0.2] * 3), [3], 10)
    [37]
    """
    from odnn_sep.audio.finetrack import phase_turn

    out = []
    for q in steps:
        a, b = max(q - span, 0) * decim, min((q + span) * decim, len(psi))
        score = []
        for side in (err[q - 1], err[q]):
            turned = np.stack([phase_turn(psi[a:b] + side, k) for k in ks], axis=1)        # (n, K)
            score.append(np.real(D[a:b] * turned[:, None, :] * np.conj(c)[None]).sum(axis=(1, 2)))
        before = np.concatenate([[0.0], np.cumsum(score[0])])
        after = np.concatenate([np.cumsum(score[1][::-1])[::-1], [0.0]])
        out.append(a + int(np.argmax(before + after)))
    return out


__all__ = ["find_steps", "piecewise", "place_steps", "Z_STEP", "MIN_STEP", "MIN_SCATTER", "MAX_STEPS"]
