"""Command-line entry point: parse, call a front-end, write, map errors to exit codes.

Each subcommand lives in its front-end as a module exposing ``register(subparsers)``; that
module imports only argparse at top level so ``odnn-sep --help`` stays fast and torch-free.
Exit codes: 0 success, 1 user error (bad input/file), 2 usage error (argparse), 130 interrupted
(Ctrl-C), 143 terminated (SIGTERM).

Every run is one transaction: its inputs and outputs are checked against each other before any
work, and if the run fails or is interrupted after writing some outputs, those are removed again.
"""
from __future__ import annotations

import argparse
import importlib
import logging
import os
import signal
import sys
import threading

from odnn_sep import __version__
from odnn_sep.errors import OdnnSepError

# Front-end command modules, in the order they appear in --help.
COMMAND_MODULES = (
    "odnn_sep.audio.command",
    "odnn_sep.image.command",
    "odnn_sep.mismatch.command",
    "odnn_sep.fit.command",
    "odnn_sep.signals.command",
    "odnn_sep.batch",
)
# The subcommand each front-end registers: a run imports only its own front-end (importing
# odnn_sep.mismatch alone costs ~0.3 s of start-up; tests check this table against ``register``).
COMMAND_OF = {
    "denoise": "odnn_sep.audio.command",
    "unwatermark": "odnn_sep.image.command",
    "mismatch": "odnn_sep.mismatch.command",
    "separate": "odnn_sep.fit.command",
    "simulate": "odnn_sep.signals.command",
    "batch": "odnn_sep.batch",
}

# Options that name files the run reads, and files it writes (checked against each other).
INPUT_OPTIONS = {"input": "the input", "data": "the input", "mask": "--mask"}
OUTPUT_OPTIONS = {"output": "--output", "report": "--report", "plot": "--plot", "truth": "--truth",
                  "summary": "--summary"}

# Flags accepted anywhere on the line (before a bare "--").
GLOBAL_FLAGS = ("--debug", "--quiet")

# Options taking several numbers: "--tone 50 100 in.wav" stops at the first non-number.
MULTI_NUMBER_OPTIONS = ("--tone",)


class Terminated(KeyboardInterrupt):
    """SIGTERM, turned into an exception so that clean-up (``finally``) runs.

    A subclass of :class:`KeyboardInterrupt`, so code that stops on Ctrl-C stops on SIGTERM too;
    :func:`main` maps it to exit code 143 (130 for Ctrl-C).

    Examples
    --------
    >>> issubclass(Terminated, KeyboardInterrupt)
    True
    >>> try:
    ...     raise Terminated()
    ... except KeyboardInterrupt as exc:
    ...     type(exc).__name__
    'Terminated'
    """


def _on_sigterm(signum, frame):
    raise Terminated()


