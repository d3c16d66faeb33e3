"""The later lines of a multi-line mark are searched near the angle of the first line found (the lines
of one mark share it), and at every angle when nothing is found there; a line not found constrains
nothing.

Before, every line was searched at every angle (+-45 degrees), however the first line lay.
"""

import odnn_sep.image.locate as locate
from odnn_sep.image.render import resolve_font
from odnn_sep.image.synth import add_text_watermark, photo_like
from odnn_sep.image.textlines import unwatermark_lines
from odnn_sep.image.textmode import NEAR_ANGLE, find

ANGLE = 14.0


def _turned_two_lines():
    y = photo_like((240, 360), random_state=5)
    for text, centre in (("Studio 2024", (180, 95)), ("John Doe", (190, 140))):
        y, _ = add_text_watermark(y, text, size=30, angle=ANGLE, center=centre, alpha=0.5)
    return y


def _spy(monkeypatch):
    """The (angle centre, angle range) of every search, in order."""
    calls, inner = [], locate.search

    def spying(img, text, fonts, **kw):
        calls.append((text, kw.get("angle_center", 0.0), kw.get("angle_range")))
        return inner(img, text, fonts, **kw)

    monkeypatch.setattr(locate, "search", spying)
    return calls


def test_later_line_searched_near_the_first_lines_angle_and_found(monkeypatch):
    calls = _spy(monkeypatch)
    r = unwatermark_lines(_turned_two_lines(), ["Studio 2024", "John Doe"], font="DejaVuSans-Bold")
    assert [ln["outcome"] for ln in r.report["lines"]] == ["removed", "removed"]
    first = [c for c in calls if c[0] == "Studio 2024"]
    second = [c for c in calls if c[0] == "John Doe"]
    assert first[0][1:] == (0.0, 45.0)        # the first line: every angle
    assert len(second) == 1                   # the later line: one search, near the first line's angle
    assert abs(second[0][1] - ANGLE) < 1.0 and second[0][2] == NEAR_ANGLE


def test_a_first_line_not_found_constrains_nothing(monkeypatch):
    calls = _spy(monkeypatch)
    r = unwatermark_lines(_turned_two_lines(), ["QWXZ", "John Doe"], font="DejaVuSans-Bold")
    assert [ln["outcome"] for ln in r.report["lines"]] == ["not found", "removed"]
    assert [c[1:] for c in calls if c[0] == "John Doe"][0] == (0.0, 45.0)


def test_nothing_near_the_given_angle_falls_back_to_every_angle():
    y = _turned_two_lines() / 255.0
    best, *_ = find(y, "John Doe", [resolve_font("DejaVuSans-Bold")], None, 45.0, 0, 0.19, near=-ANGLE)
    assert best is not None and abs(best.angle - ANGLE) < 1.5
