"""Without a pinned font: a second search with the least alike font's coarse templates, at a higher bar."""
import odnn_sep.image.textmode as tm
from odnn_sep.image.locate import least_alike
from odnn_sep.image.render import default_fonts


def test_least_alike_is_the_monospaced_font_for_a_long_text():
    fonts = default_fonts()
    assert least_alike("Preview", fonts).name == "DejaVuSansMono-Bold.ttf"
    assert least_alike("Preview", fonts[:1]) == fonts[0]


def _fake(monkeypatch, first, second):
    calls = []

    def best_match(y, text, fonts, region, angle_range, random_state, reduced=False, coarse_font=None):
        calls.append(coarse_font)
        return ("place", None, first if coarse_font is None else second, (0, 0), None)

    monkeypatch.setattr(tm, "best_match", best_match)
    return calls


def test_second_look_only_when_the_first_finds_nothing(monkeypatch):
    fonts = default_fonts()
    calls = _fake(monkeypatch, 0.5, 0.9)
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.5 and calls == [None]
    calls = _fake(monkeypatch, 0.1, 0.9)
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9 and calls[1].name == "DejaVuSansMono-Bold.ttf"
    calls = _fake(monkeypatch, 0.1, 0.9)
    assert tm.find(None, "Preview", fonts[:1], None, 45, 0, 0.19)[2] == 0.1 and calls == [None]  # font pinned


def test_second_look_needs_the_higher_bar(monkeypatch):
    fonts = default_fonts()
    bar = tm.SECOND_LOOK_FACTOR * 0.19
    _fake(monkeypatch, 0.1, 0.99 * bar)
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.1
    _fake(monkeypatch, 0.1, bar)
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == bar
