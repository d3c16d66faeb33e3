import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_bench_mismatch_units_quick_runs():
    out = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_mismatch_units.py"), "--quick"],
                         capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "same verdict in every unit: yes" in out.stdout
