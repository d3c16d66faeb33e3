"""A run imports only the front-end of its own subcommand (start-up time), and the table that says
which front-end registers which subcommand matches what the front-ends register."""
import argparse
import importlib
import subprocess
import sys

from odnn_sep.cli import COMMAND_MODULES, COMMAND_OF, build_parser


def test_command_table_matches_the_front_ends():
    found = {}
    for modname in COMMAND_MODULES:
        sub = argparse.ArgumentParser().add_subparsers(dest="command")
        importlib.import_module(modname).register(sub)
        found.update({name: modname for name in sub.choices})
    assert found == COMMAND_OF


def test_full_parser_without_a_command():
    text = build_parser().format_help()
    assert all(name in text for name in COMMAND_OF)


def test_unwatermark_run_does_not_import_other_front_ends():
    code = "from odnn_sep.cli import main; main(['unwatermark', '--help'])"
    probe = ("import sys\n"
             "try:\n    " + code + "\nexcept SystemExit:\n    pass\n"
             "print(sorted(m for m in sys.modules if m.startswith('odnn_sep.mismatch')))")
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip().splitlines()[-1] == "[]"
