"""``--plot`` figure: spectrograms before/after, line levels, and the fundamental track."""
from __future__ import annotations

import numpy as np


def plot_denoise(result, before, after, out, *, max_seconds: float = 120.0) -> None:
    """Write a 2x2 figure for a :class:`~odnn_sep.audio.DenoiseResult`.

    ``before`` / ``after``: (n,) or (n, channels) arrays of the input and output (channel 0 is
    shown; only the first ``max_seconds`` enter the spectrograms).
    """
    from scipy import signal

    from odnn_sep.report.figures import pyplot, save_figure

    plt = pyplot()
    sr = result.sr
    b = np.asarray(before, float)
    a = np.asarray(after, float)
    b = b[:, 0] if b.ndim == 2 else b
    a = a[:, 0] if a.ndim == 2 else a
    n = min(len(b), int(max_seconds * sr))
    b, a = b[:n], a[:n]
    line_f = [h["freq_hz"] for h in result.levels_before]
    fmax = min(sr / 2, (max(line_f) if line_f else 500.0) * 1.15 + 20)
    fig, ax = plt.subplots(2, 2, figsize=(12, 7.5))
    nper = int(min(n, 2 * sr))
    for axis, x, title in ((ax[0, 0], b, "before"), (ax[0, 1], a, "after")):
        f, t, S = signal.spectrogram(x, fs=sr, nperseg=nper, noverlap=nper // 2)
        m = f <= fmax
        S_db = 10 * np.log10(S[m] + 1e-20)
        vmax = np.percentile(S_db, 99.5) if S_db.size else 0
        axis.pcolormesh(t, f[m], S_db, shading="auto", vmin=vmax - 80, vmax=vmax, cmap="magma")
        axis.set_title(f"spectrogram {title} (channel 0)")
        axis.set_xlabel("time (s)")
        axis.set_ylabel("frequency (Hz)")
    names = result.line_names
    if names:
        lb = np.array([np.max(h["level_db"]) for h in result.levels_before])
        la = np.array([np.max(h["level_db"]) for h in result.levels_after])
        x = np.arange(len(names))
        ax[1, 0].bar(x - 0.2, lb, 0.4, label="before")
        ax[1, 0].bar(x + 0.2, la, 0.4, label="after")
        ax[1, 0].set_xticks(x, names, rotation=45, ha="right", fontsize=8)
        ax[1, 0].axhline(0, color="k", lw=0.8)
        ax[1, 0].legend()
    ax[1, 0].set_ylabel("line level above local floor (dB, max over channels)")
    ax[1, 0].set_title("line levels")
    if result.track_hz.size:
        ax[1, 1].plot(result.track_t, result.track_hz, ".-", ms=3)
        ax[1, 1].set_ylabel("fundamental (Hz)")
    else:
        ax[1, 1].text(0.5, 0.5, "no hum found", ha="center", va="center", transform=ax[1, 1].transAxes)
    ax[1, 1].set_xlabel("time (s)")
    ax[1, 1].set_title("tracked fundamental")
    fig.tight_layout()
    save_figure(fig, out)
