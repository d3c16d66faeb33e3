"""Audio sources (in-memory arrays or files read in blocks) and the progressive writer.

Denoising reads the input twice (tracking pass, then fit-and-write pass), always in bounded
blocks, so a file of any length uses a fixed amount of memory.
"""
from __future__ import annotations

import logging
from pathlib import Path

import numpy as np

from odnn_sep.audio.readahead import ReadAhead
from odnn_sep.errors import FormatError, InputError, as_float_array

log = logging.getLogger(__name__)


class ArraySource:
    """An in-memory signal, shaped (n, channels).

    Parameters
    ----------
    y : (n,) or (n, channels) array-like
        Samples along the first axis; copied to float64.
    sr : int
        Sample rate (Hz); a positive integer.

    Examples
    --------
    >>> import numpy as np
    >>> src = ArraySource(np.arange(6.0), 8000)
    >>> src.frames, src.channels, src.mono, src.read(4, 10).ravel().tolist()
    (6, 1, True, [4.0, 5.0])
    >>> ArraySource(np.zeros((2, 100)), 8000)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: y has shape (2, 100): more channels than samples; ...
    """

    def __init__(self, y, sr):
        arr = as_float_array("y", y, ndim=(1, 2))
        self.mono = arr.ndim == 1
        self.data = arr[:, None] if arr.ndim == 1 else arr
        if self.data.shape[1] > self.data.shape[0]:
            raise InputError(
                f"y has shape {arr.shape}: more channels than samples; pass samples along the first "
                f"axis, shape (n_samples, n_channels)")
        self.sr = _check_sr(sr)
        self.frames, self.channels = self.data.shape
        self.name = "y"

    @classmethod
    def wrap(cls, data: np.ndarray, sr: int) -> ArraySource:
        """A source over an array already checked (n, channels) float64, without copying it."""
        self = cls.__new__(cls)
        self.data, self.mono, self.sr, self.name = data, False, int(sr), "y"
        self.frames, self.channels = data.shape
        return self

    def read(self, start: int, n: int) -> np.ndarray:
        return self.data[max(start, 0): max(start + n, 0)]

    def reopen(self) -> ArraySource:
        """A source for another thread (an array is read without state: itself)."""
        return self

    def close(self):
        pass


