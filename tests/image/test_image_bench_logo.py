"""The logo benchmark recipe runs in its quick form and prints its table."""
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


@pytest.mark.slow
def test_bench_logo_quick_runs():
    pytest.importorskip("skimage", reason="the recipe uses skimage.data photos and inpaint_biharmonic")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    p = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_logo.py"), "--quick"],
                       capture_output=True, text=True, timeout=900, env=env)
    assert p.returncode == 0, p.stderr
    assert "odnn-sep --reference" in p.stdout and "cv2.inpaint TELEA, true mask" in p.stdout
    assert "False alarms:" in p.stdout