class LateSignals:
    """SIGINT and SIGTERM once a run's outputs are in place: noted, no longer raised.

    Before that point an interrupt takes every output back (exit 130 or 143). After it, the
    outputs are complete and stay, so the exit status must not say otherwise: the signal is
    only noted, :meth:`release` says so in one line and the run exits with its own status.
    A process that exits after the run (the console script) ignores both signals from then
    on, through the interpreter's shutdown, where Python would reset its handlers and let a late
    Ctrl-C end the process with 130 and no message.

    Examples
    --------
    >>> import signal
    >>> late = LateSignals()
    >>> late.hold()
    >>> late._note(signal.SIGINT, None)    # what a Ctrl-C after the outputs were committed calls
    >>> late.signum == signal.SIGINT
    True
    >>> late.release()
    'interrupted after the outputs were written; they are complete'
    >>> signal.getsignal(signal.SIGINT) is signal.default_int_handler
    True
    """

    SIGNALS = (signal.SIGINT, signal.SIGTERM)

    def __init__(self):
        self.signum = None
        self.previous: dict = {}

    def _note(self, signum, frame):
        self.signum = signum

    def hold(self) -> None:
        """From now on SIGINT and SIGTERM are only noted (main thread only; elsewhere nothing changes)."""
        if threading.current_thread() is not threading.main_thread():
            return
        for s in self.SIGNALS:
            self.previous.setdefault(s, signal.getsignal(s))
            signal.signal(s, self._note)

    def release(self, *, ignore: bool = False):
        """Put the previous handlers back (``ignore``: ignore both signals instead); the line to print or None."""
        for s, h in self.previous.items():
            signal.signal(s, signal.SIG_IGN if ignore else (h if h is not None else signal.SIG_DFL))
        self.previous.clear()
        if self.signum is None:
            return None
        what = "terminated" if self.signum == signal.SIGTERM else "interrupted"
        return f"{what} after the outputs were written; they are complete"


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The ``odnn-sep`` argument parser with every subcommand, or with ``command`` only.

    Parameters
    ----------
    command : str, optional
        A subcommand of ``COMMAND_OF``: only its front-end is imported (a faster start). Any other
        value, or None: every subcommand.

    Returns
    -------
    argparse.ArgumentParser

    Examples
    --------
    >>> args = build_parser().parse_args(["simulate", "figure2", "-o", "fig2.csv", "--seed", "3"])
    >>> args.command, args.seed
    ('simulate', 3)
    >>> "denoise" in build_parser("simulate").format_help(), "denoise" in build_parser().format_help()
    (False, True)
    """
    parser = argparse.ArgumentParser(
        prog="odnn-sep",
        description="Separate known physics (hum, watermarks, model terms) from disturbances, "
        "and find the physics a simulation left out.",
        epilog="--debug and --quiet may be given anywhere on the line.",
    )
    parser.add_argument("--version", action="version", version=f"odnn-sep {__version__}")
    parser.add_argument("--debug", action="store_true", help="show full tracebacks and debug logs")
    parser.add_argument("--quiet", action="store_true", help="no progress, summaries or info logs")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for modname in (COMMAND_OF[command],) if command in COMMAND_OF else COMMAND_MODULES:
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:  # front-end not present in this build
                continue
            raise
        mod.register(sub)
    for p in sub.choices.values():  # so that every command's --help lists the global flags
        if "--quiet" not in p._option_string_actions:
            p.add_argument("--quiet", action="store_true", help="no progress bar or summary")
        if "--debug" not in p._option_string_actions:
            p.add_argument("--debug", action="store_true", help="show full tracebacks and debug logs")
    return parser


def _split_argv(argv: list[str]):
    """(own arguments, arguments after a bare '--', global flags found)."""
    passthrough: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, passthrough = argv[:i], argv[i + 1:]
    flags = {f for f in GLOBAL_FLAGS if f in argv}
    argv = [a for a in argv if a not in GLOBAL_FLAGS]
    return _expand_multi_numbers(argv), passthrough, flags


def _expand_multi_numbers(argv: list[str]) -> list[str]:
    """'--tone 50 100' -> '--tone 50 --tone 100', so a following input file is never swallowed."""
    out: list[str] = []
    i = 0
    while i < len(argv):
        a = argv[i]
        out.append(a)
        i += 1
        if a in MULTI_NUMBER_OPTIONS and i < len(argv):
            out.append(argv[i])
            i += 1
            while i < len(argv) and _is_number(argv[i]):
                out += [a, argv[i]]
                i += 1
    return out


def _is_number(s: str) -> bool:
    try:
        float(s)
    except ValueError:
        return False
    return not s.startswith("-") or s[1:2].isdigit() or s[1:2] == "."


def _check_paths(args) -> None:
    from odnn_sep.io_paths import check_run_paths

    ns = vars(args)
    if args.command == "batch":
        return  # batch checks its many inputs and outputs itself
    inputs = {label if k != "mask" else "--mask": ns.get(k) for k, label in INPUT_OPTIONS.items()
              if isinstance(ns.get(k), str)}
    outputs = {label: ns.get(k) for k, label in OUTPUT_OPTIONS.items() if isinstance(ns.get(k), str)}
    check_run_paths(inputs, outputs)


class _StderrHandler(logging.StreamHandler):
    """Writes to whatever ``sys.stderr`` is at the time (so in-process runs and captures work)."""

    @property
    def stream(self):
        return sys.stderr

    @stream.setter
    def stream(self, value):
        pass


def _configure_logging(debug: bool, quiet: bool) -> None:
    level = logging.DEBUG if debug else logging.ERROR if quiet else logging.WARNING
    root = logging.getLogger()
    handler = next((h for h in root.handlers if isinstance(h, _StderrHandler)), None)
    if handler is None:
        handler = _StderrHandler()
        handler.setFormatter(logging.Formatter("%(levelname)s: %(message)s"))
        root.addHandler(handler)
    # libraries that set their own loggers to INFO (dask) still only reach the user at this level
    handler.setLevel(level)
    root.setLevel(level)
    if not debug:
        import warnings

        # a warning is one line for the user ("path.py:292: ConvergenceWarning: ..." and the source
        # line are for developers: --debug keeps Python's format)
        def one_line(message, category, filename, lineno, file=None, line=None):
            print(f"Warning: {message}", file=sys.stderr if file is None else file)
        warnings.showwarning = one_line
    if quiet and not debug:
        for name in ("distributed", "dask", "tornado", "asyncio", "bokeh"):
            logging.getLogger(name).setLevel(logging.ERROR)
        import warnings

        warnings.filterwarnings("ignore", module="distributed")


def main(argv: list[str] | None = None) -> int:
    """Run the ``odnn-sep`` command line; return its exit code.

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name (default ``sys.argv[1:]``). ``--debug`` and ``--quiet``
        may stand anywhere; what follows a bare ``--`` is passed on by ``batch``.

    Returns
    -------
    int
        0 success, 1 user error (bad input or file, printed as one ``Error:`` line on stderr),
        130 interrupted, 143 terminated. Usage errors exit through argparse with code 2.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     data = os.path.join(d, "fig2.csv")
    ...     made = main(["simulate", "figure2", "-o", data, "--quiet"])
    ...     fitted = main(["separate", data, "--basis", "x**2*sin(5*x)", "--disturbance", "even",
    ...                    "-o", os.path.join(d, "parts.csv"), "--quiet"])
    ...     written = sorted(os.listdir(d))
    >>> made, fitted, written
    (0, 0, ['fig2.csv', 'parts.csv'])
    >>> main(["separate", "no-such-file.csv", "--basis", "x", "--quiet"])    # the message goes to stderr
    1
    """
    # OpenCV's C++ logger would print its own warnings for every unreadable image; our errors say it
    os.environ.setdefault("OPENCV_LOG_LEVEL", "OFF")
    from_argv = argv is None
    argv = sys.argv[1:] if argv is None else list(argv)
    # Everything after a bare "--" is handed to the command a batch runs (argparse's own "--"
    # handling does not reach sub-parsers reliably).
    argv, passthrough, flags = _split_argv(argv)
    # the subcommand is the first argument (the only top-level options, --help and --version, come
    # without one: then every front-end is loaded, for the full help)
    parser = build_parser(argv[0] if argv else None)
    args = parser.parse_args(argv)
    if passthrough and args.command != "batch":
        parser.error("options after '--' are only used by 'batch'")
    args.passthrough = passthrough
    args.debug = bool(getattr(args, "debug", False) or "--debug" in flags)
    args.quiet = bool(getattr(args, "quiet", False) or "--quiet" in flags)
    _configure_logging(args.debug, args.quiet)
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    # called as the program (console script, python -m): after the run, the process only exits
    return _run(args, process_exit=from_argv)


def _run(args, *, process_exit=False) -> int:
    from odnn_sep.io_utils import describe_os_error, output_transaction
    from odnn_sep.report.schema import run_context

    installed = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGTERM, _on_sigterm) if installed else None
    late = LateSignals()
    try:
        from odnn_sep.validate import validate

        validate(args)
        _check_paths(args)
        with run_context(args.command, vars(args)), output_transaction():
            code = int(args.func(args) or 0)
            # every output is in place (only the temporary folders are left to remove): from here a
            # signal cannot take them back, so it must not turn the exit status into 130
            late.hold()
        note = late.release(ignore=process_exit)
        if note:
            print(note.capitalize() + ".", file=sys.stderr)
        return code
    except OdnnSepError as exc:
        if args.debug:
            raise
        print(f"Error: {exc}", file=sys.stderr)
        return 1
    except UnicodeDecodeError as exc:
        if args.debug:
            raise
        print(f"Error: a file that should be text is not UTF-8 ({exc.reason} at byte {exc.start}); save it as "
              "UTF-8 text", file=sys.stderr)
        return 1
    except OSError as exc:
        if args.debug:
            raise
        print(f"Error: {describe_os_error(exc)}", file=sys.stderr)
        return 1
    except MemoryError:
        if args.debug:
            raise
        print("Error: out of memory; use a smaller input (or a smaller limit) and try again", file=sys.stderr)
        return 1
    except KeyboardInterrupt as exc:
        terminated = isinstance(exc, Terminated)
        print("Terminated; nothing of this run was kept." if terminated else
              "Interrupted; nothing of this run was kept.", file=sys.stderr)
        return 143 if terminated else 130
    finally:
        late.release()
        if installed and process_exit:
            # the run is over and its exit status decided: a signal during the interpreter's
            # shutdown must not replace it
            for s in LateSignals.SIGNALS:
                signal.signal(s, signal.SIG_IGN)
        elif installed:
            signal.signal(signal.SIGTERM, previous if previous is not None else signal.SIG_DFL)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
