"""The README's "Python API" section runs as written (every ```python block, in order)."""
import re
from pathlib import Path

import numpy as np

README = Path(__file__).resolve().parents[2] / "README.md"


def _api_blocks() -> list[str]:
    text = README.read_text(encoding="utf-8")
    section = text.split("## Python API", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"```python\n(.*?)```", section, flags=re.S)


def test_readme_python_api_runs_and_the_band_stop_class_recovers_theta(capsys):
    blocks = _api_blocks()
    assert len(blocks) >= 2
    ns: dict = {}
    for code in blocks:
        exec(compile(code, str(README), "exec"), ns)   # noqa: S102 - our own README
    out = capsys.readouterr().out
    assert "point" in out
    np.testing.assert_allclose(ns["r"].theta, [0.8, 0.0], atol=1e-9)
    assert ns["r"].disturbance_class == "no power in [4, 6]"