class FileSource:
    """A sound file read with soundfile in blocks (float64, always 2-D).

    Parameters
    ----------
    path : str or path-like
        An existing sound file (WAV, FLAC, OGG, AIFF; MP3 where libsndfile supports it).

    Examples
    --------
    >>> import os, tempfile, numpy as np, soundfile as sf
    >>> p = os.path.join(tempfile.mkdtemp(), "a.wav")
    >>> sf.write(p, np.zeros((800, 2)), 8000, subtype="PCM_16")
    >>> src = FileSource(p)
    >>> src.sr, src.channels, src.frames, src.subtype, src.read(790, 100).shape
    (8000, 2, 800, 'PCM_16', (10, 2))
    >>> src.close()
    """

    def __init__(self, path):
        import soundfile as sf

        from odnn_sep.io_paths import check_input_path

        self.path = check_input_path(path, what="input audio file")
        self.name = str(self.path)
        try:
            self.f = sf.SoundFile(str(self.path))
        except (sf.LibsndfileError, RuntimeError, OSError, TypeError) as exc:
            msg = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
            raise FormatError(
                f"could not read input audio file {self.name!r}: {msg}; supported formats: WAV, FLAC, OGG, "
                f"AIFF, MP3 (where libsndfile supports it)") from None
        self.sr = int(self.f.samplerate)
        self.channels = int(self.f.channels)
        self.frames = int(self.f.frames)
        self.format, self.subtype, self.endian = self.f.format, self.f.subtype, self.f.endian
        self.mono = self.channels == 1
        # only float subtypes can hold NaN or inf (integer samples need no finiteness check)
        self._float_samples = not is_integer_subtype(self.subtype)
        if self.frames <= 0:
            self.f.close()
            raise FormatError(f"input audio file {self.name!r} has no samples (0 frames)")
        self.truncated = None
        self._decoded = self._decode_whole() if not self.f.seekable() else None
        self.reset_read_ahead()
        declared = wav_declared_frames(self.path, self.channels, self.subtype) if self.format == "WAV" else None
        if declared is not None and declared > self.frames:
            self.truncated = (
                f"input audio file {self.name!r} is truncated: its header declares {declared} frames "
                f"({declared / self.sr:.2f} s) but the file holds {self.frames} "
                f"({self.frames / self.sr:.2f} s); it ends at {self.frames / self.sr:.2f} s and only that much is "
                f"processed")
            log.warning(self.truncated)

    def _decode_whole(self) -> np.ndarray:
        """The whole file as float32 (frames, channels), for a coding libsndfile cannot seek in (GSM
        6.10 in WAV, a telephone format): every pass reads the input again from a frame it names,
        which such a file cannot give (the read failed with "Seek attempted on unseekable file
        type", called a corrupt file). At most ``MAX_UNSEEKABLE_SAMPLES`` samples (memory)."""
        import soundfile as sf

        if self.frames * self.channels > MAX_UNSEEKABLE_SAMPLES:
            self.f.close()
            raise FormatError(
                f"input audio file {self.name!r} is coded as {self.subtype}, which cannot be read in blocks, and "
                f"holds {self.frames / self.sr / 60:.0f} min, more than "
                f"{MAX_UNSEEKABLE_SAMPLES / self.channels / self.sr / 60:.0f} min read whole; convert it to WAV "
                f"(PCM) or FLAC first, e.g. sox in.wav -e signed-integer out.wav")
        try:
            return self.f.read(self.frames, dtype="float32", always_2d=True)
        except (sf.LibsndfileError, RuntimeError) as exc:
            raise FormatError(f"could not read input audio file {self.name!r}: {str(exc).splitlines()[0]} "
                              f"(the file may be truncated or corrupt)") from None

    def read(self, start: int, n: int) -> np.ndarray:
        """Samples ``start .. start + n`` (clipped to the file), float64 (m, channels); reads that
        follow each other are read ahead in a worker thread (readahead.py), the same values."""
        start = max(start, 0)
        n = max(0, min(n, self.frames - start))
        if n == 0:
            return np.zeros((0, self.channels))
        return self._reader.read(start, n)

    def reopen(self) -> FileSource:
        """The same file opened again, for reading from another thread (a sound file has one
        position); close it after use. The checks of the first opening are not repeated.

        Examples
        --------
        >>> import os, tempfile, numpy as np, soundfile as sf
        >>> p = os.path.join(tempfile.mkdtemp(), "a.wav")
        >>> sf.write(p, np.arange(8) / 10, 8000, subtype="FLOAT")
        >>> src = FileSource(p); other = src.reopen()
        >>> other.read(2, 3).ravel().round(3).tolist(), src.read(0, 1).ravel().tolist()
        ([0.2, 0.3, 0.4], [0.0])
        >>> other.close(); src.close()
        """
        import copy

        import soundfile as sf

        other = copy.copy(self)
        other.f = sf.SoundFile(str(self.path))
        other.reset_read_ahead()
        return other

    def reset_read_ahead(self):
        """Start without read-ahead state (no read in flight, no previous read, no worker)."""
        self._reader = ReadAhead(self._read_now, self.frames, lambda n: np.empty((n, self.channels)))

    def _read_now(self, start: int, n: int, out: np.ndarray | None = None) -> np.ndarray:
        import soundfile as sf

        try:
            if self._decoded is not None:      # a coding without seeking, read whole at the opening
                part = self._decoded[start: start + n]
                if out is None:
                    out = part.astype(np.float64)
                else:
                    out = out[: part.shape[0]]
                    out[...] = part
            else:
                self.f.seek(start)
                if self.subtype == "PCM_16":
                    # libsndfile's own float conversion of 16-bit samples is x / 32768, done here on the
                    # int16 read instead: the same values, at a tenth of the read's time
                    raw = self.f.read(n, dtype="int16", always_2d=True)
                    out = np.multiply(raw, 1.0 / 32768.0, out=out[: raw.shape[0]] if out is not None else None)
                else:
                    out = self.f.read(n, dtype="float64", always_2d=True, out=out)
        except (sf.LibsndfileError, RuntimeError) as exc:
            raise FormatError(f"could not read input audio file {self.name!r} at frame {start}: "
                              f"{str(exc).splitlines()[0]} (the file may be truncated or corrupt)") from None
        if out.shape[0] < n:
            raise FormatError(f"input audio file {self.name!r} ended at frame {start + out.shape[0]} but its "
                              f"header says {self.frames} frames (truncated or corrupt file)")
        if self._float_samples and not np.isfinite(out).all():
            bad = ~np.isfinite(out)
            r, c = np.argwhere(bad)[0]
            kind = "NaN" if np.isnan(out[r, c]) else "inf"
            raise InputError(f"input audio file {self.name!r} contains {kind} samples (first at frame "
                             f"{start + int(r)}, channel {int(c)}); repair the file before denoising")
        return out

    def close(self):
        self._reader.close()
        self.f.close()


