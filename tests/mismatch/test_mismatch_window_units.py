"""A --start/--duration window that keeps a handful of samples says that the window is in the time
column's unit (a window in seconds on a record timed in ms)."""
import numpy as np

from odnn_sep.cli import main


def test_a_window_in_seconds_on_a_record_in_ms_names_the_unit(tmp_path, capsys):
    t = np.linspace(0, 20000, 400)                       # ms
    x = np.cos(0.002 * t) + 0.01 * np.random.default_rng(1).normal(size=t.size)
    f = tmp_path / "osc_ms.csv"
    f.write_text("t_ms,x\n" + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), x.tolist())))
    report = tmp_path / "r.json"
    rc = main(["mismatch", str(f), "--model", "oscillator", "--duration", "10", "--quiet", "--report", str(report)])
    err = capsys.readouterr().err.strip()
    # it was "too little data for the held-out split: 1 samples", with no word on the window
    assert rc != 0 and not report.exists() and len(err.splitlines()) == 1
    assert "keeps 1 of 400 samples" in err and "unit of the time column" in err
    assert main(["mismatch", str(f), "--model", "oscillator", "--duration", "10000", "--quiet"]) == 0
