"""``odnn-sep denoise``: the audio front-end's subcommand (argparse only at import time)."""
from __future__ import annotations

import argparse
import sys

HELP = "remove mains hum (tracked 50/60 Hz and harmonics) and tones from an audio file"

DESCRIPTION = """\
Remove mains hum from audio. The hum fundamental (50 or 60 Hz, or the given one, refined to
e.g. 60.055 Hz) is detected with a significance test, its instantaneous frequency is tracked,
and the harmonics that are present are fitted block by block (amplitude and phase per block and
channel) and subtracted; the music or speech underneath is left untouched. Output keeps the
sample rate, channels and subtype of the input and is written atomically.
"""

EXAMPLES = """\
examples:
  odnn-sep denoise noisy.wav -o clean.wav
  odnn-sep denoise take3.flac -o take3_clean.flac --mains 60 --report hum.json --plot hum.png
  odnn-sep denoise lecture.wav -o out.wav --harmonics 5 --tone 1000
"""


def register(subparsers) -> None:
    """Add the ``denoise`` subcommand and its options to ``subparsers``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers()`` returned.

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers())
    >>> args = parser.parse_args(["denoise", "in.wav", "-o", "out.wav", "--mains", "60", "--tone", "1000"])
    >>> args.mains, args.tone, args.harmonics, args.func is run
    ('60', [1000.0], 'auto', True)
    """
    p = subparsers.add_parser("denoise", help=HELP, description=DESCRIPTION, epilog=EXAMPLES,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", metavar="IN", help="input audio file (WAV, FLAC, OGG, AIFF; MP3 where supported)")
    p.add_argument("-o", "--output", metavar="OUT", required=True,
                   help="output audio file (format from its extension); never the input")
    p.add_argument("--mains", default="auto", metavar="auto|50|60|HZ",
                   help="hum fundamental: auto-detect 50/60 Hz (default) or a frequency in Hz, refined within +-1%%")
    p.add_argument("--harmonics", default="auto", metavar="auto|N|K,K,...",
                   help="auto: remove only harmonics that are present (default); N: remove harmonics 1..N; "
                        "a comma-separated list: remove exactly those (e.g. 1,3,5)")
    # one value per option; the CLI turns "--tone 50 100" into "--tone 50 --tone 100", so the input
    # file after the numbers is never taken as a tone
    p.add_argument("--tone", action="append", type=float, default=[], metavar="HZ",
                   help="extra fixed tone(s) to remove, in Hz (--tone 1000 2000 or --tone 1000 --tone 2000)")
    p.add_argument("--report", metavar="R.json", help="write a JSON report (track, amplitudes, phases, levels)")
    p.add_argument("--plot", metavar="P.png", help="write a figure: spectrograms, line levels, frequency track")
    p.add_argument("--solver", choices=("exact", "network"), default="exact",
                   help="exact least squares (default) or the torch ODNN network solver (slow)")
    p.add_argument("--block-s", default="auto", metavar="auto|S",
                   help="fit block length in seconds, 50%% overlap; auto (default) picks 8 s or 16 s from the data")
    p.add_argument("--max-hz", type=float, default=None, metavar="HZ",
                   help="highest harmonic frequency to consider (default 0.95 x Nyquist, 5 Hz under Nyquist at "
                        "rates of 1 kHz and under; 40 harmonics, more "
                        "while the locked comb reaches the top of them)")
    p.add_argument("--subtype", default=None, metavar="ST",
                   help="output subtype, e.g. PCM_16, PCM_24, FLOAT (default: same as the input)")
    p.add_argument("--picks", metavar="I,J,...", default=None,
                   help="multichannel files: clean only these channels (0-based); the others are written as read. "
                        "Reads the whole file into memory")
    p.add_argument("--spatial", action="store_true",
                   help="multichannel files whose channels share the hum (EEG-like): find its spatial components "
                        "first, then fit the lines (see README). Reads the whole file into memory")
    p.add_argument("--quiet", action="store_true", help="no progress bar or summary")
    p.set_defaults(func=run)


def _first_times(times, decimals: int) -> str:
    """The first five of ``times`` (s) for the summary line, "..." after them when there are more."""
    return ", ".join(f"{t:.{decimals}f}" for t in times[:5]) + (", ..." if len(times) > 5 else "")


def run(args) -> int:
    """Run ``odnn-sep denoise`` with the parsed ``args`` (see :func:`register`).

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line.

    Returns
    -------
    int
        The exit status (0; errors are raised as :class:`~odnn_sep.errors.InputError`).

    Examples
    --------
    >>> import argparse, os, tempfile, soundfile as sf
    >>> from odnn_sep.audio.synth import make_hum_demo
    >>> d = tempfile.mkdtemp(); y, sr, _ = make_hum_demo(duration_s=3.0, sr=8000)
    >>> sf.write(os.path.join(d, "in.wav"), y, sr)
    >>> parser = argparse.ArgumentParser(prog="odnn-sep"); register(parser.add_subparsers())
    >>> args = parser.parse_args(["denoise", os.path.join(d, "in.wav"), "-o", os.path.join(d, "out.wav"),
    ...                           "--quiet"])
    >>> run(args), sf.info(os.path.join(d, "out.wav")).frames
    (0, 24000)
    """
    from pathlib import Path

    from odnn_sep.audio.api import denoise_file
    from odnn_sep.errors import InputError
    from odnn_sep.io_paths import check_input_path, check_output_path
    from odnn_sep.io_utils import write_json

    inp = check_input_path(args.input, what="input audio file")
    check_output_path(args.output, inp)
    outs = {"--output": Path(args.output)}
    for flag, p in (("--report", args.report), ("--plot", args.plot)):
        if p:
            check_output_path(p, inp)
            for other_flag, other in outs.items():
                if Path(p).resolve() == other.resolve():
                    raise InputError(f"{flag} path {p!r} is the same as {other_flag}; choose different paths")
            outs[flag] = Path(p)
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".pdf", ".svg", ".jpg", ".jpeg"):
        raise InputError(f"--plot path {args.plot!r} must end in .png, .pdf, .svg or .jpg")

    if args.picks is not None or args.spatial:
        return _run_channels(args, inp)
    res = denoise_file(inp, args.output, subtype=args.subtype, mains=args.mains, harmonics=args.harmonics,
                       tones=args.tone, block_s=args.block_s, solver=args.solver, max_hz=args.max_hz,
                       progress=not args.quiet)
    if res.clip_message and args.quiet:     # (without --quiet the log has said it already)
        print(f"Warning: {res.clip_message}", file=sys.stderr)
    if args.report:
        write_json(args.report, res.as_dict())
    if args.plot:
        import soundfile as sf

        from odnn_sep.audio.plot import plot_denoise

        n = int(min(res.info["frames"], 120 * res.sr))
        before, _ = sf.read(str(inp), frames=n, dtype="float64", always_2d=True)
        after, _ = sf.read(str(args.output), frames=n, dtype="float64", always_2d=True)
        plot_denoise(res, before, after, args.plot)
    if not args.quiet:
        if res.harmonics or res.tones:
            lines = ", ".join(res.line_names)
            f0 = f"{res.mains_hz:.4f} Hz" if res.mains_hz else "-"
            level = res.info.get("level_followed_s")
            level = f"; its level was followed at {level:g} s" if level else ""
            jumps = res.info.get("level_steps_s") or []
            if jumps:
                level += f", stepping at {_first_times(jumps, 2)} s"
            steps = res.info.get("phase_steps") or []
            if steps:
                level += (f"; its phase jumps at {_first_times([st['time_s'] for st in steps], 3)} s "
                          "(a splice or a source switched over)")
            spans = res.info.get("hum_spans") or []
            if spans:
                level += ("; the hum sounds over " + ", ".join(f"{sp['start_s']:.1f}-{sp['end_s']:.1f} s" for sp in spans)
                          + " only: removed there, the rest written as read")
            print(f"removed hum: fundamental {f0} (family {res.nominal_hz}), lines {lines}{level} -> {args.output}")
        else:
            print(f"no significant hum found; wrote the input unchanged -> {args.output}")
    return 0


def _run_channels(args, inp) -> int:
    """--picks/--spatial: the whole file in memory through the EEG/MEG path (channels_file.py)."""
    from odnn_sep.audio.channels_file import denoise_file_channels, parse_picks, summary_line
    from odnn_sep.errors import InputError
    from odnn_sep.io_utils import write_json

    if args.plot:
        raise InputError("--plot is not available with --picks/--spatial; use --report for the lines removed")
    rep = denoise_file_channels(inp, args.output, picks=parse_picks(args.picks), spatial=args.spatial,
                                subtype=args.subtype, mains=args.mains, harmonics=args.harmonics, tones=args.tone,
                                block_s=args.block_s, solver=args.solver, max_hz=args.max_hz,
                                progress=not args.quiet)
    if rep["clipping"] and args.quiet:
        print(f"Warning: {rep['clipping']}", file=sys.stderr)
    if args.report:
        write_json(args.report, rep)
    if not args.quiet:
        print(summary_line(rep))
    return 0
