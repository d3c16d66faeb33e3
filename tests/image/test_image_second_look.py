"""More looks when the first search finds nothing: the least alike font's coarse templates (no pinned
font), letter-spaced renderings, then a finer coarse grid; a later look's mark must reach a higher bar."""
import odnn_sep.image.textmode as tm
from odnn_sep.image.locate import least_alike
from odnn_sep.image.render import default_fonts, split_tracking


def test_least_alike_is_the_monospaced_font_for_a_long_text():
    fonts = default_fonts()
    assert least_alike("Preview", fonts).name == "DejaVuSansMono-Bold.ttf"
    assert least_alike("Preview", fonts[:1]) == fonts[0]


def _fake(monkeypatch, scores):
    """best_match stand-in: the k-th look scores ``scores[k]``; records each look's coarse options."""
    calls = []

    def best_match(y, text, fonts, region, angle_range, random_state, reduced=False, **coarse):
        calls.append(coarse)
        return ("place", None, scores[len(calls) - 1], (0, 0), None)

    monkeypatch.setattr(tm, "best_match", best_match)
    return calls


def test_more_looks_only_when_the_first_finds_nothing(monkeypatch):
    fonts = default_fonts()
    calls = _fake(monkeypatch, [0.5])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.5 and calls == [{}]
    calls = _fake(monkeypatch, [0.1, 0.9])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert calls[1]["coarse_font"].name == "DejaVuSansMono-Bold.ttf"
    calls = _fake(monkeypatch, [0.1, 0.1, 0.9])  # letter-spaced renderings of the first font
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert split_tracking(calls[2]["coarse_font"]) == (str(fonts[0]), tm.LOOK_TRACKING)
    calls = _fake(monkeypatch, [0.1, 0.1, 0.1, 0.9])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert calls[3] == {"coarse_height": tm.FINE_LOOK_HEIGHT}
    calls = _fake(monkeypatch, [0.1, 0.9])  # a pinned font: only the finer grid
    assert tm.find(None, "Preview", fonts[:1], None, 45, 0, 0.19)[2] == 0.9
    assert calls == [{}, {"coarse_height": tm.FINE_LOOK_HEIGHT}]


def test_later_looks_need_the_higher_bar(monkeypatch):
    fonts = default_fonts()
    bar = tm.SECOND_LOOK_FACTOR * 0.19
    _fake(monkeypatch, [0.1, 0.99 * bar, 0.99 * bar, 0.99 * bar])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.1  # the first look's score is reported
    _fake(monkeypatch, [0.1, 0.0, bar])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == bar