def _check_sr(sr) -> int:
    try:
        v = float(sr)
    except (TypeError, ValueError):
        raise InputError(f"sr must be a positive sample rate in Hz; got {sr!r}") from None
    if not np.isfinite(v) or v <= 0 or v != int(v):
        raise InputError(f"sr must be a positive integer sample rate in Hz; got {sr!r}")
    return int(v)


def output_subtype(src: FileSource, out: Path, subtype: str | None) -> tuple[str, str]:
    """Container format and subtype for the output: same as the input unless the suffix or the
    caller asks otherwise.

    Parameters
    ----------
    src : FileSource
        The input.
    out : pathlib.Path
        The output path; its suffix names the container.
    subtype : str, optional
        The subtype asked for (soundfile name).

    Returns
    -------
    (str, str)
        Container format and subtype (soundfile names).

    Raises
    ------
    InputError
        For an unknown suffix, or a subtype asked for that the container cannot hold.

    Examples
    --------
    >>> import os, tempfile, numpy as np, soundfile as sf
    >>> from pathlib import Path
    >>> p = os.path.join(tempfile.mkdtemp(), "a.wav")
    >>> sf.write(p, np.zeros(800), 8000, subtype="PCM_16")
    >>> src = FileSource(p)
    >>> output_subtype(src, Path("x.flac"), None), output_subtype(src, Path("x.wav"), "FLOAT")
    (('FLAC', 'PCM_16'), ('WAV', 'FLOAT'))
    >>> src.close()
    """
    import soundfile as sf

    ext = out.suffix.lower().lstrip(".")
    fmt = {"wav": "WAV", "flac": "FLAC", "ogg": "OGG", "oga": "OGG", "aif": "AIFF", "aiff": "AIFF",
           "mp3": "MP3", "w64": "W64", "caf": "CAF"}.get(ext)
    if fmt is None:
        raise InputError(f"output file {str(out)!r} has an unsupported extension {out.suffix!r}; use .wav, "
                         f".flac, .ogg, .aiff or .mp3")
    st = subtype or (src.subtype if fmt == src.format else None)
    if st is None or not sf.check_format(fmt, st):
        if st is not None and subtype is not None:
            raise InputError(f"subtype {st!r} cannot be written to a {fmt} file; choose one of "
                             f"{sorted(sf.available_subtypes(fmt))}")
        keep = src.subtype if sf.check_format(fmt, src.subtype) else sf.default_subtype(fmt)
        if keep != src.subtype:
            log.warning("output format %s cannot hold subtype %s; writing %s", fmt, src.subtype, keep)
        st = keep
    _check_writable(fmt, st, src.sr, src.channels)
    return fmt, st


# Subtypes that re-encode with a perceptual coder: what is written is not the cleaned samples.
LOSSY_SUBTYPES = frozenset({"VORBIS", "OPUS", "MPEG_LAYER_I", "MPEG_LAYER_II", "MPEG_LAYER_III"})
# Codings that lose detail at every encode, written without a quality option (lossy_note warns).
CODED_SUBTYPES = frozenset({"GSM610", "IMA_ADPCM", "MS_ADPCM", "VOX_ADPCM", "G721_32", "G723_24", "G723_40",
                            "NMS_ADPCM_16", "NMS_ADPCM_24", "NMS_ADPCM_32"})
# Samples of a file whose coding cannot be read in blocks, read whole instead (float32: 160 MB,
# 83 min of 8 kHz mono telephone audio).
MAX_UNSEEKABLE_SAMPLES = 40_000_000


def lossy_write_options(subtype: str) -> dict:
    """Keyword options of ``soundfile`` for writing ``subtype``: the highest quality for a lossy coder.

    At the library's default quality a Vorbis re-encode of a cleaned 44.1 kHz test file differed from
    the cleaned samples by 0.010 RMS, four times the hum left after removal there (a 43 dB removal
    read as 4 dB); at the highest quality by 0.0012 (file 2.5x larger).

    Parameters
    ----------
    subtype : str
        Output subtype (soundfile name).

    Returns
    -------
    dict
        ``{"compression_level": 0.0}`` for a lossy subtype where the installed ``soundfile`` takes it,
        else empty.

    Examples
    --------
    >>> lossy_write_options("PCM_16")
    {}
    >>> lossy_write_options("VORBIS") in ({"compression_level": 0.0}, {})
    True
    """
    import inspect

    import soundfile as sf

    if subtype not in LOSSY_SUBTYPES:
        return {}
    if "compression_level" not in inspect.signature(sf.SoundFile.__init__).parameters:
        return {}
    return {"compression_level": 0.0}


