"""recipes/table1.py --quick runs end to end on a subset and prints the table without writing."""
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_table1_quick_runs_and_prints_table():
    bench = ROOT / "BENCHMARKS.md"
    before = bench.read_text() if bench.exists() else None
    proc = subprocess.run(
        [sys.executable, str(ROOT / "recipes" / "table1.py"), "--quick", "--no-write",
         "--datasets", "figure2,implicit_convex,biology"],
        capture_output=True, text=True, timeout=240, cwd=ROOT,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    out = proc.stdout
    assert ("| dataset | class | ODNN exact | bound (any unbiased estimator) | ODNN network | regular DNN "
            "| PINN penalty | OLS | SINDy |") in out
    assert "| biology | 0.42 |" in out  # the noise companion table: target, then ODNN exact / bound per SNR
    for row in ("| figure2 | Even |", "| implicit_convex | Convex |", "| biology | Periodic |"):
        assert row in out
    assert "cannot hold: set-identified" in out
    assert "SNR 30 dB relative to the physics signal" in out
    assert (bench.read_text() if bench.exists() else None) == before


def test_table1_rejects_unknown_dataset():
    proc = subprocess.run([sys.executable, str(ROOT / "recipes" / "table1.py"), "--quick", "--datasets", "nope"],
                          capture_output=True, text=True, timeout=60, cwd=ROOT)
    assert proc.returncode == 2
    assert "unknown dataset(s) ['nope']" in proc.stderr
