"""Command-line entry point: parse, call a front-end, write, map errors to exit codes.

Each subcommand lives in its front-end as a module exposing ``register(subparsers)``; that
module imports only argparse at top level so ``odnn-sep --help`` stays fast and torch-free.
Exit codes: 0 success, 1 user error (bad input/file), 2 usage error (argparse).
"""
from __future__ import annotations

import argparse
import importlib
import logging
import sys

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


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="odnn-sep",
        description="Separate known physics (hum, watermarks, model terms) from disturbances, "
        "and find the physics a simulation left out.",
    )
    parser.add_argument("--version", action="version", version=f"odnn-sep {__version__}")
    parser.add_argument("--debug", action="store_true", help="show full tracebacks and debug logs")
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for modname in COMMAND_MODULES:
        try:
            mod = importlib.import_module(modname)
        except ModuleNotFoundError as exc:
            if exc.name == modname:  # front-end not present in this build
                continue
            raise
        mod.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    parser = build_parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    # Everything after a bare "--" is handed to the command a batch runs (argparse's own "--"
    # handling does not reach sub-parsers reliably).
    passthrough: list[str] = []
    if "--" in argv:
        i = argv.index("--")
        argv, passthrough = argv[:i], argv[i + 1:]
    args = parser.parse_args(argv)
    if passthrough and args.command != "batch":
        parser.error("options after '--' are only used by 'batch'")
    args.passthrough = passthrough
    logging.basicConfig(
        level=logging.DEBUG if args.debug else logging.WARNING,
        format="%(levelname)s: %(message)s",
    )
    if not getattr(args, "func", None):
        parser.print_help()
        return 2
    try:
        return int(args.func(args) or 0)
    except OdnnSepError as exc:
        if args.debug:
            raise
        print(f"Error: {exc}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        print("Interrupted.", file=sys.stderr)
        return 130


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