def lossy_note(fmt: str, subtype: str) -> str | None:
    """The warning for a lossy output, or None.

    Examples
    --------
    >>> lossy_note("WAV", "PCM_24") is None
    True
    >>> lossy_note("OGG", "VORBIS").split(":")[0]
    'OGG/VORBIS is a lossy format'
    >>> lossy_note("WAV", "GSM610").split(":")[0]
    'WAV/GSM610 is a lossy coding (telephone or ADPCM)'
    """
    if subtype in CODED_SUBTYPES:
        return (f"{fmt}/{subtype} is a lossy coding (telephone or ADPCM): the cleaned audio was re-encoded, and "
                f"its coding error stays in the file; give --subtype PCM_16 (or write .flac) for the exact result")
    if subtype not in LOSSY_SUBTYPES:
        return None
    return (f"{fmt}/{subtype} is a lossy format: the cleaned audio was re-encoded (at the highest quality), and "
            f"the coding error stays in the file (0.0012 RMS on a 44.1 kHz test file, -35 dB re its signal, more "
            f"than a good removal leaves); write .wav or .flac for the exact result")


def _check_writable(fmt: str, subtype: str, sr: int, channels: int) -> None:
    """Open the output format in memory with the input's rate and channels, before any work: a
    container that cannot hold them (MP3 takes 8-48 kHz and at most 2 channels, FLAC at most 8
    channels) otherwise failed when the file was opened or first written, after the analysis."""
    import io

    import numpy as np
    import soundfile as sf

    try:
        with sf.SoundFile(io.BytesIO(), "w", samplerate=sr, channels=channels, format=fmt, subtype=subtype) as f:
            f.write(np.zeros((16, channels)))
    except (sf.LibsndfileError, RuntimeError, ValueError) as e:
        why = str(e).split("Error : ")[-1].split(": ", 1)[-1].strip().rstrip(".")
        raise InputError(f"the {fmt} format cannot hold {channels} channel(s) at {sr} Hz ({why}); write .wav or "
                         f".flac instead") from None


class BackgroundWriter:
    """Writes blocks to an open sound file from one worker thread, in order, with at most one
    block waiting: the encoding and the disk write (the sound-file library releases the GIL)
    overlap the fit of the next block. Errors surface at the next :meth:`write` or at
    :meth:`wait`.

    Parameters
    ----------
    fo : soundfile.SoundFile
        Open for writing; written only through this object until :meth:`wait` returns.

    Examples
    --------
    >>> import os, tempfile, numpy as np, soundfile as sf
    >>> p = os.path.join(tempfile.mkdtemp(), "a.wav")
    >>> with sf.SoundFile(p, "w", samplerate=8000, channels=1, subtype="PCM_16") as fo:
    ...     w = BackgroundWriter(fo)
    ...     w.write(np.zeros(800)); w.write(np.zeros(200)); w.close()
    >>> sf.info(p).frames
    1000
    """

    def __init__(self, fo):
        from concurrent.futures import ThreadPoolExecutor

        self.fo = fo
        self.pool = ThreadPoolExecutor(max_workers=1, thread_name_prefix="denoise-write")
        self.pending = None

    def write(self, block: np.ndarray):
        """Queue ``block`` (not modified afterwards by the caller) after the previous one."""
        self.wait()
        self.pending = self.pool.submit(self.fo.write, block)

    def wait(self):
        """Until every queued block is written (raises the write's error, if any)."""
        fut, self.pending = self.pending, None
        if fut is not None:
            fut.result()

    def close(self):
        """Wait for the queued block and stop the thread (errors are raised by :meth:`wait`)."""
        self.pool.shutdown(wait=True)


