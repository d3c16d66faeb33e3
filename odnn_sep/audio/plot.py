"""``--plot`` figure: spectrograms before/after (one colour scale), line levels, and the fundamental track."""
from __future__ import annotations

import numpy as np

COMB_COLOURS = ("tab:cyan", "tab:green", "tab:orange", "tab:pink")


def _comb_lines(result) -> list[tuple[str, list[tuple[str, float]]]]:
    """(label, [(line name, frequency)]) for the main comb, each further comb and the tones."""
    groups = []
    f0 = result.mains_hz
    if result.harmonics and f0:
        groups.append((f"main comb, f0 {f0:.3f} Hz", [(f"h{k}", k * f0) for k in result.harmonics]))
    for i, c in enumerate(result.extra_combs):
        fc = c["fundamental_hz"]
        groups.append((f"comb {i + 2}, f0 {fc:.3f} Hz", [(f"c{i + 2}_h{k}", k * fc) for k in c["harmonics"]]))
    if result.tones:
        groups.append(("tones", [(f"{t:g} Hz", t) for t in result.tones]))
    return groups


def plot_denoise(result, before, after, out, *, max_seconds: float = 120.0) -> None:
    """Write a 2x2 figure for a :class:`~odnn_sep.audio.DenoiseResult`.

    ``before`` / ``after``: (n,) or (n, channels) arrays of the input and output (channel 0 is
    shown). Only the first ``max_seconds`` enter the spectrograms, and their titles say so when
    the input is longer. Both spectrograms share one colour scale (set by the input), so what
    was removed shows as a change of colour; the removed lines are marked and labelled by comb.

    Parameters
    ----------
    result : DenoiseResult
        What :func:`~odnn_sep.audio.denoise` or :func:`~odnn_sep.audio.denoise_file` returned.
    before, after : (n,) or (n, channels) arrays
        Input and output samples.
    out : str or path-like
        The figure file (.png, .pdf, .svg or .jpg).
    max_seconds : float
        Longest stretch shown in the spectrograms (s).

    Examples
    --------
    >>> import os, tempfile
    >>> from odnn_sep.audio import denoise
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=2.0, sr=2000)
    >>> r = denoise(y, sr)
    >>> with tempfile.TemporaryDirectory() as d:
    ...     plot_denoise(r, y, r.y, os.path.join(d, "hum.png"))
    ...     os.path.getsize(os.path.join(d, "hum.png")) > 10_000
    True
    """
    from scipy import signal

    from odnn_sep.report.figures import pyplot, save_figure

    plt = pyplot()
    sr = result.sr
    b = np.asarray(before, float)
    a = np.asarray(after, float)
    b = b[:, 0] if b.ndim == 2 else b
    a = a[:, 0] if a.ndim == 2 else a
    n = min(len(b), len(a), int(max_seconds * sr))
    b, a = b[:n], a[:n]
    total_s = result.info.get("duration_s", n / sr)
    shown = f" (first {n / sr:.0f} s of {total_s:.0f} s)" if total_s > n / sr + 1e-6 else ""
    groups = _comb_lines(result)
    line_f = [f for _, lines in groups for _, f in lines] or [h["freq_hz"] for h in result.levels_before]
    fmax = min(sr / 2, (max(line_f) if line_f else 500.0) * 1.15 + 20)
    fig, ax = plt.subplots(2, 2, figsize=(13, 8))
    nper = int(max(16, min(n, 2 * sr)))
    specs = []
    for x in (b, a):
        f, t, S = signal.spectrogram(x, fs=sr, nperseg=min(nper, len(x)), noverlap=min(nper, len(x)) // 2)
        m = f <= fmax
        specs.append((t, f[m], 10 * np.log10(S[m] + 1e-20)))
    vmax = float(np.percentile(specs[0][2], 99.5)) if specs[0][2].size else 0.0
    vmin = vmax - 80.0
    for axis, (t, f, S_db), title in zip((ax[0, 0], ax[0, 1]), specs, ("before", "after"), strict=True):
        mesh = axis.pcolormesh(t, f, S_db, shading="auto", vmin=vmin, vmax=vmax, cmap="magma")
        cb = fig.colorbar(mesh, ax=axis)
        cb.set_label("power spectral density (dB re 1/Hz)")
        axis.set_title(f"spectrogram {title}, channel 0{shown}")
        axis.set_xlabel("time (s)")
        axis.set_ylabel("frequency (Hz)")
        axis.ticklabel_format(axis="y", useOffset=False, style="plain")
    _mark_lines(ax[0, 0], groups, fmax)
    _levels_panel(ax[1, 0], result)
    _track_panel(ax[1, 1], result)
    fig.tight_layout()
    save_figure(fig, out)


def _mark_lines(axis, groups, fmax):
    """The removed lines, labelled by comb, at the right edge of the input's spectrogram."""
    for gi, (label, lines) in enumerate(groups):
        col = COMB_COLOURS[gi % len(COMB_COLOURS)]
        for j, (name, f) in enumerate(lines):
            if f > fmax:
                continue
            axis.axhline(f, color=col, lw=0.6, ls="--", alpha=0.8, label=label if j == 0 else None)
            axis.annotate(name, (1.0, f), xycoords=("axes fraction", "data"), xytext=(2, 0),
                              textcoords="offset points", fontsize=6, color=col, va="center")
    if groups:
        axis.legend(loc="upper left", fontsize=7, framealpha=0.7)


def _levels_panel(axis, result):
    """Line levels above the local floor before and after, per line."""
    names = result.line_names
    if names:
        lb = np.array([np.max(h["level_db"]) for h in result.levels_before])
        la = np.array([np.max(h["level_db"]) for h in result.levels_after])
        x = np.arange(len(names))
        axis.bar(x - 0.2, lb, 0.4, label="before")
        axis.bar(x + 0.2, la, 0.4, label="after")
        axis.set_xticks(x, names, rotation=45, ha="right", fontsize=8)
        axis.axhline(0, color="k", lw=0.8)
        axis.legend()
    else:
        axis.text(0.5, 0.5, "no hum found: nothing removed", ha="center", va="center",
                      transform=axis.transAxes)
    axis.set_ylabel("line level above local floor (dB, max over channels)")
    axis.set_title("line levels (h: main comb, cN_h: further comb N)")


def _track_panel(axis, result):
    """The tracked fundamental over the whole input."""
    if result.track_hz.size:
        axis.plot(result.track_t, result.track_hz, ".-", ms=3)
        axis.set_ylabel("fundamental (Hz)")
        axis.ticklabel_format(axis="y", useOffset=False, style="plain")
    else:
        axis.text(0.5, 0.5, "no hum found", ha="center", va="center", transform=axis.transAxes)
    axis.set_xlabel("time (s)")
    axis.set_title("tracked fundamental (whole input)")
