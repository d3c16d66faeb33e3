import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_bench_mismatch_hum_quick_runs():
    # one short case per kind (about 1-2 minutes): the table is printed, nothing is written
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    out = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_mismatch_hum.py"), "--quick",
                          "--kinds", "wander,null"], capture_output=True, text=True, timeout=600, cwd=ROOT, env=env)
    assert out.returncode == 0, out.stderr[-2000:]
    assert "| wander | 1 |" in out.stdout and "| null | 1 |" in out.stdout
