"""Public entry points of the audio front-end: :func:`denoise` on arrays, :func:`denoise_file` on
files (streamed). Both run the passes of :mod:`pipeline` and return a :class:`DenoiseResult`."""
from __future__ import annotations

import logging
import os
from collections.abc import Sequence

import numpy as np

from odnn_sep.audio.io import (
    ArraySource,
    BackgroundWriter,
    ClipCounter,
    FileSource,
    is_integer_subtype,
    lossy_note,
    lossy_write_options,
    output_subtype,
    rounding_steps,
)
from odnn_sep.audio.options import DenoiseOptions
from odnn_sep.audio.pipeline import run
from odnn_sep.audio.result import DenoiseResult

log = logging.getLogger(__name__)


def denoise(y: np.ndarray, sr: int | None = None, *, mains: str | float = "auto",
            harmonics: str | int | Sequence[int] = "auto", tones: Sequence[float] = (),
            block_s: str | float = "auto", solver: str = "exact", alpha: float = 1e-3,
            max_hz: float | None = None, progress: bool = False, random_state: int | None = 0,
            **channel_options):
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
    harmonics : 'auto', int or sequence of int
        ``'auto'`` removes only harmonics that pass the line test; an integer N removes 1..N; a
        sequence removes exactly those harmonic numbers (e.g. ``[1, 3, 5]`` for odd-only hum).
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
        Highest harmonic frequency considered (default: 0.95 x Nyquist, 5 Hz under Nyquist at rates of
        1 kHz and under; 40 harmonics, more while the locked comb reaches the top of them).
    progress : bool
        Show a progress bar on stderr (only when it is a terminal).
    random_state : int
        Seed for the network solver.
    **channel_options
        EEG/MEG use (``sfreq=``, ``picks=``, ``channel_axis=``, ``spatial=``, ``return_report=``):
        ``y`` is then a channels-first array with a float ``sfreq`` or an MNE Raw, and the result
        has the input's type; see :func:`odnn_sep.audio.channels.denoise_channels`.

    The keyword options are the public interface (librosa style); they are gathered at once into
    one :class:`~odnn_sep.audio.options.DenoiseOptions`, which is why this function takes more
    than eight parameters (why long).

    Returns
    -------
    DenoiseResult (the input's type for EEG/MEG use)

    Examples
    --------
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, truth = make_hum_demo(duration_s=4.0, sr=8000)
    >>> r = denoise(y, sr)
    >>> r.nominal_hz, r.harmonics[:2]
    (50.0, [1, 2])
    """
    from odnn_sep.audio import channels

    if channels.is_channel_call(y, sr, channel_options):
        return channels.denoise_channels(y, sr, **channel_options, mains=mains, harmonics=harmonics, tones=tones,
                                         block_s=block_s, solver=solver, alpha=alpha, max_hz=max_hz,
                                         progress=progress, random_state=random_state)
    opts = DenoiseOptions(mains=mains, harmonics=harmonics, tones=tones, block_s=block_s, solver=solver,
                          alpha=alpha, max_hz=max_hz, progress=progress, random_state=random_state)
    return denoise_array(y, sr, opts)


def denoise_array(y, sr, opts: DenoiseOptions) -> DenoiseResult:
    """:func:`denoise` with its options gathered in ``opts`` (validated in the pipeline).

    Parameters
    ----------
    y : (n,) or (n, channels) array
        Samples (any units); not modified.
    sr : int
        Sample rate (Hz).
    opts : DenoiseOptions
        The options of :func:`denoise`, as given (they are validated against ``sr`` here).

    Returns
    -------
    DenoiseResult
        With ``y`` (the cleaned samples) and ``hum`` (what was removed), shaped like the input,
        float32 for a float32 (or float16) input and float64 otherwise (as the channels-first
        EEG/MEG call keeps its input's type).

    Examples
    --------
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> r = denoise_array(y, sr, DenoiseOptions(mains=50))
    >>> r.y.shape == y.shape, r.nominal_hz, denoise_array(y.astype("float32"), sr, DenoiseOptions()).y.dtype
    (True, 50.0, dtype('float32'))
    """
    src = ArraySource(y, sr)
    # the source holds a private copy of y, read strictly ahead of what is written: the output
    # goes into it in place (one large allocation less)
    out = src.data
    k = unit_exponent(out)
    if k:
        out *= 2.0 ** -k      # a power of two: exact, and undone exactly below
    hum = np.empty_like(src.data)
    pos = [0]

    def sink(piece, removed):
        # piece is out[pos: pos + n] itself (a view of the private copy): subtract in place
        n = piece.shape[0]
        np.subtract(piece, removed, out=out[pos[0]: pos[0] + n])
        hum[pos[0]: pos[0] + n] = removed
        pos[0] += n

    res = run(src, sink, opts, after_source_fn=lambda: ArraySource.wrap(out, sr))
    if k:
        _rescale(res, out, hum, 2.0 ** k)
    res.y = out[:, 0] if src.mono else out
    res.hum = hum[:, 0] if src.mono else hum
    kind = getattr(y, "dtype", None)
    if kind is not None and kind.kind == "f" and kind.itemsize < 8:
        # computed in float64; handed back in the input's precision (librosa loads float32)
        res.y, res.hum = res.y.astype(np.float32), res.hum.astype(np.float32)
    return res


UNIT_RANGE = (2.0 ** -40, 2.0 ** 20)   # peak magnitudes analysed as given (about 1e-12 to 1e6)


def unit_exponent(x: np.ndarray) -> int:
    """The power of two that brings the peak of ``x`` to about 1 where it lies outside
    :data:`UNIT_RANGE`, else 0. The analysis keeps single-precision chunk sums and absolute
    floors: samples of 1e20 overflowed them (hundreds of NumPy warnings, then "no hum found"),
    samples of 1e-30 fell under them ("no hum found" in silence); the result must not depend on
    the units.

    Examples
    --------
    >>> unit_exponent(np.array([0.5, -0.9])), unit_exponent(np.array([3e20])), unit_exponent(np.array([1e-30]))
    (0, 68, -100)
    >>> unit_exponent(np.zeros(4))
    0
    """
    peak = float(np.max(np.abs(x))) if x.size else 0.0
    if peak == 0 or UNIT_RANGE[0] <= peak <= UNIT_RANGE[1]:
        return 0
    return int(np.round(np.log2(peak)))


def _rescale(res: DenoiseResult, out: np.ndarray, hum: np.ndarray, g: float) -> None:
    """Back to the input's units: the samples, the amplitudes and the spectra (levels are ratios)."""
    out *= g
    hum *= g
    res.amplitudes = res.amplitudes * g
    if res.amplitude_overall is not None:
        res.amplitude_overall = res.amplitude_overall * g
    with np.errstate(over="ignore"):    # the power of samples near 1e200 is past float64: inf
        res.spectra = {k: (v * g * g if k != "freqs" else v) for k, v in res.spectra.items()}


def denoise_file(path_in: str | os.PathLike, path_out: str | os.PathLike, *, subtype: str | None = None,
                 mains: str | float = "auto", harmonics: str | int | Sequence[int] = "auto",
                 tones: Sequence[float] = (), block_s: str | float = "auto", solver: str = "exact",
                 alpha: float = 1e-3, max_hz: float | None = None, progress: bool = False,
                 random_state: int | None = 0) -> DenoiseResult:
    """Stream ``path_in`` through :func:`denoise` into ``path_out`` (atomic; same rate, channels and
    subtype unless ``subtype`` is given). Options as in :func:`denoise` (gathered into one
    :class:`~odnn_sep.audio.options.DenoiseOptions`: why long).

    Parameters
    ----------
    path_in : str or path-like
        Input sound file (WAV, FLAC, OGG, AIFF; MP3 where supported).
    path_out : str or path-like
        Output file (format from its extension; never the input), written atomically.
    subtype : str, optional
        Output subtype (soundfile name, e.g. ``'PCM_24'``, ``'FLOAT'``); default: the input's.
    mains, harmonics, tones, block_s, solver, alpha, max_hz, progress, random_state
        As in :func:`denoise`.

    Returns
    -------
    DenoiseResult
        Without sample arrays (``y`` and ``hum`` are None); ``info`` names the files, format and
        subtype, ``clip_message`` and ``requantisation_message`` say what writing cost.

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
    opts = DenoiseOptions(mains=mains, harmonics=harmonics, tones=tones, block_s=block_s, solver=solver,
                          alpha=alpha, max_hz=max_hz, progress=progress, random_state=random_state)
    return denoise_path(path_in, path_out, opts, subtype=subtype)


def denoise_path(path_in, path_out, opts: DenoiseOptions, *, subtype: str | None = None) -> DenoiseResult:
    """:func:`denoise_file` with its options gathered in ``opts``.

    Parameters
    ----------
    path_in, path_out : str or path-like
        Input sound file and the file to write (written atomically).
    opts : DenoiseOptions
        The options of :func:`denoise`.
    subtype : str, optional
        Output subtype (soundfile name, e.g. ``'PCM_24'``); default: the input's.

    Returns
    -------
    DenoiseResult
        Without sample arrays; ``info`` names the files, format and subtype written.

    Examples
    --------
    >>> import tempfile, os, soundfile as sf
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> d = tempfile.mkdtemp(); y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> sf.write(os.path.join(d, "in.wav"), y, sr, subtype="PCM_16")
    >>> r = denoise_path(os.path.join(d, "in.wav"), os.path.join(d, "out.wav"), DenoiseOptions(),
    ...                  subtype="FLOAT")
    >>> r.info["subtype"], sf.info(os.path.join(d, "out.wav")).frames
    ('FLOAT', 24000)
    """
    import soundfile as sf

    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output

    src = FileSource(path_in)
    try:
        out = check_output_path(path_out, src.path)
        fmt, st = output_subtype(src, out, subtype)
        clip = ClipCounter(is_integer_subtype(st), rounding_steps(st))
        with atomic_output(out) as tmp:
            kw = {"endian": src.endian} if fmt == src.format else {}
            with sf.SoundFile(str(tmp), "w", samplerate=src.sr, channels=src.channels, format=fmt, subtype=st,
                              **kw, **lossy_write_options(st)) as fo:
                res, removed_ss = _run_to_file(src, fo, tmp, clip, opts)
    finally:
        src.close()
    res.clip_message = clip.message()
    if res.clip_message:
        log.warning(res.clip_message)
    res.info.update({"input": str(src.path), "output": str(out), "format": fmt, "subtype": st,
                     "input_subtype": src.subtype, "truncated": src.truncated})
    res.requantisation_message = requantisation_note(removed_ss / max(src.frames * src.channels, 1), st)
    if res.requantisation_message:
        log.warning(res.requantisation_message)
    lossy = lossy_note(fmt, st)
    if lossy:
        res.info["lossy_output"] = lossy
        log.warning(lossy)
    return res


def _run_to_file(src, fo, tmp, clip, opts: DenoiseOptions):
    """All passes over ``src`` with the cleaned blocks written to ``fo`` (open on ``tmp``) by a
    BackgroundWriter: the result and the sum of the squared hum removed."""
    removed_ss = [0.0]
    writer = BackgroundWriter(fo)

    def sink(piece, removed):
        removed_ss[0] += float(np.sum(np.square(removed, dtype=np.float64)))
        writer.write(clip(piece - removed))

    def written():
        writer.wait()
        return _flushed(fo, tmp)

    try:
        res = run(src, sink, opts, after_source_fn=written)
    finally:
        writer.close()
    return res, removed_ss[0]


def _flushed(fo, tmp):
    # finish the file (FLAC/OGG cannot be read back while open for writing); the surrounding
    # ``with`` closing it again is a no-op
    fo.close()
    return FileSource(tmp)


_PCM_BITS = {"PCM_S8": 8, "PCM_U8": 8, "PCM_16": 16}


def requantisation_note(removed_power: float, subtype: str) -> str | None:
    """A warning when the hum removed (mean power, full scale 1) is within 10 dB of the noise that
    writing ``subtype`` adds (an 8/16-bit integer output is requantised after the subtraction:
    noise of power LSB^2 / 12 over the whole band, where the hum was a few lines).

    Parameters
    ----------
    removed_power : float
        Mean power of the hum removed per sample (full scale 1).
    subtype : str
        Output subtype (soundfile name); only 8- and 16-bit integer subtypes can warn.

    Returns
    -------
    str or None
        The warning, or None when the requantisation noise is negligible.

    Examples
    --------
    >>> requantisation_note(1e-2, "PCM_16") is None
    True
    >>> requantisation_note(1e-12, "PCM_16")
    'the hum removed (-120.0 dBFS) is within 10 dB of the requantisation noise ... PCM_24 or FLOAT ...'
    >>> requantisation_note(1e-12, "FLOAT") is None
    True
    """
    bits = _PCM_BITS.get(subtype)
    if bits is None or removed_power <= 0:
        return None
    q_power = (2.0 ** (1 - bits)) ** 2 / 12
    if removed_power >= 10 * q_power:
        return None
    return (f"the hum removed ({10 * np.log10(removed_power):.1f} dBFS) is within 10 dB of the requantisation "
            f"noise that writing {subtype} adds ({10 * np.log10(q_power):.1f} dBFS, spread over the whole band): "
            f"write --subtype PCM_24 or FLOAT to keep the difference")
