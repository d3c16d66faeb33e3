"""``denoise``: remove mains hum (tracked fundamental + harmonics) and named tones from audio.

Pipeline (all passes stream in blocks, so memory does not grow with the file length):

1. detection on a Welch spectrum: fundamental (50/60 Hz or given), harmonics present, tones;
2. pass 1: demodulated 10 ms chunk sums -> per-block fundamental track (track.py);
3. pass 2: per 50 %-overlapping block, weighted least squares of the samples on the tracked
   harmonic basis (fit.py), fitted hum windowed by sin^2 (the windows sum to one, so blocks join
   without clicks), subtracted and written progressively;
4. line levels above the local floor before and after, for the report.
"""
from __future__ import annotations

import logging
import sys
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.audio import baseband as _baseband
from odnn_sep.audio import blockfit as _blockfit
from odnn_sep.audio import blocklen as _blocklen
from odnn_sep.audio import detect as _detect
from odnn_sep.audio import track as _track
from odnn_sep.audio.io import ArraySource, ClipCounter, FileSource, is_integer_subtype, output_subtype
from odnn_sep.errors import InputError

log = logging.getLogger(__name__)

SMOOTH_BLOCKS = 4   # line amplitudes pooled over up to this many blocks on each side (blockfit.py)
POOL_MAIN = True


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
    clip_message: str | None = None
    info: dict = field(default_factory=dict)
    spectra: dict = field(default_factory=dict, repr=False)

    def line_amplitude(self, name: str) -> np.ndarray:
        """Median peak amplitude of one line per channel, over blocks fully inside the signal."""
        i = self.line_names.index(name)
        sel = self.block_valid if self.block_valid is not None and self.block_valid.any() else slice(None)
        return np.median(self.amplitudes[sel, :, i], axis=0)

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
        }


def _parse_mains(mains, sr):
    if isinstance(mains, str) and mains.strip().lower() == "auto":
        return "auto"
    try:
        v = float(mains)
    except (TypeError, ValueError):
        raise InputError(f"mains must be 'auto', 50, 60 or a frequency in Hz; got {mains!r}") from None
    if not np.isfinite(v) or v <= 0:
        raise InputError(f"mains must be a positive frequency in Hz; got {mains!r}")
    if v >= sr / 2:
        raise InputError(f"mains={v:g} Hz is at or above the Nyquist frequency ({sr / 2:g} Hz for sr={sr}); "
                         f"choose a fundamental below {sr / 2:g} Hz")
    return v


def _parse_harmonics(harmonics):
    if isinstance(harmonics, str) and harmonics.strip().lower() == "auto":
        return "auto"
    if isinstance(harmonics, (list, tuple)):
        # an explicit set of harmonic numbers (internal use: re-running on an excerpt)
        return sorted({_parse_harmonics(h) for h in harmonics})
    try:
        v = int(harmonics)
        if v != float(harmonics):
            raise ValueError
    except (TypeError, ValueError):
        raise InputError(f"harmonics must be 'auto' or a positive integer; got {harmonics!r}") from None
    if v < 1:
        raise InputError(f"harmonics must be 'auto' or a positive integer; got {harmonics!r}")
    return v


def _parse_tones(tones, sr):
    out = []
    for t in tones or ():
        try:
            v = float(t)
        except (TypeError, ValueError):
            raise InputError(f"tone must be a frequency in Hz; got {t!r}") from None
        if not np.isfinite(v) or v <= 0 or v >= sr / 2:
            raise InputError(f"tone={t!r} Hz must be between 0 and the Nyquist frequency ({sr / 2:g} Hz)")
        out.append(v)
    return out


def _progress_bar(enabled: bool, total: int, desc: str):
    if not enabled or not sys.stderr.isatty():
        return None
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, unit="smp", unit_scale=True, file=sys.stderr, leave=False)


