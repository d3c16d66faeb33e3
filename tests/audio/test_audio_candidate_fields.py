"""The report's candidate rows name their p-values for what they are.

A phase-lock row's p-value is the lock test's own; the bar it must pass depends on the family and on
which harmonics the comb already holds (Bonferroni over the lines tested, or none for a missing low
harmonic), so it is reported uncorrected as ``p_value``. Only the spectrum's rows, which are corrected
over every line tested, carry ``p_value_bonferroni``.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.audio import denoise


def test_phase_lock_rows_give_the_uncorrected_p_value_under_its_own_name():
    rng = np.random.default_rng(6)
    sr = 4000
    t = np.arange(40 * sr) / sr
    y = sum(a * np.cos(2 * np.pi * k * 50.0 * t + k) for k, a in ((1, 1.0), (2, 0.5), (3, 0.3), (5, 0.3)))
    r = denoise(y + 0.3 * rng.standard_normal(t.size), sr)
    locks = [c for c in r.candidates if c.get("look") == "phase lock"]
    assert locks, "no phase-lock rows in the report"
    for row in locks:
        assert "p_value_bonferroni" not in row, row
        assert 0.0 <= row["p_value"] <= 1.0
    by_k = {c["harmonic"]: c for c in locks}
    assert by_k[1]["p_value"] < 1e-6 and by_k[4]["p_value"] > by_k[5]["p_value"]
    spectrum_rows = [c for c in r.candidates if c.get("look") is None and c["harmonic"] is not None]
    assert spectrum_rows and all("p_value_bonferroni" in c for c in spectrum_rows)
