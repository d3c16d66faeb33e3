"""CSV layouts users hand over: a pandas index column, comment lines above the header, spaces.

Before, a pandas index was taken for the time and the time column for the values (a cooling record
read as temperatures "up to 300, looking like degF" and a nonsense verdict); '# sensor: ...' lines
above the header were read as the header ("needs at least two columns"); a space-separated table was
refused as "one column", then named as space-separated, and is now read as such.
"""
import json

import numpy as np


def _cooling(n=200):
    t = np.linspace(0, 300, n)
    return t, 20 + 60 * np.exp(-0.01 * t) + 0.05 * np.random.default_rng(0).normal(size=n)


def test_mismatch_reads_past_a_pandas_index(tmp_path, capsys):
    from odnn_sep.cli import main
    t, T = _cooling()
    f = tmp_path / "pd.csv"
    f.write_text(",t,T\n" + "".join(f"{k},{a},{b}\n" for k, (a, b) in enumerate(zip(t, T, strict=True))))
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(f), "--model", "cooling", "--report", str(rep)]) == 0
    d = json.loads(rep.read_text())
    assert "counts the rows" in capsys.readouterr().err
    assert abs(d["calibration"]["parameters"]["h"]["value"] - 0.01) < 1e-3


def test_a_sample_number_time_column_is_kept():
    from odnn_sep.io_read import row_index_column
    t, T = _cooling(5)
    # named 'index', values that do not rise next to it: the counter is the time in samples
    assert not row_index_column(["index", "T", "ref"], [list(range(5)), list(T)])
    assert row_index_column(["index", "time_s", "T"], [list(range(5)), list(t)])


def test_comment_lines_above_the_header(tmp_path, capsys):
    from odnn_sep.cli import main
    t, T = _cooling()
    f = tmp_path / "logger.csv"
    f.write_text("# exported by the logger\n# sensor: PT100, range 0-100\nt,T\n"
                 + "".join(f"{a},{b}\n" for a, b in zip(t, T, strict=True)))
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(f), "--model", "cooling", "--report", str(rep), "--quiet"]) == 0
    assert abs(json.loads(rep.read_text())["calibration"]["parameters"]["h"]["value"] - 0.01) < 1e-3
    g = tmp_path / "sig.csv"
    x = np.linspace(0, 10, 200)
    g.write_text("# from the scope\nx,y\n" + "".join(f"{a},{2 * np.sin(1.3 * a)}\n" for a in x))
    assert main(["separate", str(g), "--basis", "sin(1.3*x)", "--quiet"]) == 0


def test_space_separated_table_is_read(tmp_path, capsys):
    import json

    from odnn_sep.cli import main
    t, T = _cooling(50)
    f = tmp_path / "ws.csv"
    f.write_text("t T\n" + "".join(f"{a} {b}\n" for a, b in zip(t, T, strict=True)))
    rep = tmp_path / "r.json"
    assert main(["mismatch", str(f), "--model", "cooling", "--report", str(rep)]) == 0
    assert "read as space-separated" in capsys.readouterr().err
    assert abs(json.loads(rep.read_text())["calibration"]["parameters"]["h"]["value"] - 0.01) < 1e-3
