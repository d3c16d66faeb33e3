import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_bench_mismatch_quick_runs():
    out = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_mismatch.py"), "--quick"],
                         capture_output=True, text=True, timeout=300, cwd=ROOT)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "naming_accuracy_ratio_ge_1.2" in out.stdout
