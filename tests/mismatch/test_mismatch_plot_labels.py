"""The mismatch figure says what it shows.

A record where nothing was added had an "after" curve labelled "+ " (no name) drawn over the
calibrated model, and before/after residuals that were the same fit twice; a long record fitted on
a subsample showed the fitted samples only, without a word.
"""
import numpy as np

from odnn_sep.mismatch import explain
from odnn_sep.mismatch.report import _plot_series
from odnn_sep.report.figures import pyplot


def _labels(res):
    plt = pyplot()
    added = list(res.effects) + [d["effect"] for d in res.disturbances]
    fig = _plot_series(plt, res, added, " (data units)")
    try:
        return fig.axes[0].get_title(), [[t.get_text() for t in a.get_legend().get_texts()] for a in fig.axes]
    finally:
        plt.close(fig)


def _cooling(n, seed=0):
    t = np.linspace(0, 600, n)
    return t, 20 + 70 * np.exp(-0.01 * t) + 0.1 * np.random.default_rng(seed).normal(size=n)


def test_nothing_added_draws_one_fit():
    res = explain("cooling", *_cooling(300))
    assert res.effects == [] and res.disturbances == []
    _, legends = _labels(res)
    assert legends[0] == ["data", "calibrated model"]
    assert legends[1][0] == f"calibrated model (rms {res.calibration.fit.rms:.3g})"
    assert not [s for s in legends[1] + legends[2] if s.startswith(("before", "after"))]


def test_long_record_title_says_a_subsample_was_fitted():
    res = explain("cooling", *_cooling(8000))
    assert res.subsample == {"step": 4, "record": 8000}
    title, _ = _labels(res)
    assert "fitted on one sample in 4, 2000 of 8000" in title


def test_record_fitted_whole_has_no_subsample():
    assert explain("cooling", *_cooling(500)).subsample is None
