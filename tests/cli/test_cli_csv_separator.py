"""A table saved with ';' (and decimal commas), tabs or spaces is read as its header shows, by every reader.

A spreadsheet saved in a locale with decimal commas writes ``t;x`` over ``0,05;0,99``; such files were
refused with a request to re-save them. They now give the same numbers as the comma-separated file,
with a note saying how the file was read.
"""
import json

import pytest

from odnn_sep.cli import main
from odnn_sep.io_read import check_header, separator_of, table_rows

ROWS = [(0.05 * i, 1.0 - 0.01 * i + 0.3 * (0.05 * i) ** 2) for i in range(40)]


def _write(path, sep, decimal="."):
    def num(v):
        return f"{v:.6f}".replace(".", decimal)
    path.write_text(f"t{sep}x\n" + "\n".join(f"{num(a)}{sep}{num(b)}" for a, b in ROWS) + "\n")
    return path


CASES = [(";", ".", "';'-separated"), ("\t", ".", "tab-separated"), (";", ",", "';'-separated with decimal commas"),
         (" ", ".", "space-separated")]


@pytest.mark.parametrize("sep, decimal, how", CASES)
def test_separate_reads_other_separators(tmp_path, sep, decimal, how):
    reports = []
    for name, s, d in (("comma.csv", ",", "."), ("other.csv", sep, decimal)):
        rep = tmp_path / (name + ".json")
        assert main(["separate", str(_write(tmp_path / name, s, d)), "--basis", "t**2", "--report", str(rep),
                     "--quiet"]) == 0
        reports.append(json.loads(rep.read_text()))
    assert reports[0]["parameters"] == reports[1]["parameters"]


@pytest.mark.parametrize("sep, decimal, how", CASES)
def test_mismatch_reads_other_separators_with_a_note(tmp_path, capsys, sep, decimal, how):
    values = []
    for name, s, d in (("comma.csv", ",", "."), ("other.csv", sep, decimal)):
        rep = tmp_path / (name + ".json")
        assert main(["mismatch", str(_write(tmp_path / name, s, d)), "--model", "freefall", "--report", str(rep)]) == 0
        values.append(json.loads(rep.read_text())["calibration"]["parameters"])
    assert values[0] == values[1]
    assert f"Note: other.csv read as {how}" in capsys.readouterr().err


def test_series_reader_reads_decimal_commas(tmp_path):
    from odnn_sep.mismatch.series_io import read_series_csv

    p = tmp_path / "mugs.csv"
    p.write_text("t;mug;T\n0;A;90,5\n1;A;85,1\n0;B;80\n1;B;76,25\n")
    got = {k: (t.tolist(), y.tolist()) for k, (t, y) in read_series_csv(p, "mug").items()}
    assert got == {"A": ([0.0, 1.0], [90.5, 85.1]), "B": ([0.0, 1.0], [80.0, 76.25])}


def test_comma_files_and_text_cells_are_not_changed(tmp_path):
    assert separator_of(["t", "x"], ["0", "1"]) is None
    assert separator_of(["temperature"], ["20.5"]) is None            # one column: other checks say so
    assert separator_of(["t;x"], ["0.5;a"]) == ("';'", False)          # ';' without decimal commas
    check_header(["t", "note;x"], path="a.csv")                       # ';' inside a comma-separated cell
    p = tmp_path / "a.csv"
    p.write_text("t,note\n0,\"a;b\"\n1,\"c,d\"\n")
    assert table_rows(p) == ([["t", "note"], ["0", "a;b"], ["1", "c,d"]], None)
    p.write_text("t;note\n0,5;Hall 1,2\n")                           # a comma in a text cell stays
    assert table_rows(p)[0] == [["t", "note"], ["0.5", "Hall 1,2"]]
