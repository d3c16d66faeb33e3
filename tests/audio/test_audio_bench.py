"""The audio benchmark recipe runs in quick mode (no BENCHMARKS.md update)."""
from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_bench_audio_quick():
    bench = ROOT / "BENCHMARKS.md"
    before = bench.read_text() if bench.exists() else None
    p = subprocess.run([sys.executable, str(ROOT / "recipes" / "bench_audio.py"), "--quick"],
                       capture_output=True, text=True, timeout=300)
    assert p.returncode == 0, p.stderr[-2000:]
    assert "| seed | case | odnn-sep gain / damage (dB)" in p.stdout and "hum-free recording" in p.stdout
    assert "odnn-sep" in p.stdout and "iirnotch" in p.stdout
    after = bench.read_text() if bench.exists() else None
    assert before == after
