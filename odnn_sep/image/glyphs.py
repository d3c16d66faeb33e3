"""Which fonts can draw the watermark's text: a font without a glyph for a character draws a box.

A text in a script the fonts tried do not cover (Chinese, Arabic, ...) was rendered as empty boxes,
searched for seconds and reported "not found (best match score 0.047)", which reads as if the mark
were too faint. Fonts without a glyph for every visible character are now left out of the search,
and when none is left the error says which characters no font has.
"""
from __future__ import annotations

import functools
from pathlib import Path

from odnn_sep.errors import InputError


@functools.lru_cache(maxsize=64)
def _codepoints(path: str) -> frozenset | None:
    """The code points ``path`` maps to a glyph (None when the file cannot be read as a font)."""
    try:
        from fontTools.ttLib import TTFont

        with TTFont(path, fontNumber=0, lazy=True) as f:
            return frozenset(f.getBestCmap() or {})
    except Exception:  # noqa: BLE001 - an unreadable cmap says nothing: the font is kept
        return None


def missing(text: str, font) -> list[str]:
    """The visible characters of ``text`` that ``font`` (a path) has no glyph for, in order, once each.

    Examples
    --------
    >>> from odnn_sep.image.render import resolve_font
    >>> missing("© 2024 Foto", resolve_font("DejaVuSans-Bold"))
    []
    >>> missing("水印 ok", resolve_font("DejaVuSans-Bold"))
    ['水', '印']
    """
    cmap = _codepoints(str(Path(str(font).split("@")[0])))
    if cmap is None:
        return []
    out = []
    for ch in str(text):
        if not ch.isspace() and ord(ch) not in cmap and ch not in out:
            out.append(ch)
    return out


def fonts_for(text: str, fonts: list, *, given: bool) -> list:
    """The fonts of ``fonts`` that have a glyph for every visible character of ``text``.

    Parameters
    ----------
    text : str
        The watermark's text.
    fonts : list of Path
        The fonts to be tried (the one given with ``--font``, or the defaults).
    given : bool
        Whether the user named the font (the error then names it).

    Returns
    -------
    list of Path

    Raises
    ------
    InputError
        When no font is left, naming the characters (at most 5) and what to do.

    Examples
    --------
    >>> from odnn_sep.image.render import default_fonts
    >>> len(fonts_for("SAMPLE", default_fonts(), given=False)) == len(default_fonts())
    True
    >>> fonts_for("水印", default_fonts(), given=False)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: none of the fonts tried (DejaVuSans-Bold, ...) has a glyph for '水' (U+6C34), '印' (U+5370): ...
    """
    if not given and all(32 <= ord(c) < 127 for c in str(text)):
        # every default face draws Basic Latin (reading their five cmaps cost a quarter second a command)
        return list(fonts)
    keep = [f for f in fonts if not missing(text, f)]
    if keep:
        return keep
    chars = []
    for f in fonts:
        chars += [c for c in missing(text, f) if c not in chars]
    shown = ", ".join(f"{c!r} (U+{ord(c):04X})" for c in chars[:5]) + (", ..." if len(chars) > 5 else "")
    names = ", ".join(Path(str(f).split("@")[0]).stem for f in fonts[:3]) + (", ..." if len(fonts) > 3 else "")
    if given:
        raise InputError(f"font {names} has no glyph for {shown}: it would draw empty boxes; give --font with a "
                         f"font file that has the mark's characters")
    raise InputError(f"none of the fonts tried ({names}) has a glyph for {shown}: give --font with a font file "
                     f"that has the mark's characters (a font for its script)")
