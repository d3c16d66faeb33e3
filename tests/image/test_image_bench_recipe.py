import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
DATA = ROOT.parent / "shared" / "data" / "photos_clean_skimage"


@pytest.mark.skipif(not DATA.exists(), reason=f"real photos not available at {DATA}")
def test_bench_watermark_quick_runs():
    p = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_watermark.py"), "--quick"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr
    assert "odnn-sep, font given" in p.stdout and "cv2.inpaint TELEA, true mask" in p.stdout
