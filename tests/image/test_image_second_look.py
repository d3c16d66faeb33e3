"""More looks when the first search finds nothing: the least alike font's coarse templates (no pinned
font), letter-spaced renderings, a finer coarse grid, the slanted faces, then the glyph-by-glyph look
over every look's placements; a later look's mark must reach a higher bar."""
import odnn_sep.image.layoutlook as ll
import odnn_sep.image.textmode as tm
from odnn_sep.image.locate import least_alike
from odnn_sep.image.render import SLANTED_FONT_NAMES, default_fonts, split_tracking


def test_least_alike_is_the_monospaced_font_for_a_long_text():
    fonts = default_fonts()
    assert least_alike("Preview", fonts).name == "DejaVuSansMono-Bold.ttf"
    assert least_alike("Preview", fonts[:1]) == fonts[0]


def _fake(monkeypatch, scores, moved=0.0):
    """best_match stand-in: the k-th look scores ``scores[k]`` (0 past the list); records each look's
    fonts and coarse options. The glyph-by-glyph look scores ``moved`` and records what it was given."""
    calls = []

    def best_match(y, text, fonts, region, angle_range, random_state, reduced=False, tried=None, **coarse):
        calls.append(coarse)
        calls[-1]["fonts"] = fonts
        tried.append(f"placement of look {len(calls)}")
        return ("place", None, scores[len(calls) - 1] if len(calls) <= len(scores) else 0.0, (0, 0), None)

    def layout_look(y, text, tried, random_state):
        calls.append({"layout_look": tried})
        return ("moved", moved) if moved else (None, 0.0)

    monkeypatch.setattr(tm, "best_match", best_match)
    monkeypatch.setattr(ll, "keep_better", lambda y, text, p, score, rs: (p, score))
    monkeypatch.setattr(ll, "layout_look", layout_look)
    monkeypatch.setattr(tm, "_as_match", lambda p, score, off: None)
    return calls


def _looks(calls):
    return [{k: v for k, v in c.items() if k != "fonts"} for c in calls]


def test_more_looks_only_when_the_first_finds_nothing(monkeypatch):
    fonts = default_fonts()
    calls = _fake(monkeypatch, [0.5])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.5 and _looks(calls) == [{}]
    calls = _fake(monkeypatch, [0.1, 0.9])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert calls[1]["coarse_font"].name == "DejaVuSansMono-Bold.ttf"
    calls = _fake(monkeypatch, [0.1, 0.1, 0.9])  # letter-spaced renderings of the first font
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert split_tracking(calls[2]["coarse_font"]) == (str(fonts[0]), tm.LOOK_TRACKING)
    calls = _fake(monkeypatch, [0.1, 0.1, 0.1, 0.9])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert _looks(calls)[3] == {"coarse_height": tm.FINE_LOOK_HEIGHT}
    calls = _fake(monkeypatch, [0.1, 0.1, 0.1, 0.1, 0.9])  # the slanted faces of the family
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.9
    assert calls[4]["fonts"] == default_fonts(SLANTED_FONT_NAMES) and len(calls[4]["fonts"]) == 2
    calls = _fake(monkeypatch, [0.1], moved=0.9)  # then the glyphs moved, over every look's placements
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[:3] == ("moved", None, 0.9)
    assert calls[5]["layout_look"] == [[f"placement of look {k}"] for k in range(1, 6)]
    calls = _fake(monkeypatch, [0.1, 0.9])  # a pinned font: only the finer grid, nothing moved
    assert tm.find(None, "Preview", fonts[:1], None, 45, 0, 0.19)[2] == 0.9
    assert _looks(calls) == [{}, {"coarse_height": tm.FINE_LOOK_HEIGHT}]
    calls = _fake(monkeypatch, [0.1, 0.1], moved=0.9)
    assert tm.find(None, "Preview", fonts[:1], None, 45, 0, 0.19)[2] == 0.1 and len(calls) == 2


def test_later_looks_need_the_higher_bar(monkeypatch):
    fonts = default_fonts()
    bar = tm.SECOND_LOOK_FACTOR * 0.19
    _fake(monkeypatch, [0.1, 0.99 * bar, 0.99 * bar, 0.99 * bar])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.1  # the first look's score is reported
    _fake(monkeypatch, [0.1, 0.0, bar])
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == bar
    _fake(monkeypatch, [0.1], moved=0.99 * tm.LAYOUT_LOOK_FACTOR * 0.19)
    assert tm.find(None, "Preview", fonts, None, 45, 0, 0.19)[2] == 0.1
