"""Steady lines of the content right beside a hum line: found, fitted jointly with the hum, and kept.

A drum loop placed to the sample has a line on every multiple of its pattern's rate, so a line at
exactly 60.000 Hz sits under a hum line at 60.045 Hz, half a resolution cell of a 10 s input away.
The block fit and the amplitude paths see one line there: whatever of the loop's line projects on
the hum's basis is taken for hum and subtracted (18 dB of gain where 40 dB were possible).

Here, per harmonic, on pass 1's chunk sums (a 10 Hz baseband in the fixed frame ``k f_ref``):

1. the hum is one column, the tracked phase ``exp(2 pi i k psi(t))`` at one complex amplitude per
   channel (a drifting hum is frequency-modulated there, a host line is not);
2. steady lines at fixed frequencies within ``band_hz`` (at most ``BAND_CELLS`` resolution cells)
   of the hum's mean frequency are added one by one where the projected periodogram of the
   residual peaks (frequency shared by the channels), and kept only where the data support them:
   the peak is a peak inside the band (not the skirt of a note outside it) and stands
   ``MIN_RATIO`` over the residual's floor; the mirror frequency across the hum line holds far
   less (a hum whose level or phase moves against the track leaves conjugate-symmetric sidebands
   there; a host line has no mirror); the line is not the hum itself (at least ``MIN_CELLS`` of a
   cell from it, and weaker than the hum it sits beside) and not within the hum's own misfit (at least ``MIN_SHARE`` of its amplitude);
3. where the hum's amplitudes are read with near-power weights (the amplitude paths of inputs of
   several blocks: the hum is read in the quiet moments), the search is made again with the same
   weights: a drum's hits or a gated note are weaker there than on average, and taking their
   average line out would leave it alone in the pauses (a gated bass note lost 9 dB that way);
4. the lines kept are taken out of the chunk sums and of the samples before the hum is fitted
   (:class:`WithoutLines`), and the output keeps them: they are content.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.audio import finetrack as _finetrack
from odnn_sep.audio import track as _track
from odnn_sep.audio.nearpower import near_power

MAX_LINES = 3        # host lines per harmonic at most
MIN_RATIO = 30.0     # a line's projected power over the residual's floor (chi2(2C)/2 ~ p 1e-13 at C=1)
MIRROR_SHARE = 0.25  # the mirror across the hum line holds at most this share of the line's power
MIN_SHARE = 0.02     # a line at least this share of the hum line's amplitude beside it (-34 dB)
MIN_CELLS = 0.2      # a host line stands at least this many resolution cells (1/T) from the hum's mean frequency
MIN_SECONDS = 4.0    # shorter inputs: nothing is looked for (a 10 Hz baseband of 40 samples)
MIN_HARMONICS = 2    # a comb of one line: its track is that line's alone, and a note beside it pulls the
                     # track off the hum, which then stands beside the track as steady as a content line
BAND_CELLS = 2.0     # lines looked for within this many resolution cells of the whole input (farther ones
                     # the whole-input amplitude paths resolve themselves)
AGREE = 0.5          # the line's amplitude read in the quiet moments (near-power weights) differs from the
                     # plain one by at most this share: a steady line is there all the time
PAD = 16             # zero-padding of the periodogram (finer than a cell) ...
MAX_FFT = 1 << 16    # ... up to this length (long inputs: twice their length; the peak is refined anyway)


@dataclass(frozen=True)
class HostLine:
    """A steady line of the content: frequency (Hz) and complex peak amplitude per channel
    (``Re(amp exp(2 pi i freq t))``, ``t`` from the input's first sample), and the harmonic it sits
    beside.

    Examples
    --------
    >>> import numpy as np
    >>> line = HostLine(freq_hz=60.0, amp=np.array([0.1 + 0.0j]), harmonic=1)
    >>> t = np.arange(4) / 480.0
    >>> np.round(np.real(line.amp[0] * np.exp(2j * np.pi * line.freq_hz * t)), 4).tolist()
    [0.1, 0.0707, 0.0, -0.0707]
    """

    freq_hz: float
    amp: np.ndarray
    harmonic: int


def find(D: np.ndarray, sr: int, f_ref: float, ks, psi: np.ndarray, band_hz: float,
         weighted: bool = False) -> list[HostLine]:
    """Steady host lines within ``band_hz`` of each tracked harmonic (see the module text).

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
        Tracked phase of the fundamental (cycles, relative to ``f_ref t``) at the chunk centres.
    band_hz : float
        How far from a harmonic's mean frequency lines are looked for (Hz), at most ``BAND_CELLS``
        resolution cells of the input.
    weighted : bool, default False
        Whether the hum's amplitudes will be read with near-power weights (the amplitude paths of
        inputs of several blocks): the lines are then fitted with the same weights.

    Returns
    -------
    list of HostLine

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 2000; t = np.arange(10 * sr) / sr; rng = np.random.default_rng(0)
    >>> hum = np.cos(2 * np.pi * 60.045 * t + 1.0) + 0.5 * np.cos(2 * np.pi * 120.09 * t)
    >>> host = 0.2 * np.cos(2 * np.pi * 60.0 * t + 0.3) + 0.05 * rng.standard_normal(t.size)
    >>> D = _track.demodulate(ArraySource(hum + host, sr), 60.0, [1, 2])
    >>> psi = 0.045 * _finetrack.chunk_times(len(D), sr)
    >>> [(h.harmonic, round(h.freq_hz, 3), round(float(abs(h.amp[0])), 2)) for h in find(D, sr, 60.0, [1, 2], psi, 0.6)]
    [(1, 60.0, 0.2)]
    >>> find(_track.demodulate(ArraySource(hum + 0.05 * rng.standard_normal(t.size), sr), 60.0, [1, 2]),
    ...      sr, 60.0, [1, 2], psi, 0.6)
    []
    """
    J, C, K = D.shape
    m = _track.chunk_length(sr)
    nd = J // _finetrack.DECIM
    dt = _finetrack.DECIM * m / sr                 # decimated sample spacing (s)
    T = nd * dt
    if T < MIN_SECONDS or len(ks) < MIN_HARMONICS:
        return []
    band_hz = min(band_hz, BAND_CELLS / T)
    tj = (np.arange(nd * _finetrack.DECIM) * m + (m - 1) / 2) / sr        # chunk centres (s)
    td = tj.reshape(nd, _finetrack.DECIM).mean(axis=1)
    kk = np.asarray(ks, float)
    ones = np.ones((nd * _finetrack.DECIM, 1, K), np.complex64)
    # the hum's column per harmonic: exp(2 pi i k psi) averaged as the chunk sums are
    hum_cols = np.conj(_finetrack.decimated_baseband(ones, psi, kk, np.ones(K, bool), nd)[:, 0, :])
    W = D[: nd * _finetrack.DECIM].reshape(nd, _finetrack.DECIM, C, K).mean(axis=1).astype(np.complex128)
    dpsi = (psi[nd * _finetrack.DECIM - 1] - psi[0]) / max(tj[-1] - tj[0], 1e-9)   # mean offset (Hz)
    out = []
    for i, k in enumerate(ks):
        centre = k * dpsi                                      # hum's mean offset from k f_ref (Hz)
        found = _lines_beside(W[:, :, i], hum_cols[:, i], td, T, centre, band_hz, np.ones(nd))
        if found and weighted:
            # looked for again as the amplitude paths will read the hum: in the quiet moments (a
            # drum's hits or a gated note's line is weaker there than on average, and taking out its
            # average would leave it alone in the pauses, where the hum is read)
            sw = _quiet_weights(D[: nd * _finetrack.DECIM, :, i], psi[: nd * _finetrack.DECIM], k, sr / m, nd)
            found = _lines_beside(W[:, :, i], hum_cols[:, i], td, T, centre, band_hz, sw / sw.max())
        for off, b in found:
            f = k * f_ref + off
            # chunk sums of Re(c exp(2 pi i f t)): (c / 2) Dm exp(2 pi i off t_j) (Dirichlet kernel Dm)
            dm = _dirichlet(off, m, sr) * _decim_gain(off, m, sr)
            out.append(HostLine(freq_hz=float(f), amp=2.0 * b / dm, harmonic=int(k)))
    return out


def _dirichlet(off: float, m: int, sr: int) -> float:
    """Sum over a chunk of ``m`` samples of ``exp(2 pi i off n / sr)`` about its centre (real)."""
    x = np.pi * off / sr
    return float(m) if abs(x) < 1e-12 else float(np.sin(m * x) / np.sin(x))


def _decim_gain(off: float, m: int, sr: int) -> float:
    """Gain of the mean over DECIM chunks at ``off`` Hz (about their mean centre)."""
    x = np.pi * off * m / sr
    n = _finetrack.DECIM
    return 1.0 if abs(x) < 1e-12 else float(np.sin(n * x) / (n * np.sin(x)))


def _lines_beside(w: np.ndarray, h: np.ndarray, td: np.ndarray, T: float, centre: float, band_hz: float,
                  sw: np.ndarray):
    """Greedy search of steady lines in the decimated fixed-frame baseband ``w`` (nd, C) beside the
    hum column ``h`` (nd,), least squares weighted by ``sw ** 2``: ``[(offset from k f_ref in Hz,
    complex amplitude (C,) in w's units)]``."""
    nd, C = w.shape
    w = w * sw[:, None]
    cols = [h * sw]
    nfft = 1 << int(np.ceil(np.log2(nd * PAD if nd * PAD <= MAX_FFT else 2 * nd)))
    fs = 1.0 / (td[1] - td[0])
    freqs = np.fft.fftfreq(nfft, 1.0 / fs)
    rel = freqs - centre
    in_band = (np.abs(rel) <= band_hz) & (np.abs(rel) >= MIN_CELLS / T)
    # the residual's floor: the projected periodogram 1.5 band widths and more away from the hum,
    # within the baseband's own low-passed band (the decimation's mean over DECIM chunks)
    floor_sel = (np.abs(rel) > 1.5 * band_hz) & (np.abs(freqs) < 0.25 * fs)
    if not in_band.any() or floor_sel.sum() < 8:
        return []
    kept = []
    for _ in range(MAX_LINES):
        Q, coef, resid = _project(cols, w)
        stat = _projected_periodogram(Q, resid, sw, nfft)
        floor = float(np.median(stat[floor_sel]))
        if not floor > 0:
            break
        # lines already kept are not looked for again (a line's own frequency holds nothing more)
        free = in_band.copy()
        for f in kept:
            free &= np.abs(freqs - f) >= MIN_CELLS / T
        cand = np.where(free, stat, -np.inf)
        j = int(np.argmax(cand))
        if not cand[j] > MIN_RATIO * floor:
            break
        # a peak on the band's edge is the skirt of something outside it (a note's gated partial)
        if not (stat[(j - 1) % nfft] < stat[j] > stat[(j + 1) % nfft]) or not (in_band[(j - 1) % nfft]
                                                                           and in_band[(j + 1) % nfft]):
            break
        off = _refine(Q, resid, td, sw, freqs[j], fs / nfft)
        trial = cols + [np.exp(2j * np.pi * off * td) * sw]
        Q_t, coef_t, resid_t = _project(trial, w)
        b, a = coef_t[-1], coef_t[0]
        # the mirror across the hum line, with the line fitted: a modulation of the hum itself (its
        # level or phase moving against the track) has a sideband there as strong, a host line has none
        mirror = 2 * centre - off
        if _stat_near(Q_t, resid_t, td, sw, mirror, fs / nfft) > MIRROR_SHARE * cand[j]:
            break
        # a line this much weaker than the hum beside it is within what the hum's own misfit leaves
        # (a track's phase error of 0.01-0.02 rad on a fast-drifting grid hum)
        if np.sum(np.abs(b) ** 2) < MIN_SHARE ** 2 * np.sum(np.abs(a) ** 2):
            break
        # a "content line" stronger than the hum beside it is more likely the hum itself, its track
        # a little off (a high harmonic multiplies the fundamental's error): kept only where the hum
        # stays the stronger
        if np.sum(np.abs(b) ** 2) > np.sum(np.abs(a) ** 2):
            break
        cols = trial
        kept.append(off)
    if not kept:
        return []
    _, coef, _ = _project(cols, w)
    return [(off, coef[1 + n]) for n, off in enumerate(kept)]


def _quiet_weights(d, psi, k, fs: float, nd: int) -> np.ndarray:
    """Per decimated sample, the square root of the inverse content power beside the hum line
    (:func:`nearpower.near_power`, channels summed): the weights of the amplitude paths
    (steadypath.py), which read the hum in the quiet moments."""
    u = d * _finetrack.phase_turn(psi, k)[:, None]
    p = sum(near_power(u[:, c], fs).astype(float) for c in range(u.shape[1]))
    return 1.0 / np.sqrt(p.reshape(nd, -1).mean(axis=1))


def _project(cols, w):
    """Least squares of ``w`` (nd, C) on the columns: (orthonormal basis, coefficients (p, C), residual)."""
    A = np.stack(cols, axis=1)
    Q, R = np.linalg.qr(A)
    qw = Q.conj().T @ w
    coef = np.linalg.solve(R, qw)
    return Q, coef, w - Q @ qw


def _projected_periodogram(Q, resid, sw, nfft):
    """Per frequency of the zero-padded grid: the weighted residual's power along a weighted tone
    ``S e`` orthogonalised to the (weighted, orthonormal) columns ``Q``, summed over channels
    (``|(S e)^H r|^2 / |(I - QQ^H) S e|^2``, ``S = diag(sw)``)."""
    # (S e)^H r on the grid: a DFT of S r; the tone's norm left after projection from each column's DFT
    num = np.sum(np.abs(np.fft.fft(sw[:, None] * resid, nfft, axis=0)) ** 2, axis=1)
    proj = np.sum(np.abs(np.fft.fft(sw[:, None] * Q, nfft, axis=0)) ** 2, axis=1)
    n2 = float(np.sum(sw ** 2))
    return num / np.maximum(n2 - proj, 1e-9 * n2)


def _stat(Q, resid, td, sw, f: float) -> float:
    """The projected periodogram (:func:`_projected_periodogram`) at one frequency ``f`` (Hz)."""
    e = np.exp(2j * np.pi * f * td) * sw
    e_perp = e - Q @ (Q.conj().T @ e)
    return float(np.sum(np.abs(e.conj() @ resid) ** 2) / max(np.real(np.vdot(e_perp, e_perp)), 1e-12))


def _stat_near(Q, resid, td, sw, f: float, step: float) -> float:
    """The largest projected periodogram value within one grid ``step`` of ``f`` (Hz)."""
    return max(_stat(Q, resid, td, sw, f + d * step) for d in (-1.0, -0.5, 0.0, 0.5, 1.0))


def _refine(Q, resid, td, sw, f0: float, step: float) -> float:
    """The peak of the projected periodogram near ``f0`` (Hz), by a golden-section search over one
    grid step on each side."""
    def stat(f):
        return _stat(Q, resid, td, sw, f)

    a, b = f0 - step, f0 + step
    g = (np.sqrt(5) - 1) / 2
    c, d = b - g * (b - a), a + g * (b - a)
    fc, fd = stat(c), stat(d)
    for _ in range(30):
        if fc > fd:
            b, d, fd = d, c, fc
            c = b - g * (b - a)
            fc = stat(c)
        else:
            a, c, fc = c, d, fd
            d = a + g * (b - a)
            fd = stat(d)
    return (a + b) / 2


class WithoutLines:
    """A source read with the host lines taken out (``read`` returns the samples less the lines);
    every other attribute is the wrapped source's.

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; t = np.arange(2000) / sr
    >>> src = ArraySource(np.cos(2 * np.pi * 60.0 * t + 0.5), sr)
    >>> w = WithoutLines(src, [HostLine(60.0, np.array([np.exp(0.5j)]), 1)])
    >>> float(np.abs(w.read(100, 500)).max()) < 1e-9, w.frames
    (True, 2000)
    """

    def __init__(self, base, lines: list[HostLine]):
        self.base, self.lines = base, lines

    def __getattr__(self, name):
        return getattr(self.base, name)

    def read(self, start: int, n: int) -> np.ndarray:
        x = self.base.read(start, n)
        return x - lines_at(self.lines, max(start, 0), x.shape[0], self.base.sr, x.shape[1]).astype(x.dtype)


def lines_at(lines: list[HostLine], start: int, n: int, sr: int, C: int) -> np.ndarray:
    """The host lines' samples ``start .. start + n`` (n, C), float64.

    Examples
    --------
    >>> lines_at([HostLine(1.0, np.array([1.0 + 0j]), 1)], 0, 3, 4, 1).round(6).ravel().tolist()
    [1.0, 0.0, -1.0]
    """
    out = np.zeros((n, C))
    for ln in lines:
        # the phase in cycles reduced before scaling: t f reaches 1e8 cycles on long inputs
        cyc = np.mod(ln.freq_hz * np.arange(start, start + n, dtype=float) / sr, 1.0)
        e = np.exp(2j * np.pi * cyc)
        out += np.real(np.outer(e, ln.amp[:C]))
    return out


def chunk_sums(lines: list[HostLine], J: int, sr: int, f_ref: float, ks) -> np.ndarray:
    """The lines' chunk sums at ``k f_ref`` (J, C, K), complex64, as :func:`track.demodulate` makes
    them (the positive-frequency part: the chunk sums are used near the lines only).

    Examples
    --------
    >>> from odnn_sep.audio.io import ArraySource
    >>> sr = 1000; ln = [HostLine(60.2, np.array([0.5 * np.exp(1j)]), 1)]
    >>> D = _track.demodulate(ArraySource(lines_at(ln, 0, 4000, sr, 1), sr), 60.0, [1])
    >>> mean10 = lambda z: z[:, 0, 0].reshape(-1, 10).mean(axis=1)        # the narrow band about the line
    >>> bool(np.abs(mean10(chunk_sums(ln, len(D), sr, 60.0, [1])) - mean10(D)).max() < 0.02 * np.abs(D).max())
    True
    """
    m = _track.chunk_length(sr)
    C = len(lines[0].amp) if lines else 1
    out = np.zeros((J, C, len(ks)), np.complex64)
    j = np.arange(J, dtype=float)
    for ln in lines:
        if ln.harmonic not in ks:
            continue
        i = list(ks).index(ln.harmonic)
        off = ln.freq_hz - ln.harmonic * f_ref
        # phase at each chunk centre in cycles, reduced before scaling
        cyc = np.mod(off * (j * m + (m - 1) / 2) / sr, 1.0)
        out[:, :, i] += (0.5 * _dirichlet(off, m, sr) * np.exp(2j * np.pi * cyc)[:, None] * ln.amp[None, :]
                         ).astype(np.complex64)
    return out