def _run(source, sink, **kw):
    # Many small matrix products: BLAS threads only add spin-wait overhead here (and collapse
    # when the machine is busy), so run them single-threaded.
    try:
        from threadpoolctl import threadpool_limits  # present through librosa -> scikit-learn
    except ImportError:  # pragma: no cover
        return _run_inner(source, sink, **kw)
    with threadpool_limits(limits=1, user_api="blas"):
        return _run_inner(source, sink, **kw)


def _run_inner(source, sink, *, mains, harmonics, tones, block_s, solver, alpha, max_hz, progress, random_state,
               after_source_fn, max_combs=3, smooth_blocks=None):
    sr, N, C = source.sr, source.frames, source.channels
    mains = _parse_mains(mains, sr)
    harmonics = _parse_harmonics(harmonics)
    tones = _parse_tones(tones, sr)
    if solver not in ("exact", "network"):
        raise InputError(f"solver must be 'exact' or 'network'; got {solver!r}")
    auto_block = isinstance(block_s, str) and block_s.strip().lower() == "auto"
    if not auto_block:
        try:
            block_s = float(block_s)
        except (TypeError, ValueError):
            raise InputError(f"block_s must be 'auto' or a duration in seconds; got {block_s!r}") from None
        if not np.isfinite(block_s) or block_s * 10 < 1.0 or block_s > 60:
            raise InputError(f"block_s must be between 0.1 and 60 s; got {block_s!r}")
    min_s = 0.2
    if N < min_s * sr:
        raise InputError(f"input is too short ({N} samples = {N / sr:.3f} s at {sr} Hz) to resolve mains hum; "
                         f"pass at least {min_s:g} s of audio")

    nyq = sr / 2
    top = min(0.95 * nyq, max_hz if max_hz is not None else np.inf,
              (_detect.MAX_HARMONICS + 1) * (65.0 if mains == "auto" else mains))
    spec_before = _detect.excerpt_spectrum(source, keep_segments_hz=top + 2 * _detect.FLOOR_WIDTH_HZ)
    det = _detect.detect_hum(spec_before, sr, mains=mains, harmonics=harmonics, tones=tones, alpha=alpha,
                             max_hz=max_hz)
    ks, tl = det.harmonics, det.tones
    if auto_block and (not ks or N < 3 * _blocklen.CANDIDATES_S[-1] * sr):
        block_s, auto_block = _blocklen.CANDIDATES_S[0], False
    bar = _progress_bar(progress, (2 if ks else 1) * N, "denoise")
    tick = (lambda k: bar.update(k)) if bar is not None else None
    trk, D3 = None, None
    look_again = bool(ks) and not isinstance(harmonics, int) and max_combs > 1
    # gaps in the comb, for a second look once the track is known (isolated lines above the
    # highest harmonic found are more likely tonal content than hum, as for further combs)
    missing = [k for k in range(1, max(ks)) if k not in ks] if look_again else []
    if ks:
        weights = np.stack([1.0 / np.maximum(det.floors[("h", k)], 1e-300) for k in ks], axis=1)   # (C, K)
        # one demodulation pass for the harmonics found and the gaps
        D = _track.demodulate(source, det.mains_hz, list(ks) + missing, progress=tick)
        D, D3 = D[:, :, : len(ks)], D[:, :, len(ks):]
        if auto_block:
            block_s, trk = _blocklen.choose_block(D, sr, N, det.mains_hz, ks, weights)
        else:
            trk = _track.track_fundamental(D, sr, N, det.mains_hz, ks, weights,
                                           hop=max(1, int(round(block_s * sr / 2))))
        del D
    hop = max(1, int(round(block_s * sr / 2)))
    nb = (N - 1) // hop + 2
    names = [f"h{k}" for k in ks] + [f"tone_{t:g}Hz" for t in tl]
    if not ks and not tl:
        log.warning("no significant mains hum found (tested %s); the output equals the input",
                    "50 and 60 Hz" if mains == "auto" else f"{mains:g} Hz")
    if not ks:
        t = np.arange(nb) * hop / sr
        z = np.zeros(nb)
        trk = _track.Track(t=t, f0=z, rate=z, curv=z, confident=np.zeros(nb, bool), strength=z)

    combs, df_hr, f_med, spec_hr = [], 1.0, det.mains_hz, None
    if look_again:
        # further combs near the same nominal frequency, on a finer spectrum with the tracked
        # comb's lines (widened by how far the track wandered) masked out
        f_med = float(np.median(trk.f0[trk.confident])) if trk.confident.any() else det.mains_hz
        spread = float(np.ptp(trk.f0[trk.confident])) if trk.confident.sum() > 1 else 0.0
        seg_hr = float(np.clip(N / sr / 4, 4.0, 16.0))
        spec_hr = _detect.excerpt_spectrum(source, seg_s=seg_hr, keep_segments_hz=top + 2 * _detect.FLOOR_WIDTH_HZ)
        df_hr = spec_hr.df
        known = [(k * f_med, 2 * df_hr + 0.5 * k * spread) for k in ks] + \
                [(t, 2 * df_hr) for t in tl]
        k_top = max(ks)
        more = []
        if missing:
            n_first = sum(1 for c in det.candidates if c["harmonic"] is not None)
            more, cands2 = _baseband.second_look(D3, sr, det.mains_hz, missing, trk, alpha=alpha,
                                                 n_tests=n_first + len(missing), seg_s=seg_hr)
            det.candidates += cands2
        del D3
        if more:
            ks = sorted(ks + more)
            known = [(k * f_med, 2 * df_hr + 0.5 * k * spread) for k in ks] + [(t, 2 * df_hr) for t in tl]
            names = [f"h{k}" for k in ks] + [f"tone_{t:g}Hz" for t in tl]
        combs = _detect.detect_extra_combs(spec_hr, sr, det.nominal_hz, known, min_sep_hz=1.5 * sr / (2 * hop),
                                           alpha=alpha, max_hz=max_hz, max_combs=max_combs - 1,
                                           max_harmonic=k_top, main_f0=f_med)
    # the spectrum locates a further comb only to a fraction of a bin; refine it on the
    # demodulated signal (one long window) so a 16 s fixed-frequency fit stays in phase; one
    # demodulation pass serves every further comb
    D2 = _track.demodulate(source, 1.0, [k * c.fundamental_hz for c in combs for k in c.harmonics]) \
        if combs else None
    col = 0
    for ci, c in enumerate(combs):
        others = [f_med] + [o.fundamental_hz for j, o in enumerate(combs) if j != ci]
        half = min(2 * df_hr / min(c.harmonics), 0.45 * min(abs(o - c.fundamental_hz) for o in others))
        w2 = np.stack([1.0 / np.maximum(spec_hr.psd[np.argmin(np.abs(spec_hr.freqs - k * c.fundamental_hz))], 1e-300)
                       for k in c.harmonics], axis=1)
        kc = len(c.harmonics)
        c.fundamental_hz = _track.refine_fixed_comb(D2[:, :, col: col + kc], sr, c.fundamental_hz, c.harmonics, w2,
                                                    half_hz=half)
        col += kc
    del D2
    comb_tones = [k * c.fundamental_hz for c in combs for k in c.harmonics]
    names += [f"c{i + 2}_h{k}" for i, c in enumerate(combs) for k in c.harmonics]
    tl_fit = list(tl) + comb_tones
    fixed_lines = list(tl) + [(c.fundamental_hz, c.harmonics) for c in combs]

    f_top = max([k * (det.mains_hz or 0.0) * 1.01 for k in ks] + [float(t) for t in tl_fit] + [1.0])
    gram_step = max(1, int(sr // (4 * f_top + 1)))
    # local noise floor at every line (for pooling amplitudes across blocks)
    main_psd = fixed_psd = None
    if ks or tl_fit:
        spec_fl = spec_hr if spec_hr is not None else spec_before
        all_f = [k * f_med for k in ks] + tl_fit
        fl_all = [(f, 2 * spec_fl.df) for f in all_f]
        psd = np.stack([_detect.line_level(spec_fl, f, 2 * spec_fl.df,
                                           [e for e in fl_all if abs(e[0] - f) > 1e-9])["floor"] for f in all_f])
        if np.isfinite(psd).all():
            main_psd, fixed_psd = (psd[: len(ks)] if ks else None), (psd[len(ks):] if tl_fit else None)
    amps, phs, valid = _blockfit.fit_pass(source, sink, hop=hop, trk=trk, ks=ks, fixed_lines=fixed_lines,
                                          names=names, solver=solver, random_state=random_state,
                                          gram_step=gram_step, fixed_psd=fixed_psd,
                                          main_psd=main_psd if POOL_MAIN else None,
                                          smooth_blocks=SMOOTH_BLOCKS if smooth_blocks is None else smooth_blocks,
                                          tick=tick)
    if bar is not None:
        bar.close()

    out_src = after_source_fn()
    spec_after = _detect.excerpt_spectrum(out_src)
    out_src.close()
    f_med = float(np.median(trk.f0[trk.confident])) if ks and trk.confident.any() else det.mains_hz
    line_f = [k * f_med for k in ks] + list(tl_fit)
    before = _detect.line_levels(spec_before, line_f)
    after = _detect.line_levels(spec_after, line_f)
    return DenoiseResult(
        y=None, hum=None, sr=sr, mains_hz=f_med, nominal_hz=det.nominal_hz, harmonics=ks, tones=tl,
        extra_combs=[{"fundamental_hz": c.fundamental_hz, "harmonics": c.harmonics} for c in combs],
        line_freqs=line_f,
        track_t=trk.t, track_hz=trk.f0 if ks else np.zeros(0), amplitudes=amps, phases=phs,
        line_names=names, levels_before=before, levels_after=after,
        candidates=det.candidates + [c for comb in combs for c in comb.candidates],
        block_valid=valid,
        info={"solver": solver, "block_s": 2 * hop / sr, "channels": C, "frames": N, "duration_s": N / sr},
        spectra={"freqs": spec_before.freqs, "before": spec_before.psd, "after": spec_after.psd},
    )


def denoise(y, sr, *, mains="auto", harmonics="auto", tones=(), block_s="auto", solver: str = "exact",
            alpha: float = 1e-3, max_hz: float | None = None, progress: bool = False,
            random_state=0) -> DenoiseResult:
    """Remove mains hum (drift-tracked fundamental and harmonics) and named tones from audio.

    Parameters
    ----------
    y : (n,) or (n, channels) array
        Samples (any units); not modified.
    sr : int
        Sample rate (Hz).
    mains : 'auto', 50, 60 or float
        Hum fundamental. ``'auto'`` decides between the 50 and 60 Hz families from the data; a
        number is refined within +-1 % (sound-card clock offsets), e.g. 60.055 Hz.
    harmonics : 'auto' or int
        ``'auto'`` removes only harmonics that pass the line test; an integer N removes 1..N.
    tones : sequence of float
        Extra fixed tones (Hz) to remove (refined within +-0.5 Hz).
    block_s : 'auto' or float
        Fit block length (s); blocks overlap by half. ``'auto'`` picks 8 or 16 s: the one whose
        processed lines sit closest to their local floor on a central excerpt (16 s suits
        steady hum, 8 s follows faster drift); inputs shorter than 48 s use 8 s.
    solver : {'exact', 'network'}
        ``'network'`` fits every block with the torch ODNN solver (slow; same answer within noise).
    alpha : float
        Family-wise significance level of the line tests (Bonferroni over all lines tested).
    max_hz : float, optional
        Highest harmonic frequency considered (default: 0.95 x Nyquist, at most 40 harmonics).
    progress : bool
        Show a progress bar on stderr (only when it is a terminal).
    random_state : int
        Seed for the network solver.

    Returns
    -------
    DenoiseResult

    Examples
    --------
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, truth = make_hum_demo(duration_s=4.0, sr=8000)
    >>> r = denoise(y, sr)
    >>> r.nominal_hz, r.harmonics[:2]
    (50.0, [1, 2])
    """
    return _denoise_array(y, sr, mains=mains, harmonics=harmonics, tones=tones, block_s=block_s, solver=solver,
                          alpha=alpha, max_hz=max_hz, progress=progress, random_state=random_state)


def _denoise_array(y, sr, *, mains, harmonics, tones, block_s, solver, alpha, max_hz, progress, random_state,
                   max_combs=3):
    src = ArraySource(y, sr)
    out = np.empty_like(src.data)
    hum = np.empty_like(src.data)
    pos = [0]

    def sink(block, removed):
        n = block.shape[0]
        out[pos[0]: pos[0] + n] = block
        hum[pos[0]: pos[0] + n] = removed
        pos[0] += n

    res = _run(src, sink, mains=mains, harmonics=harmonics, tones=tones, block_s=block_s, solver=solver,
               alpha=alpha, max_hz=max_hz, progress=progress, random_state=random_state,
               after_source_fn=lambda: ArraySource(out, sr), max_combs=max_combs)
    res.y = out[:, 0].copy() if src.mono else out
    res.hum = hum[:, 0].copy() if src.mono else hum
    return res


def denoise_file(path_in, path_out, *, subtype: str | None = None, mains="auto", harmonics="auto", tones=(),
                 block_s="auto", solver: str = "exact", alpha: float = 1e-3, max_hz: float | None = None,
                 progress: bool = False, random_state=0) -> DenoiseResult:
    """Stream ``path_in`` through :func:`denoise` into ``path_out`` (atomic; same rate, channels and
    subtype unless ``subtype`` is given). Options as in :func:`denoise`.

    Examples
    --------
    >>> import tempfile, os, soundfile as sf
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> d = tempfile.mkdtemp(); y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> sf.write(os.path.join(d, "in.wav"), y, sr, subtype="PCM_16")
    >>> r = denoise_file(os.path.join(d, "in.wav"), os.path.join(d, "out.wav"))
    >>> sf.info(os.path.join(d, "out.wav")).subtype
    'PCM_16'
    """
    import soundfile as sf

    from odnn_sep.io_utils import atomic_output, check_output_path

    src = FileSource(path_in)
    try:
        out = check_output_path(path_out, src.path)
        fmt, st = output_subtype(src, out, subtype)
        clip = ClipCounter(is_integer_subtype(st))
        with atomic_output(out) as tmp:
            kw = {"endian": src.endian} if fmt == src.format else {}
            with sf.SoundFile(str(tmp), "w", samplerate=src.sr, channels=src.channels, format=fmt, subtype=st,
                              **kw) as fo:
                def sink(block, removed):
                    fo.write(clip(block))

                res = _run(src, sink, mains=mains, harmonics=harmonics, tones=tones, block_s=block_s,
                           solver=solver, alpha=alpha, max_hz=max_hz, progress=progress,
                           random_state=random_state, after_source_fn=lambda: _flushed(fo, tmp))
    finally:
        src.close()
    res.clip_message = clip.message()
    if res.clip_message:
        log.warning(res.clip_message)
    res.info.update({"input": str(src.path), "output": str(out), "format": fmt, "subtype": st,
                     "input_subtype": src.subtype})
    return res


def _flushed(fo, tmp):
    # finish the file (FLAC/OGG cannot be read back while open for writing); the surrounding
    # ``with`` closing it again is a no-op
    fo.close()
    return FileSource(tmp)
