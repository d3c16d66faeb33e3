"""The probe's generator: null twins share every draw with their effect record but the effect."""
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "recipes"))
import bench_mismatch_probe as bp  # noqa: E402


def test_null_twins_differ_from_the_effect_record_by_the_effect_only():
    for preset in bp.PRESETS:
        for kind in bp.KINDS:
            rng = np.random.default_rng([3, bp.PRESETS.index(preset), bp.KINDS.index(kind), 7])
            t, null, eff, effect, unit, extra, f_sys, sigma = bp.system(preset, rng, True)
            (y0, y1), info = bp.disturb(kind, rng, t, (null, eff), f_sys, sigma)
            assert np.all(np.diff(t) > 0) and len(t) >= 30 and np.all(np.isfinite(y0 + y1))
            assert effect in bp.EFFECTS[preset]
            if kind not in ("adc", "clip"):
                assert np.allclose(y1 - y0, eff - null), (preset, kind)
            assert np.std(y0 - null) > 0.5 * sigma, (preset, kind)   # the disturbance is there


def test_pickups_sit_near_but_not_on_the_system_frequency():
    for seed in range(5):
        rng = np.random.default_rng(seed)
        t = np.linspace(0, 20, 2000)
        _, f = bp._pickup(rng, t, 1.0, True, 1.0)
        assert 0.08 <= abs(f - 1.0) <= 0.3
        _, f = bp._pickup(rng, t, 1.0, False, 1.0)
        assert any(0.05 <= abs(f / k - 1) <= 0.2 for k in (2, 3)), f
