"""The result object of :func:`~odnn_sep.audio.denoise`: what was found and removed, and its JSON form."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np


@dataclass
class DenoiseResult:
    """What :func:`denoise` found and removed.

    Attributes
    ----------
    y : ndarray or None
        Cleaned signal, same shape as the input (None from :func:`denoise_file`).
    hum : ndarray or None
        The removed hum + tones (``input = y + hum``).
    sr : int
    mains_hz : float or None
        Median tracked fundamental (Hz); None when no hum was found.
    nominal_hz : float or None
        Family chosen by detection (50, 60 or the requested value).
    harmonics : list of int
        Harmonic numbers removed.
    tones : list of float
        Tone frequencies removed (refined, Hz).
    track_t, track_hz : ndarray
        Fundamental track: block centres (s) and frequency (Hz).
    amplitudes, phases : ndarray, shape (n_blocks, channels, n_lines)
        Peak amplitude (sample units) and phase (rad) of each line per block; phases are at the
        block centre for harmonics and at t = 0 for tones (cosine convention).
    amplitude_overall : ndarray or None, shape (channels, n_lines)
        Whole-input amplitude of each steady line (NaN where the line changes more than the noise
        allows): for the harmonics, the generalised least-squares estimate of ``amplitude.py``
        (instants weighted by the inverse of the content's local power near the line); for tones and
        further combs, the modulus of the precision-weighted mean of the blocks' complex amplitudes
        in a common phase reference.
    line_names : list of str
        ``h<k>`` for the tracked comb, ``tone_<f>Hz`` for tones, ``c<i>_h<k>`` for further combs.
    line_freqs : list of float
        Frequency of each line (Hz; harmonics at the median tracked fundamental).
    extra_combs : list of dict
        Further steady combs within 0.3 % of the main one (``fundamental_hz``, ``harmonics``),
        e.g. the same grid seen through a second sample clock or a second device.
    levels_before, levels_after : list of dict
        Each line's level above its local noise floor (dB, per channel).
    report : dict
        JSON-ready summary (see :meth:`as_dict`).

    Examples
    --------
    >>> from odnn_sep.audio import denoise
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> r = denoise(y, sr)
    >>> r.line_names[:2], r.amplitudes.shape[1:], bool(abs(y - r.y - r.hum).max() < 1e-12)
    (['h1', 'h2'], (1, 5), True)
    >>> d = r.as_dict(); d["mains"]["nominal_hz"], [ln["name"] for ln in d["lines"]][:2]
    (50.0, ['h1', 'h2'])
    """

    y: np.ndarray | None
    hum: np.ndarray | None
    sr: int
    mains_hz: float | None
    nominal_hz: float | None
    harmonics: list
    tones: list
    track_t: np.ndarray
    track_hz: np.ndarray
    amplitudes: np.ndarray
    phases: np.ndarray
    line_names: list
    levels_before: list
    levels_after: list
    candidates: list = field(default_factory=list)
    extra_combs: list = field(default_factory=list)
    line_freqs: list = field(default_factory=list)
    block_valid: np.ndarray | None = None
    amplitude_overall: np.ndarray | None = None
    clip_message: str | None = None
    requantisation_message: str | None = None
    info: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict, repr=False)

    def line_amplitude(self, name: str) -> np.ndarray:
        """Peak amplitude of one line per channel over the whole input: the pooled estimate where the
        line is steady (:attr:`amplitude_overall`), else the median over blocks fully inside the
        signal."""
        i = self.line_names.index(name)
        sel = self.block_valid if self.block_valid is not None and self.block_valid.any() else slice(None)
        med = np.median(self.amplitudes[sel, :, i], axis=0)
        if self.amplitude_overall is None:
            return med
        ov = self.amplitude_overall[:, i]
        return np.where(np.isfinite(ov), ov, med)

    def as_dict(self) -> dict:
        sel = self.block_valid if self.block_valid is not None and self.block_valid.any() else slice(None)
        lines = []
        for i, name in enumerate(self.line_names):
            ph = self.phases[:, :, i]
            circ = np.angle(np.exp(1j * ph[sel]).mean(axis=0)) if ph.size else []
            is_h = i < len(self.harmonics)
            lines.append({
                "name": name,
                "harmonic": self.harmonics[i] if is_h else None,
                "freq_hz": self.line_freqs[i] if i < len(self.line_freqs) else None,
                "amplitude_peak": {"median": np.median(self.amplitudes[sel, :, i], axis=0).tolist()
                                   if self.amplitudes.size else [],
                                   "overall": self.line_amplitude(name).tolist() if self.amplitudes.size else [],
                                   "per_block": self.amplitudes[:, :, i].tolist()},
                "phase_rad": {"circular_mean": np.asarray(circ).tolist(), "per_block": ph.tolist(),
                              "reference": "block centre (harmonics), t = 0 (tones); cosine"},
                "level_above_floor_db": {"before": self.levels_before[i]["level_db"],
                                         "after": self.levels_after[i]["level_db"]},
            })
        return {
            **self.info,
            "sr": self.sr,
            "mains": {"nominal_hz": self.nominal_hz, "fundamental_hz": self.mains_hz,
                      "candidates_tested": self.candidates},
            "harmonics": list(self.harmonics),
            "tones_hz": list(self.tones),
            "extra_combs": self.extra_combs,
            "track": {"time_s": self.track_t.tolist(), "freq_hz": self.track_hz.tolist()},
            "lines": lines,
            "units": {"amplitude_peak": "same units as the samples (full scale = 1.0 for files)",
                      "level_above_floor_db": "mean PSD within the line band over the median local floor, "
                                              "dB, per channel"},
            "clipping": self.clip_message,
            "requantisation": self.requantisation_message,
        }
