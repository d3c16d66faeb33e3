"""Find TrueType fonts: the default candidate set and ``--font NAME|PATH`` resolution."""
from __future__ import annotations

import functools
import os
from pathlib import Path

from odnn_sep.errors import InputError

# Common watermark faces, tried in this order when the user does not pin one. Only files that exist
# are used; matplotlib's DejaVu copies are the guaranteed fallback (they ship with the package).
DEFAULT_FONT_FILES = (
    "DejaVuSans-Bold.ttf", "DejaVuSans.ttf", "DejaVuSerif-Bold.ttf", "DejaVuSerif.ttf",
    "DejaVuSansMono.ttf", "LiberationSans-Bold.ttf", "LiberationSans-Regular.ttf",
    "LiberationSerif-Regular.ttf", "Arial.ttf", "arial.ttf", "arialbd.ttf", "Arial Bold.ttf",
    "FreeSans.ttf", "FreeSansBold.ttf", "Roboto-Regular.ttf", "Roboto-Bold.ttf",
)

SYSTEM_FONT_DIRS = ("/usr/share/fonts", "/usr/local/share/fonts", "~/.fonts", "~/.local/share/fonts",
                    "/Library/Fonts", "/System/Library/Fonts", "C:/Windows/Fonts")


def _matplotlib_font_dir() -> Path:
    import matplotlib

    return Path(matplotlib.get_data_path()) / "fonts" / "ttf"


@functools.lru_cache(maxsize=1)
def _font_index() -> dict[str, Path]:
    """Map lower-case file name -> path over system dirs, then matplotlib's fonts (system copies win)."""
    index: dict[str, Path] = {}
    dirs = [Path(os.path.expanduser(d)) for d in SYSTEM_FONT_DIRS] + [_matplotlib_font_dir()]
    for d in dirs:
        if not d.is_dir():
            continue
        for p in sorted(d.rglob("*")):
            if p.suffix.lower() in (".ttf", ".otf") and p.name.lower() not in index:
                index[p.name.lower()] = p
    return index


def default_fonts(max_fonts: int = 6) -> list[Path]:
    """Candidate fonts tried when none is given (at most ``max_fonts``, in preference order)."""
    index = _font_index()
    out: list[Path] = []
    seen_stems: set[str] = set()
    for name in DEFAULT_FONT_FILES:
        p = index.get(name.lower())
        if p is not None and p.stem.lower() not in seen_stems:
            out.append(p)
            seen_stems.add(p.stem.lower())
        if len(out) >= max_fonts:
            break
    if not out:  # pragma: no cover - matplotlib always ships DejaVu
        raise InputError("no TrueType font found on this system; pass --font PATH to a .ttf file")
    return out


def resolve_font(font) -> Path:
    """Turn a path, a file name (``DejaVuSerif.ttf``) or a family name (``DejaVu Sans``) into a font path.

    Examples
    --------
    >>> resolve_font("DejaVu Sans").name
    'DejaVuSans.ttf'
    """
    s = str(font)
    p = Path(os.path.expanduser(s))
    if p.is_file():
        return p
    index = _font_index()
    key = s.lower()
    for cand in (key, key + ".ttf", key + ".otf", key.replace(" ", "") + ".ttf",
                 key.replace(" ", "-") + ".ttf"):
        if cand in index:
            return index[cand]
    try:
        from matplotlib import font_manager

        found = font_manager.findfont(font_manager.FontProperties(family=s), fallback_to_default=False)
        return Path(found)
    except (ValueError, RuntimeError):
        pass
    raise InputError(
        f"font {s!r} not found (not a file, and no installed font has that file or family name); "
        f"pass a path to a .ttf/.otf file, or a name such as 'DejaVu Sans'"
    )
