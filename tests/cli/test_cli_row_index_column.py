"""A CSV written by pandas (its row index first, unnamed) is read with the right time and values.

Before, the index was taken for the time and the time column for the values: a cooling record read
as temperatures "up to 300, looking like degF" and a nonsense verdict.
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
