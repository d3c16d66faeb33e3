"""``odnn-sep denoise --picks/--spatial``: a multichannel sound file cleaned channel by channel or
through the hum's spatial components (channels.py, spatial.py).

Unlike the streamed default (api.denoise_file), these read the whole file into memory (the spatial
method needs every channel at once; picks leave the other channels bit for bit as read), so the
file's size is limited (``ODNN_SEP_MAX_IN_MEMORY_SAMPLES``). The output keeps the rate, channels
and subtype and is written atomically.
"""
from __future__ import annotations

import logging

from odnn_sep import limits
from odnn_sep.errors import InputError

log = logging.getLogger(__name__)


def parse_picks(text: str | None) -> list[int] | None:
    """``"0,2"`` -> ``[0, 2]`` (channel indices of a sound file, 0-based).

    Parameters
    ----------
    text : str or None
        The ``--picks`` value: comma-separated integers.

    Returns
    -------
    list of int or None
        None when no picks were given.

    Raises
    ------
    InputError
        When an entry is not an integer.

    Examples
    --------
    >>> parse_picks("0,2"), parse_picks("1,"), parse_picks(None)
    ([0, 2], [1], None)
    >>> parse_picks("left")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --picks must be comma-separated channel indices such as 0,2; got 'left'
    """
    if text is None:
        return None
    try:
        return [int(p) for p in text.split(",") if p.strip()]
    except ValueError:
        raise InputError(f"--picks must be comma-separated channel indices such as 0,2; got {text!r}") from None


def denoise_file_channels(path_in, path_out, *, picks=None, spatial=False, subtype=None, **engine_options) -> dict:
    """Clean the picked channels of ``path_in`` into ``path_out``; returns a JSON-ready report.

    Options as in :func:`odnn_sep.audio.channels.denoise_channels`; ``picks`` are channel indices.

    Parameters
    ----------
    path_in, path_out : str or path-like
        Input sound file and the file to write (atomically).
    picks : list of int, optional
        Channels to clean (0-based); default: all.
    spatial : bool
        Use the hum's spatial components (needs at least 2 channels).
    subtype : str, optional
        Output subtype (soundfile name); default: the input's.
    **engine_options
        ``mains``, ``harmonics``, ``tones``, ... as in :func:`odnn_sep.audio.denoise`.

    Returns
    -------
    dict
        JSON-ready: the files, format, per-channel summaries and one entry per line removed.

    Examples
    --------
    >>> import os, tempfile, soundfile as sf
    >>> from odnn_sep.audio.synth import make_hum_mix
    >>> y, _, _ = make_hum_mix(4.0, 8000, channels=2)
    >>> d = tempfile.mkdtemp(); sf.write(os.path.join(d, "in.wav"), y, 8000, subtype="FLOAT")
    >>> rep = denoise_file_channels(os.path.join(d, "in.wav"), os.path.join(d, "out.wav"), picks=[1])
    >>> rep["picks"], rep["channels"], sorted({ln["channel"] for ln in rep["lines"]})
    ([1], 2, [1])
    """
    import soundfile as sf

    from odnn_sep.audio.channels import denoise_channels
    from odnn_sep.audio.io import (
        ClipCounter,
        FileSource,
        is_integer_subtype,
        lossy_note,
        lossy_write_options,
        output_subtype,
        rounding_steps,
    )
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output

    src = FileSource(path_in)
    try:
        if spatial and src.channels < 2:
            raise InputError(f"--spatial needs a file with several channels sharing the hum; "
                             f"{src.name!r} has 1 channel: leave --spatial out")
        limits.check("in_memory_samples", src.frames * src.channels, "samples (frames x channels) to hold in memory",
                     hint="--picks/--spatial read the whole file; without them the file is streamed")
        out = check_output_path(path_out, src.path)
        fmt, st = output_subtype(src, out, subtype)
        data = src.read(0, src.frames)                                 # (frames, channels) float64
    finally:
        src.close()
    cleaned, report = denoise_channels(data, float(src.sr), picks=picks, spatial=spatial, channel_axis=1,
                                       return_report=True, **engine_options)
    clip = ClipCounter(is_integer_subtype(st), rounding_steps(st))
    kw = {"endian": src.endian} if fmt == src.format else {}
    with atomic_output(out) as tmp:
        sf.write(str(tmp), clip(cleaned), src.sr, format=fmt, subtype=st, **kw, **lossy_write_options(st))
    msg = clip.message()
    if msg:
        log.warning(msg)
    lossy = lossy_note(fmt, st)
    if lossy:
        log.warning(lossy)
    rep = _file_report(report, src, out, fmt, st, msg)
    if lossy:
        rep["lossy_output"] = lossy
    return rep


def _file_report(report: dict, src, out, fmt: str, st: str, clip_message) -> dict:
    lines = []
    for ch, summary in zip(report["picks"], report["channels"], strict=True):
        for i, f in enumerate(summary.get("line_freqs_hz", [])):
            lines.append({"channel": ch, "freq_hz": f,
                          "harmonic": summary["harmonics"][i] if i < len(summary["harmonics"]) else None,
                          "level_above_floor_db": {"before": summary["level_before_db"][i],
                                                   "after": summary["level_after_db"][i]}})
    return {"input": str(src.path), "output": str(out), "format": fmt, "subtype": st, "sr": src.sr,
            "channels": src.channels, "frames": src.frames, "duration_s": src.frames / src.sr,
            "method": report["method"], "picks": report["picks"], "per_channel": report["channels"],
            "spatial": report.get("spatial"), "lines": lines, "clipping": clip_message}


def summary_line(rep: dict) -> str:
    """One line for the terminal: what was removed where.

    Parameters
    ----------
    rep : dict
        A report of :func:`denoise_file_channels`.

    Returns
    -------
    str

    Examples
    --------
    >>> summary_line({"lines": [{"channel": 0}], "output": "out.wav"})
    'removed hum on channel(s) [0] -> out.wav'
    >>> summary_line({"lines": [], "output": "out.wav"})
    'no significant hum found on the picked channels; wrote the input unchanged -> out.wav'
    """
    found = sorted({ln["channel"] for ln in rep["lines"]})
    comps = (rep.get("spatial") or {}).get("components") or {}
    head = ""
    if comps.get("harmonics"):
        head = (f"removed hum through {rep['spatial']['n_components']} spatial component(s): fundamental "
                f"{comps['mains_hz']:.4f} Hz, harmonics {comps['harmonics']}")
    if not found and not head:
        return f"no significant hum found on the picked channels; wrote the input unchanged -> {rep['output']}"
    if head:
        per = f"; refitted channel(s) {found} on their own" if found else ""
        return f"{head}{per} -> {rep['output']}"
    return f"removed hum on channel(s) {found} -> {rep['output']}"
