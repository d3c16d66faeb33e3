"""A CSV with an empty value cell or a units row under the header is refused in one line that says
how to fix it, with no output written."""
from odnn_sep.cli import main

ROWS = [(2.0 * i, 22 + 58 * 0.997 ** (2 * i)) for i in range(60)]


def _run(tmp_path, capsys, text):
    src, rep = tmp_path / "d.csv", tmp_path / "r.json"
    src.write_text(text)
    rc = main(["mismatch", str(src), "--model", "cooling", "--quiet", "--report", str(rep)])
    return rc, capsys.readouterr().err.strip().splitlines(), rep


def test_an_empty_cell_is_named_as_a_missing_value(tmp_path, capsys):
    body = "\n".join(f"{a},{'' if i == 7 else b}" for i, (a, b) in enumerate(ROWS))
    rc, err, rep = _run(tmp_path, capsys, "t,T\n" + body + "\n")
    assert rc == 1 and len(err) == 1 and not rep.exists()
    assert "line 9" in err[0] and "the cell is empty (a missing value): remove that row or fill it" in err[0]


def test_a_units_row_says_where_units_go(tmp_path, capsys):
    body = "\n".join(f"{a},{b}" for a, b in ROWS)
    rc, err, rep = _run(tmp_path, capsys, "t,T\ns,degC\n" + body + "\n")
    assert rc == 1 and len(err) == 1 and not rep.exists()
    assert "line 2" in err[0] and "units belong in the header" in err[0]
