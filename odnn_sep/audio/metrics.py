"""Quality measures for hum removal when no clean reference exists (and SNR when one does).

All spectra: Welch, Hann, 4 s segments, 50 % overlap (0.25 Hz bins).

- line level: mean PSD within +-0.5 Hz of the line over the local floor (median PSD 2-10 Hz away,
  other lines excluded), in dB. 0 dB = the line is gone and the floor left intact.
- hole: the deepest cut within +-1 Hz of the line, in dB: each bin of the output over the lower
  of the floor and the input's own bin (a notch that digs into the music/noise shows up as a
  large negative number; a natural dip of the input's spectrum does not).
- off-line removal: energy of (input - output) farther than 2 Hz from every harmonic of the
  fundamental, relative to the input's energy there, in dB (distortion of the content).
"""
from __future__ import annotations

import numpy as np
from scipy import signal


def _psd(x, sr, seg_s=4.0, window="hann"):
    nper = int(min(seg_s * sr, len(x)))
    return signal.welch(x, fs=sr, window=window, nperseg=nper, noverlap=nper // 2, axis=0)


def line_metrics(x_in, x_out, sr, lines, *, f0=None, seg_s: float = 4.0) -> dict:
    """Line level, hole depth and off-line removal for 1-D signals ``x_in`` -> ``x_out``.

    Parameters
    ----------
    x_in, x_out : (n,) arrays
    sr : sample rate (Hz)
    lines : line frequencies (Hz) to report
    f0 : fundamental (Hz); every harmonic of it is excluded from the off-line measure
        (default: only ``lines``)

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0); t = np.arange(80000) / 8000
    >>> noise = rng.standard_normal(t.size)
    >>> m = line_metrics(noise + np.sin(2 * np.pi * 60 * t), noise, 8000, [60.0])
    >>> abs(m["level_db"][0]) < 1.0, m["level_in_db"][0] > 20
    (True, True)
    """
    x_in = np.asarray(x_in, float)
    x_out = np.asarray(x_out, float)
    f, Pi = _psd(x_in, sr, seg_s)
    _, Po = _psd(x_out, sr, seg_s)
    _, Pr = _psd(x_in - x_out, sr, seg_s)
    lines = [float(v) for v in lines]
    all_lines = lines if f0 is None else list(np.arange(1, int(sr / 2 / f0) + 1) * f0)
    levels, holes, levels_in = [], [], []
    # other lines' bins are left out of each floor (the line's own are: d >= 2 Hz)
    other = _near(f, all_lines + lines, 1.0)
    for fl in lines:
        d = np.abs(f - fl)
        near = (d >= 2.0) & (d <= 10.0) & ~other
        floor_o, floor_i = np.median(Po[near]), np.median(Pi[near])
        band = d <= 0.5
        levels.append(float(10 * np.log10(Po[band].mean() / floor_o)))
        levels_in.append(float(10 * np.log10(Pi[band].mean() / floor_i)))
        w = d <= 1.0
        holes.append(float(10 * np.log10((Po[w] / np.minimum(Pi[w], floor_i)).min())))
    off = ~_near(f, all_lines + lines, 2.0) & (f > 2.0)
    removed = float(10 * np.log10(max(Pr[off].sum(), 1e-300) / max(Pi[off].sum(), 1e-300)))
    return {"lines_hz": lines, "level_in_db": levels_in, "level_db": levels, "hole_db": holes,
            "offline_removed_db": removed}


def snr_improvement_db(host, hum, y_out) -> float:
    """Output SNR minus input SNR (dB) when the clean host and the hum are known.

    Parameters
    ----------
    host : array
        The clean signal.
    hum : array
        The hum added to it (the input is ``host + hum``).
    y_out : array
        The processed output.

    Returns
    -------
    float
        ``10 log10(sum(hum^2) / sum((y_out - host)^2))`` (dB): the host's power cancels.

    Examples
    --------
    >>> import numpy as np
    >>> round(snr_improvement_db(np.zeros(4), np.ones(4), np.full(4, 0.1)), 1)
    20.0
    """
    host = np.asarray(host, float)
    err = np.asarray(y_out, float) - host
    return float(10 * np.log10(np.sum(np.asarray(hum, float) ** 2) / max(np.sum(err ** 2), 1e-300)))


def band_floor_offset_db(x, sr, lines, exclude_hz, *, seg_s: float = 32.0, exclude_half_width_hz: float = 0.2):
    """How far the content under each line sits from its local floor, before any processing.

    Mean PSD within +-0.5 Hz of each line with the bins near every hum line (``exclude_hz``,
    +-``exclude_half_width_hz``) left out, over the median PSD 2-10 Hz away (other lines left
    out), in dB, on a fine Welch spectrum. It is the line level a perfect removal would show
    with the report's metric: a floor that is not flat near a line (room modes, a neighbouring
    partial) puts a lower bound on ``|level after|`` there.

    Parameters
    ----------
    x : (n,) array
        The input.
    sr : int
        Sample rate (Hz).
    lines : sequence of float
        Lines to report (Hz).
    exclude_hz : sequence of float
        Every hum line (Hz), left out of the bands and floors.
    seg_s : float
        Welch segment length (s).
    exclude_half_width_hz : float
        Half-width left out around each of ``exclude_hz`` within the band (Hz).

    Returns
    -------
    list of float
        dB per line; NaN where the band or the floor has no bin left.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(1); t = np.arange(960000) / 8000
    >>> x = rng.standard_normal(t.size) + np.sin(2 * np.pi * 60 * t)
    >>> abs(band_floor_offset_db(x, 8000, [60.0], [60.0])[0]) < 1.0
    True
    """
    x = np.asarray(x, float)
    f, P = _psd(x, sr, seg_s, window="blackmanharris")
    near_line = _near(f, exclude_hz, exclude_half_width_hz)
    out = []
    for fl in lines:
        d = np.abs(f - fl)
        band = (d <= 0.5) & ~near_line
        floor = (d >= 2.0) & (d <= 10.0) & ~_near(f, exclude_hz, 1.0)
        out.append(float(10 * np.log10(P[band].mean() / np.median(P[floor]))) if band.any() and floor.any()
                   else float("nan"))
    return out


def beside_line_cut_db(x_in, x_out, sr, lines, exclude_hz, *, seg_s: float = 32.0,
                       exclude_half_width_hz: float = 0.2, width_hz: float = 1.0) -> list[float]:
    """Deepest cut of the content beside each line: output over input PSD (dB), minimum over the
    bins within ``width_hz`` of the line, with the bins near every hum line (``exclude_hz``,
    +-``exclude_half_width_hz``) left out, on a fine Welch spectrum.

    The hole measure of :func:`line_metrics` compares the output with the lower of the input and
    a floor 2-10 Hz away, on 0.25 Hz bins that also hold the line: where the content under a line
    is naturally below that floor, removing the line alone reads as a hole there. This measure
    looks only where the input has no line at a resolution that separates them, and so reads 0 dB
    when a removal leaves the content beside the lines untouched.

    Parameters
    ----------
    x_in, x_out : (n,) arrays
        Input and output.
    sr : int
        Sample rate (Hz).
    lines : sequence of float
        Lines to report (Hz).
    exclude_hz : sequence of float
        Every hum line (Hz).
    seg_s : float
        Welch segment length (s).
    exclude_half_width_hz : float
        Half-width left out around each of ``exclude_hz`` (Hz).
    width_hz : float
        Half-width of the region searched beside each line (Hz).

    Returns
    -------
    list of float
        dB per line; NaN where no bin is left.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(2); t = np.arange(960000) / 8000
    >>> noise = rng.standard_normal(t.size)
    >>> cut = beside_line_cut_db(noise + np.sin(2 * np.pi * 60 * t), noise, 8000, [60.0], [60.0])
    >>> abs(cut[0]) < 0.1
    True
    """
    x_in = np.asarray(x_in, float)
    x_out = np.asarray(x_out, float)
    f, Pi = _psd(x_in, sr, seg_s, window="blackmanharris")
    _, Po = _psd(x_out, sr, seg_s, window="blackmanharris")
    near_line = _near(f, exclude_hz, exclude_half_width_hz)
    out = []
    for fl in lines:
        w = (np.abs(f - fl) <= width_hz) & ~near_line & (Pi > 0)
        out.append(float(10 * np.log10((Po[w] / Pi[w]).min())) if w.any() else float("nan"))
    return out


def _near(f: np.ndarray, lines_hz, half_width_hz: float) -> np.ndarray:
    """Bins of ``f`` within ``half_width_hz`` of any of ``lines_hz``."""
    near = np.zeros(f.shape, bool)
    for g in lines_hz:
        near |= np.abs(f - g) <= half_width_hz
    return near
