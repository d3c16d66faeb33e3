"""Welch spectra of a source (whole input, or evenly spaced excerpts of a long one), with the
per-segment periodograms kept near the hum lines for the persistence test."""
from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

FFT_WORKERS = 2    # threads for a batch of segment transforms (each transform is computed whole by one)
UNEVEN_CHANNELS = 10.0   # broadband levels of the channels this many times apart: each pooled over its own


@dataclass
class Spectrum:
    """A Welch PSD per channel, with the per-segment periodograms near the lines when kept.

    Attributes
    ----------
    freqs : (nf,) array
        Bin frequencies (Hz).
    psd : (nf, channels) array
        Mean power per Hz over the segments.
    n_segments : int
        Welch segments averaged (per channel).
    seconds : float
        Signal duration analysed (s).
    segments : (nf_keep, channels, n_segments) array or None
        Per-segment PSD of the lowest bins (for the persistence test).

    Examples
    --------
    >>> import numpy as np
    >>> s = Spectrum(freqs=np.arange(5) * 0.25, psd=np.ones((5, 1)), n_segments=4, seconds=10.0)
    >>> s.df, s.dof_per_bin
    (0.25, 7.2)
    """

    freqs: np.ndarray        # (nf,)
    psd: np.ndarray          # (nf, channels), mean power per Hz over segments
    n_segments: int          # Welch segments averaged (per channel)
    seconds: float           # signal duration analysed
    segments: np.ndarray | None = None   # (nf, channels, n_segments) per-segment PSD (for detection)

    @property
    def df(self) -> float:
        return float(self.freqs[1] - self.freqs[0])

    @functools.cached_property
    def numerical_floor(self) -> float:
        # a mean over every bin: computed once (line tests ask for it hundreds of times)
        return 1e-12 * float(np.mean(self.psd)) + 1e-300

    @functools.cached_property
    def channel_weights(self) -> np.ndarray | None:
        """Weights that put every channel over its own broadband level (its median PSD above 1 Hz)
        when those levels differ by more than ``UNEVEN_CHANNELS`` times, else None (the channels
        are pooled by their plain sum). One EEG electrode that saturated for 5 s of 60 raised its
        level so far that the plain sum hid the other seven channels' line; channels that share a
        level (the two of a stereo take) pool the same either way, and keep the plain sum."""
        C = self.psd.shape[1]
        if C < 2:
            return None
        sel = self.freqs > 1.0
        level = np.median(self.psd[sel] if sel.sum() >= 4 else self.psd, axis=0)
        level = np.maximum(level, 1e-300)
        if float(level.max() / level.min()) <= UNEVEN_CHANNELS:
            return None
        return 1.0 / level

    @property
    def dof_per_bin(self) -> float:
        # Hann, 50 % overlap: each extra segment adds about 0.9 of an independent one
        return 2.0 * max(1.0, 0.9 * self.n_segments)


