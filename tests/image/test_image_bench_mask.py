"""The mask-mode benchmark recipe runs on tiny cases and its rows have the documented structure."""
import importlib.util
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]


def _recipe():
    spec = importlib.util.spec_from_file_location("bench_watermark_mask", ROOT / "recipes" / "bench_watermark_mask.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_bench_mask_rows_structure():
    pytest.importorskip("skimage", reason="the recipe's anchors and scores use scikit-image")
    from odnn_sep.image.synth import photo_like

    bench = _recipe()
    if not bench.fonts():
        pytest.skip("none of the population's fonts (matplotlib, mujoco) is installed")
    photos = [("synthetic", photo_like((110, 220), random_state=3))]
    rows = bench.run(photos, bench.DEV_SEED0, 1, 1, kinds=("stroke", "box"))
    assert [r["kind"] for r in rows] == ["stroke", "box", "clean"]
    for r in rows:
        assert r["outcome"] in ("removed", "still visible", "not found")
        assert r["exit"] == {"removed": 0, "still visible": 3, "not found": 1}[r["outcome"]]
        assert set(r["scores"]) == set(bench.METHODS)
        for s in r["scores"].values():
            assert set(s) == {"psnr", "psnr_box", "ssim", "ssim_box"}
            assert all(isinstance(v, float) for v in s.values())
        assert r["font"] in bench.fonts() and r["time_s"] >= 0
    wm, clean = rows[:2], rows[2]
    assert all(0.25 <= r["alpha"] <= 0.7 for r in wm)
    assert all(r["alpha_err"] is None or r["alpha_est"] is not None for r in wm)
    assert clean["alpha"] is None and clean["alpha_err"] is None
    assert clean["scores"][bench.INPUT]["psnr"] == 99.0            # the clean photo is its own input
    text = bench.summarise(rows)
    assert "**stroke** mask (1 cases)" in text and "**box** mask" in text and "False alarms:" in text
