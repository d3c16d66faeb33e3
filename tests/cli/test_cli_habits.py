"""Conventions users expect: global flags anywhere, --tone before the input, one --column rule,
--quiet everywhere, warnings on stderr."""
from __future__ import annotations

import json
import logging
import sys
from pathlib import Path

import numpy as np
import pytest

from odnn_sep.cli import _expand_multi_numbers, build_parser, main

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "robustness"))
from robustness_helpers import write_csv, write_wav  # noqa: E402


def test_tone_values_stop_at_the_first_non_number():
    assert _expand_multi_numbers(["denoise", "--tone", "1000", "2000", "in.wav", "-o", "o.wav"]) == [
        "denoise", "--tone", "1000", "--tone", "2000", "in.wav", "-o", "o.wav"]
    assert _expand_multi_numbers(["--tone", "50", "--tone", "60"]) == ["--tone", "50", "--tone", "60"]


@pytest.mark.parametrize("argv", [
    ["denoise", "--tone", "1000", "2000", "IN", "-o", "OUT"],
    ["denoise", "--tone", "1000", "--tone", "2000", "IN", "-o", "OUT"],
    ["denoise", "IN", "-o", "OUT", "--tone", "1000", "2000"],
])
def test_tone_forms_parse_the_same(argv):
    args = build_parser().parse_args(_expand_multi_numbers(argv))
    assert args.tone == [1000.0, 2000.0] and args.input == "IN"


def test_tone_before_input_runs(tmp_path):
    wav = write_wav(tmp_path / "a.wav", seconds=1.0)
    assert main(["denoise", "--tone", "1000", str(wav), "-o", str(tmp_path / "b.wav"), "--quiet"]) == 0


@pytest.mark.parametrize("where", ["first", "middle", "last"])
def test_debug_and_quiet_anywhere(tmp_path, where, capsys):
    csv = write_csv(tmp_path / "d.csv")
    core = ["separate", str(csv), "--basis", "x"]
    argv = {"first": ["--quiet", *core], "middle": [core[0], "--quiet", *core[1:]], "last": [*core, "--quiet"]}[where]
    assert main(argv) == 0
    assert capsys.readouterr().out == ""
    bad = ["separate", str(tmp_path / "missing.csv"), "--basis", "x"]
    argv = {"first": ["--debug", *bad], "middle": [bad[0], "--debug", *bad[1:]], "last": [*bad, "--debug"]}[where]
    with pytest.raises(Exception, match="does not exist"):
        main(argv)


def test_quiet_simulate_prints_nothing(tmp_path, capsys):
    assert main(["simulate", "figure2", "-o", str(tmp_path / "f.csv"), "--quiet"]) == 0
    assert capsys.readouterr().out == ""


def test_quiet_silences_dask_logging():
    main_args = ["--quiet", "simulate", "--help"]
    with pytest.raises(SystemExit):
        main(main_args)
    from odnn_sep.cli import _configure_logging

    _configure_logging(debug=False, quiet=True)
    assert logging.getLogger("distributed").getEffectiveLevel() >= logging.ERROR


def test_separate_warnings_go_to_stderr(tmp_path, capsys):
    x = np.linspace(-2, 2, 201)
    y = np.sin(5 * x) + x**2
    p = tmp_path / "c.csv"
    np.savetxt(p, np.c_[x, y], delimiter=",", header="x,y", comments="")
    assert main(["separate", str(p), "--basis", "sin(5*x)", "--disturbance", "convex"]) == 0
    out = capsys.readouterr()
    assert "Warning:" not in out.out and "Warning:" in out.err


@pytest.mark.parametrize("command", ["separate", "mismatch"])
def test_same_column_rule(tmp_path, command, capsys):
    csv = write_csv(tmp_path / "d.csv")
    base = {"separate": ["separate", str(csv), "--basis", "x"],
            "mismatch": ["mismatch", str(csv), "--model", "cooling"]}[command]
    assert main([*base, "--column", "0"]) == 1
    assert "is the coordinate column" in capsys.readouterr().err
    assert main([*base, "--column", "7"]) == 1
    assert "--column '7' is out of range" in capsys.readouterr().err
    assert main([*base, "--column", "yy"]) == 1
    assert "--column 'yy' is not a column of the CSV; did you mean 'y'?" in capsys.readouterr().err


def test_batch_summary_lists_options_and_patterns_cover_formats(tmp_path):
    from odnn_sep.batch import TARGETS

    assert "*.aiff" in TARGETS["denoise"][2] and "*.bmp" in TARGETS["unwatermark"][2]
    (tmp_path / "in").mkdir()
    write_wav(tmp_path / "in" / "A.Wav", seconds=0.5)
    assert main(["batch", "denoise", str(tmp_path / "in"), "-o", str(tmp_path / "out"), "--jobs", "1"]) == 0
    s = json.loads((tmp_path / "out" / "batch_summary.json").read_text())
    assert s["files"] == 1 and s["options"]["jobs"] == 1