def excerpt_spectrum(source, *, seg_s: float = 4.0, max_total_s: float = 240.0,
                     n_excerpts: int = 8, keep_segments_hz: float | None = None) -> Spectrum:
    """Welch PSD of the whole input, or of evenly spaced excerpts when it is longer than
    ``max_total_s`` (bounded time and memory on long files).

    ``keep_segments_hz``: also keep the per-segment periodograms below this frequency (used by
    the persistence test in :func:`detect_hum`).

    Parameters
    ----------
    source : ArraySource or FileSource
        Anything with ``sr``, ``frames`` and ``read(start, n) -> (n, channels)``.
    seg_s : float
        Welch segment length (s); Hann window, 50 % overlap.
    max_total_s : float
        Longest input analysed whole (s).
    n_excerpts : int
        Excerpts read from a longer input.
    keep_segments_hz : float, optional
        Keep the per-segment periodograms below this frequency (Hz).

    Returns
    -------
    Spectrum

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.audio.io import ArraySource
    >>> y = np.sin(2 * np.pi * 50 * np.arange(24000) / 8000)
    >>> s = excerpt_spectrum(ArraySource(y, 8000))
    >>> s.psd.shape, s.n_segments, s.seconds, float(s.freqs[s.psd[:, 0].argmax()])
    ((6001, 1), 3, 3.0, 50.0)
    """
    sr, n = source.sr, source.frames
    nper = int(min(seg_s * sr, max(n // 2, 16)))
    nper = max(nper, min(n, 16))
    total = int(max_total_s * sr)
    if n <= total:
        spans = [(0, n)]
    else:
        length = total // n_excerpts
        starts = np.linspace(0, n - length, n_excerpts).astype(int)
        spans = [(int(s), length) for s in starts]
    acc, nseg, segs = None, 0, []
    for s, length in spans:
        x = source.read(s, length)
        if x.shape[0] < nper:
            continue
        f, P_sum, k, P_keep = _periodograms(x, sr, nper, keep_segments_hz)
        acc = P_sum if acc is None else acc + P_sum
        nseg += k
        if P_keep is not None:
            segs.append(P_keep)
    return Spectrum(freqs=f, psd=acc / nseg, n_segments=nseg, seconds=sum(s[1] for s in spans) / sr,
                    segments=np.concatenate(segs, axis=-1) if segs else None)


def _periodograms(x, sr, nper, keep_hz, batch: int = 16):
    """Hann-windowed, mean-removed periodograms of 50 %-overlapping segments (one-sided PSD, the
    scaling of ``scipy.signal.spectrogram(mode='psd')``), computed a few segments at a time so
    memory stays bounded. Returns freqs, the sum over segments (nf, C), the segment count and,
    when ``keep_hz`` is given, the per-segment PSD below it (nf_keep, C, segments) in float32."""
    from numpy.lib.stride_tricks import sliding_window_view
    from scipy import fft

    step = nper - nper // 2
    n, C = x.shape
    nseg = 1 + (n - nper) // step
    win = _hann(nper)
    scale = 1.0 / (sr * float((win.astype(np.float64) ** 2).sum()))
    f = fft.rfftfreq(nper, 1.0 / sr)
    onesided = np.full(len(f), 2.0)
    onesided[0] = 1.0
    if nper % 2 == 0:
        onesided[-1] = 1.0
    nkeep = int(np.searchsorted(f, keep_hz, side="right")) if keep_hz is not None else 0
    P_sum = np.zeros((len(f), C))
    keep = np.empty((nkeep, C, nseg), np.float32) if keep_hz is not None else None
    fac = (scale * onesided).astype(np.float32)
    buf = np.empty((min(batch, nseg), nper), np.float32)
    for c in range(C):
        # one contiguous copy of the channel: each sample is read by two overlapping segments
        view = sliding_window_view(np.ascontiguousarray(x[:, c]), nper)[::step][:nseg]
        for b0 in range(0, nseg, batch):
            seg = view[b0: b0 + batch]
            # mean removed in float64, then float32 for the window and the FFT: its rounding
            # noise (~1e-7 of the segment's RMS) sits far below the 120 dB numerical floor used
            # by the line tests, at half the cost of a float64 transform (the difference is
            # rounded to float32 as it is written: no float64 temporary)
            sb = buf[: seg.shape[0]]
            np.subtract(seg, seg.mean(axis=1, keepdims=True), out=sb, casting="same_kind")
            sb *= win
            X = fft.rfft(sb, axis=1, workers=FFT_WORKERS)   # (the segments split between threads: same values)
            Xv = X.view(np.float32).reshape(X.shape + (2,))
            np.square(Xv, out=Xv)
            P = np.add(Xv[..., 0], Xv[..., 1])                   # float32: no cancellation here
            P *= fac
            P_sum[:, c] += P.sum(axis=0, dtype=np.float64)
            if keep is not None:
                keep[:, c, b0: b0 + P.shape[0]] = P[:, :nkeep].T
    return f, P_sum, nseg, keep


@functools.lru_cache(maxsize=8)
def _hann(nper: int) -> np.ndarray:
    # periodic Hann, as scipy.signal.get_window("hann", nper) computes it (same values; avoids
    # importing scipy.signal on the command line's path)
    fac = np.linspace(-np.pi, np.pi, nper + 1)
    w = np.zeros(nper + 1)
    for k, a in enumerate((0.5, 0.5)):
        w += a * np.cos(k * fac)
    w = w[:-1].astype(np.float32)
    w.flags.writeable = False
    return w