class ClipCounter:
    """Clips to [-1, 1] for integer subtypes and remembers how much was cut (never silently).

    Parameters
    ----------
    integer : bool
        Whether the output subtype is an integer one (only those are clipped).
    steps : int, optional
        Round to this many steps per unit before writing (128 for 8-bit subtypes, which
        libsndfile truncates: every sample came out half a step low, a DC shift of -0.5 LSB).

    Examples
    --------
    >>> import numpy as np
    >>> clip = ClipCounter(integer=True)
    >>> clip(np.array([0.5, 1.5, -2.0])).tolist(), clip.n_clipped
    ([0.5, 1.0, -1.0], 2)
    >>> clip.message()
    'output clipped: 2 sample(s) exceeded full scale by up to 6.02 dB (peak 2.0000); ...'
    >>> ClipCounter(integer=False).message() is None
    True
    >>> (ClipCounter(integer=True, steps=128)(np.array([0.3 + 0.7 / 128])) * 128).tolist()
    [39.0]
    """

    def __init__(self, integer: bool, steps: int | None = None):
        self.integer = integer
        self.steps = steps
        self.n_clipped = 0
        self.peak = 0.0

    def __call__(self, block: np.ndarray) -> np.ndarray:
        peak = 0.0
        if block.size:
            # max |x| from the extremes: no array of magnitudes per block
            peak = float(np.maximum(block.max(), -block.min()))
            self.peak = max(self.peak, peak)
        if self.integer and not peak <= 1.0:      # (a NaN peak too)
            over = np.abs(block) > 1.0
            if over.any():
                self.n_clipped += int(over.sum())
                block = np.clip(block, -1.0, 1.0)
        if self.steps:
            block = np.round(block * self.steps) / self.steps
        return block

    def message(self) -> str | None:
        if self.peak <= 1.0:
            return None
        db = 20 * np.log10(self.peak)
        if self.integer:
            return (f"output clipped: {self.n_clipped} sample(s) exceeded full scale by up to {db:.2f} dB "
                    f"(peak {self.peak:.4f}); lower the input gain or write a float subtype (--subtype FLOAT)")
        return (f"output peak {self.peak:.4f} exceeds full scale by {db:.2f} dB (float file, not clipped); "
                f"players may clip it")


def rounding_steps(subtype: str) -> int | None:
    """Steps per unit to round to before writing ``subtype`` (see :class:`ClipCounter`): 128 for the
    8-bit subtypes, None for the others (libsndfile rounds those itself).

    Examples
    --------
    >>> rounding_steps("PCM_U8"), rounding_steps("PCM_16")
    (128, None)
    """
    return 128 if subtype in ("PCM_U8", "PCM_S8") else None


def is_integer_subtype(subtype: str) -> bool:
    """Whether a soundfile subtype stores integers (PCM and the companded/ADPCM codecs).

    Parameters
    ----------
    subtype : str
        A soundfile subtype name.

    Returns
    -------
    bool

    Examples
    --------
    >>> is_integer_subtype("PCM_16"), is_integer_subtype("ULAW"), is_integer_subtype("FLOAT")
    (True, True, False)
    """
    return subtype.startswith(("PCM", "ULAW", "ALAW", "DWVW", "DPCM", "IMA", "MS_ADPCM", "GSM", "G72"))


_BYTES = {"PCM_U8": 1, "PCM_S8": 1, "PCM_16": 2, "PCM_24": 3, "PCM_32": 4, "FLOAT": 4, "DOUBLE": 8}


def wav_declared_frames(path, channels: int, subtype: str) -> int | None:
    """Frames the ``data`` chunk of a RIFF/WAVE header declares (None when not a plain PCM/float
    WAV, or when the size field is a streaming placeholder).

    Parameters
    ----------
    path : str or path-like
        The file.
    channels : int
        Channels of the file.
    subtype : str
        Its soundfile subtype (gives the bytes per sample).

    Returns
    -------
    int or None

    Examples
    --------
    >>> import os, tempfile, numpy as np, soundfile as sf
    >>> p = os.path.join(tempfile.mkdtemp(), "a.wav")
    >>> sf.write(p, np.zeros((800, 2)), 8000, subtype="PCM_16")
    >>> wav_declared_frames(p, 2, "PCM_16"), wav_declared_frames(p, 2, "VORBIS")
    (800, None)
    """
    width = _BYTES.get(subtype)
    if width is None:
        return None
    with open(path, "rb") as fh:
        head = fh.read(12)
        if len(head) < 12 or head[:4] != b"RIFF" or head[8:12] != b"WAVE":
            return None
        for _ in range(64):            # chunks before "data" (fmt, LIST, fact, ...)
            ch = fh.read(8)
            if len(ch) < 8:
                return None
            size = int.from_bytes(ch[4:8], "little")
            if ch[:4] == b"data":
                if size in (0, 0xFFFFFFFF):
                    return None
                return size // (width * channels)
            fh.seek(size + (size & 1), 1)
    return None
