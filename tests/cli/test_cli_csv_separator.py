"""A CSV saved with ';' or tabs as separator (and decimal commas) is named in one line by every reader."""
import pytest

from odnn_sep.cli import main
from odnn_sep.io_read import check_header, separator_of

ROWS = [(0.05 * i, 1.0 - 0.01 * i) for i in range(40)]


def _write(path, sep, decimal="."):
    def num(v):
        return f"{v:.6f}".replace(".", decimal)
    path.write_text(f"t{sep}x\n" + "\n".join(f"{num(a)}{sep}{num(b)}" for a, b in ROWS) + "\n")
    return path


CASES = [(";", ".", "';' as separator; save it as comma-separated with '.' decimals"),
         ("\t", ".", "tabs as separator; save it as comma-separated with '.' decimals"),
         (";", ",", "';' as separator (and ',' as decimal mark); save it as comma-separated with '.' decimals")]


@pytest.mark.parametrize("sep, decimal, message", CASES)
@pytest.mark.parametrize("command", [["separate", "--basis", "x"], ["mismatch", "--model", "oscillator"]])
def test_separator_is_named(tmp_path, capsys, sep, decimal, message, command):
    path = _write(tmp_path / "d.csv", sep, decimal)
    rc = main([command[0], str(path), *command[1:], "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert rc == 1
    assert err == [f"Error: {str(path)!r} seems to use {message}"]


def test_series_reader_names_the_separator(tmp_path):
    from odnn_sep.errors import FormatError
    from odnn_sep.mismatch.series_io import read_series_csv

    p = tmp_path / "mugs.csv"
    p.write_text("t;mug;T\n0;A;90,5\n1;A;85,1\n")
    with pytest.raises(FormatError, match=r"seems to use ';' as separator \(and ',' as decimal mark\)"):
        read_series_csv(p, "mug")


def test_comma_files_and_text_cells_are_not_flagged():
    assert separator_of(["t", "x"], ["0", "1"]) is None
    assert separator_of(["temperature"], ["20.5"]) is None            # one column: other checks say so
    assert separator_of(["t;x"], ["0.5;a"]) == ("';'", False)          # ';' without decimal commas
    check_header(["t", "note;x"], path="a.csv", first_row=["0", "a;b"])   # ';' inside a comma-separated cell
