"""Find a rendered text in an image: position, size (px), rotation and repeats.

The search is coarse-to-fine on band-pass correlation (``features.match_bandpass``; the coarse grid
transforms each level once, ``spectra``): every (size, angle) on a log/linear grid at a pyramid
level where the glyphs are about 10 px tall, the best places of each, then one step of a finer
(size, angle, position) grid at a level where they are about 24 px tall around many of them
(without a pinned font: at the best of them for the two fonts that look best there, elsewhere for
the coarse grid's font), and a last, finer step for the best of those.
The caller screens the hypotheses with the blend fit, and the final sub-pixel fit minimises the
blend model's residual (see ``register``).
"""
from __future__ import annotations

import dataclasses
import functools
import logging
import os
from pathlib import Path

import numpy as np

from odnn_sep.image.features import (
    BASE_MAX,
    PAD,
    Pyramid,
    bp_template,
    edge_template,
    match_bandpass,
    match_edges,
    peaks,
)
from odnn_sep.image.render import render_text

log = logging.getLogger(__name__)

REF_SIZE = 100.0
COARSE_H = 10.0    # glyph height (px) at the coarse level
COARSE_W = 80.0     # px: the coarse template is at most this wide (long texts go one level coarser)
MIN_COARSE_H = 8.0  # px: glyphs smaller than this at the coarse level only match noise
# The largest text searched is this many times the image's diagonal wide (a mark cut by the edges).
MAX_WIDTH_DIAGONALS = 1.05
FINE_H = 24.0      # glyph height (px) at the refinement level
# refinement grids at that level: (size step, angle step in deg, half-width in steps, wide position
# window: the placement is only known to a coarse pixel)
QUICK = (0.05, 2.5, 0, True)    # position only
MEDIUM = (0.05, 1.8, 1, True)   # covers half a coarse grid step in size and angle
# the same, one coordinate at a time (angle, then size): 5 templates instead of 9
MEDIUM_ANGLE = (0.0, 1.8, 1, True)
MEDIUM_SIZE = (0.05, 0.0, 1, True)
FINE = (0.02, 0.7, 1, False)
CHUNK_W = 96.0   # px at the coarse level: widest template (longer texts: their middle part)
WIDE_RAD = 16    # px at the refinement level: widest position window of the wide grids
FONT_PLACES = 3  # without a pinned font, the best places where every font is tried on the finer grids


@dataclasses.dataclass
class Match:
    """One placement hypothesis of the search: font, em size (px), angle (degrees, counter-clockwise),
    ink-box centre (x, y) and the band-pass match score.

    Examples
    --------
    >>> from pathlib import Path
    >>> from odnn_sep.image.locate import Match
    >>> m = Match(Path("DejaVuSans-Bold.ttf"), 20.0, 0.0, (32.0, 24.0), 0.9)
    >>> m.size, m.center
    (20.0, (32.0, 24.0))
    """

    font: Path
    size: float          # em size in px at full resolution
    angle: float         # degrees, counter-clockwise as displayed
    center: tuple[float, float]  # (x, y) of the ink-box centre, full-resolution px
    score: float         # band-pass match score at the refinement level


def _ink(text: str, font) -> tuple[float, float]:
    """(width, height) of the ink box of ``text`` at ``REF_SIZE`` px."""
    return _ink_cached(text, str(font))


@functools.lru_cache(maxsize=256)
def _ink_cached(text: str, font: str) -> tuple[float, float]:
    # cached: the finer grids ask for it once per font at every place (about a thousand times a search)
    m = render_text(text, font, REF_SIZE)
    return m.shape[1] - 4.0, m.shape[0] - 4.0


def _centre(xx, yy, t, f):
    """Full-resolution centre of a template whose top-left corner is at (xx, yy) of a padded map."""
    return (xx - PAD + (t.shape[1] - 1) / 2) / f, (yy - PAD + (t.shape[0] - 1) / 2) / f


def _subpixel(r, yy, xx) -> tuple[float, float]:
    """Parabolic interpolation of a correlation peak (a level pixel is several image pixels: the
    blend-fit screening that follows needs the placement to about a pixel)."""
    def off(a, b, c):
        den = a - 2.0 * b + c
        return float(np.clip(0.5 * (a - c) / den, -0.5, 0.5)) if den < 0 else 0.0

    dy = off(r[yy - 1, xx], r[yy, xx], r[yy + 1, xx]) if 0 < yy < r.shape[0] - 1 else 0.0
    dx = off(r[yy, xx - 1], r[yy, xx], r[yy, xx + 1]) if 0 < xx < r.shape[1] - 1 else 0.0
    return dy, dx


def _corner(cx, cy, t, f):
    """Inverse of ``_centre`` (rounded)."""
    return int(round(cx * f - (t.shape[1] - 1) / 2)) + PAD, int(round(cy * f - (t.shape[0] - 1) / 2)) + PAD


def search(img: np.ndarray, text: str, fonts: list[Path], *, angle_range: float = 45.0,
           min_height_px: float = 8.0, max_hypotheses: int = 8, per_size_bin: int = 1,
           peaks_per_map: int = 2, coarse_factor: int = 4, coarse_font: Path | None = None,
           coarse_height: float = COARSE_H, angle_center: float = 0.0) -> list[Match]:
    """Coarse-to-fine search for ``text`` (any of ``fonts``); returns distinct hypotheses, best first.

    Why long (12 parameters): the image, text and fonts, then keyword options of the grids.

    ``coarse_factor`` x ``max_hypotheses`` coarse places get one step of the finer grid; the best
    ``max_hypotheses`` (per font kept, at most two) get the last step. The coarse grid uses the
    templates of ``coarse_font`` (default: the first font), with glyphs ``coarse_height`` px tall
    (a finer grid costs more and tells faint marks from texture better).

    Parameters
    ----------
    img : np.ndarray
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    fonts : list of Path
        Fonts to try.
    angle_range : float, default 45.0
        Largest rotation searched, degrees either way.
    min_height_px : float, default 8.0
        Smallest glyph height searched.
    max_hypotheses : int, default 8
        Hypotheses returned at most.
    per_size_bin, peaks_per_map, coarse_factor : int
        Options of the coarse grid (places kept per size, peaks per score map, coarse places per
        hypothesis).
    coarse_font : Path, optional
        Font of the coarse grid's templates (default the first font).
    coarse_height : float
        Glyph height of the coarse grid, px.
    angle_center : float, default 0.0
        The coarse grid's angles are ``angle_center`` +- ``angle_range``.

    Returns
    -------
    list of Match
        Distinct hypotheses, best first (empty when no place fits).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.locate import search
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> y, _ = add_text_watermark(np.full((64, 96, 3), 90, np.uint8), "Hi", size=20, center=(40, 30), alpha=0.5)
    >>> best = search(y / 255.0, "Hi", [resolve_font("DejaVuSans-Bold")])[0]
    >>> round(best.size), round(best.angle), [round(c) for c in best.center]
    (20, 0, [40, 29])
    """
    pyr = Pyramid(img)
    f0 = str(coarse_font or fonts[0])
    w100 = _ink(text, f0)[0]
    cands = _coarse(pyr, img.shape[:2], text, f0, (angle_center, angle_range), min_height_px, peaks_per_map,
                    coarse_height)
    if not cands:
        return []
    # Many more coarse places than are finally kept: at the coarse level (glyphs ~10 px) a faint
    # mark on a textured photo scores below dozens of chance matches (development photos: coarse
    # rank up to ~40 of the distinct places), while one step of the finer grid ranks it first.
    top = _select(sorted(cands, key=lambda c: -c[0]), w100, coarse_factor * max_hypotheses, per_size_bin)
    return _finer(pyr, text, fonts, f0, top, w100, max_hypotheses)


def _coarse(pyr, shape, text, f0, angles_around, min_height_px, peaks_per_map, coarse_height) -> list[tuple]:
    """Coarse grid of ``search``: (score, size, angle, cx, cy) of the best places of every (size, angle).

    ``angles_around``: (centre, range) of the angles, degrees.
    Why long (8 parameters): ``search``'s options of the coarse grid, passed on."""
    angle_center, angle_range = angles_around
    H, W = shape
    w100, h100 = _ink(text, f0)
    h100 = max(h100, 1.0)
    full_w100 = w100
    s_min = _smallest_size(h100, min_height_px, pyr.base)
    s_max = max(MAX_WIDTH_DIAGONALS * np.hypot(H, W) / max(w100, 1) * REF_SIZE, s_min * 1.01)
    # A long text is matched on a coarser level (template at most COARSE_W px wide): it has letters
    # enough to be found there, and the grid below grows with the square of the template's width;
    # never below MIN_COARSE_H, or the letters blur into the photo's texture.
    coarse_h = max(MIN_COARSE_H, min(coarse_height, COARSE_W * coarse_height / COARSE_H * h100 / max(w100, 1.0)))
    # Longer still: only its middle CHUNK_W px are matched, and the whole text's centre follows
    text, off100 = coarse_chunk(text, f0, CHUNK_W * h100 / coarse_h)
    w100 = _ink(text, f0)[0] if off100 is not None else full_w100
    # grid steps keep the template's ends within ~1.5 px at the coarse level
    w_lvl = coarse_h * w100 / h100
    da = float(np.clip(np.rad2deg(2 * 1.5 / (w_lvl / 2)), 1.5, 5.0))
    ratio = float(np.clip(1 + 2 * 1.5 / (w_lvl / 2), 1.04, 1.1))
    sizes = np.exp(np.arange(np.log(s_min), np.log(s_max) + 1e-9, np.log(ratio)))
    n_a = int(np.ceil(angle_range / da))
    angles = np.linspace(-angle_range, angle_range, 2 * n_a + 1) if n_a else np.zeros(1)
    if angle_center:  # (only then: the angles of a level search stay bit for bit the same)
        angles = angles + float(angle_center)
    # levels first (their spectra are computed once each), then the sizes on a few threads
    # (OpenCV's transforms release the GIL and run single-threaded at these sizes).
    # Every colour channel counts at the coarse level too: a coloured mark can differ from the photo
    # in hue far more than in brightness (the channel mean lost such marks on development photos).
    maps = {s: pyr.spectra(coarse_h / (h100 * s / REF_SIZE)) for s in sizes}

    def one_size(s):
        S, f = maps[s]
        found = []
        for a in angles:
            T, band = bp_template(text, f0, round(s * f, 2), float(a))
            r = S.match(T, band)
            if r is None:
                continue
            for v, yy, xx in peaks(r, peaks_per_map, max(2, min(T.shape) // 2), 0.0):
                cx, cy = _centre(xx, yy, T, f)
                if off100 is not None:  # the chunk's centre -> the whole text's
                    dx, dy = _turn(off100, a, s / REF_SIZE)
                    cx, cy = cx - dx, cy - dy
                found.append((v, s, float(a), cx, cy))
        return found

    return [c for found in _map(one_size, sizes) for c in found]  # (score, size, angle, cx, cy)


def _smallest_size(h100: float, min_height_px: float, base: float) -> float:
    """Smallest font size (px) the coarse grid tries, for ink ``h100`` px tall at ``REF_SIZE``.

    Glyph height >= ``min_height_px``; the pyramid starts at <= 768 px (scale ``base``), where the
    text must be at least ``MIN_COARSE_H`` px tall (smaller only matches noise)."""
    return max(4.0, min_height_px / h100 * REF_SIZE * 1.4, MIN_COARSE_H / h100 * REF_SIZE / base)


def smallest_text(text: str, font, shape, *, min_height_px: float = 8.0) -> tuple[float, float, bool]:
    """(width, height) in px of ``text`` at the smallest size the search tries in an image of
    ``shape``, and whether that is too wide for the image.

    The search tries sizes from the smallest it can tell from noise up to a text
    ``MAX_WIDTH_DIAGONALS`` times the image's diagonal wide; when even the smallest is wider, the
    text cannot be in the image (a "not found" with a score of 0 would not say why).

    Parameters
    ----------
    text : str
        The mark's text.
    font : str or Path
        Font of the coarse grid.
    shape : tuple
        (H, W, ...) of the image searched.
    min_height_px : float, default 8.0
        As in ``search``.

    Returns
    -------
    tuple
        (width, height, too wide).

    Examples
    --------
    >>> from odnn_sep.image.locate import smallest_text
    >>> from odnn_sep.image.render import resolve_font
    >>> f = resolve_font("DejaVuSans-Bold")
    >>> smallest_text("Hi", f, (64, 96))[2], smallest_text("A LONG COPYRIGHT NOTICE", f, (40, 60))[2]
    (False, True)
    """
    H, W = shape[:2]
    w100, h100 = _ink(text, font)
    h100 = max(h100, 1.0)
    s = _smallest_size(h100, min_height_px, min(1.0, BASE_MAX / max(H, W)))
    width, height = w100 * s / REF_SIZE, h100 * s / REF_SIZE
    return width, height, bool(width > MAX_WIDTH_DIAGONALS * np.hypot(H, W))


def _turn(off, angle, scale) -> tuple[float, float]:
    """Offset ``off`` (x, y) of an upright rendering, in the image once the rendering is rotated by
    ``angle`` degrees (counter-clockwise as displayed, y down) and scaled by ``scale``."""
    t = np.deg2rad(angle)
    return (scale * (off[0] * np.cos(t) + off[1] * np.sin(t)), scale * (-off[0] * np.sin(t) + off[1] * np.cos(t)))


def coarse_chunk(text: str, font, max_w100: float) -> tuple[str, tuple[float, float] | None]:
    """(the middle part of ``text`` at most ``max_w100`` px wide at ``REF_SIZE``, its centre's offset
    from the whole text's ink-box centre there, upright); ``(text, None)`` when the whole fits.

    A long text has letters enough to be found by a part of it; the coarse grid grows with the
    square of the template's width (angle and size steps both shrink as it widens).

    Parameters
    ----------
    text : str
        The mark's text.
    font : str or Path
        Font file or name.
    max_w100 : float
        Widest part (px at ``REF_SIZE``).

    Returns
    -------
    chunk : str
        The part matched.
    offset : tuple of float or None
        (dx, dy) px at ``REF_SIZE`` from the whole text's centre to the chunk's; None for the whole.

    Examples
    --------
    >>> from odnn_sep.image.locate import coarse_chunk
    >>> coarse_chunk("SAMPLE", "DejaVuSans-Bold", 1000.0)
    ('SAMPLE', None)
    >>> chunk, off = coarse_chunk("acquisition and representation", "DejaVuSans-Bold", 900.0)
    >>> chunk, abs(off[0]) < 60, abs(off[1]) < 10
    ('tion and repres', True, True)
    """
    import cv2

    w100 = _ink(text, font)[0]
    if w100 <= max_w100:
        return text, None
    n = max(4, int(len(text) * max_w100 / w100))
    while n > 4:
        i = (len(text) - n) // 2
        chunk = text[i:i + n].strip()
        if chunk and _ink(chunk, font)[0] <= max_w100:
            break
        n -= 1
    full = render_text(text, font, REF_SIZE).astype(np.float32)
    part = render_text(chunk, font, REF_SIZE).astype(np.float32)
    # where the chunk sits in the whole rendering (kerning and ink boxes make arithmetic unreliable)
    r = cv2.matchTemplate(full, part, cv2.TM_CCORR_NORMED)
    yy, xx = divmod(int(np.argmax(r)), r.shape[1])
    off = (xx + (part.shape[1] - 1) / 2 - (full.shape[1] - 1) / 2, yy + (part.shape[0] - 1) / 2 - (full.shape[0] - 1) / 2)
    return chunk, (float(off[0]), float(off[1]))


def _finer(pyr, text, fonts, f0, top, w100, max_hypotheses) -> list[Match]:
    """The finer grids of ``search`` for the coarse places ``top`` (found with the font ``f0``, whose
    text is ``w100`` px wide at ``REF_SIZE``); distinct hypotheses, best first.

    Why long (7 parameters): ``search``'s pyramid, text, fonts and coarse places, passed on."""
    def one_hypothesis(ic):
        i, (_, s0, a0, cx0, cy0) = ic
        # several fonts: a quick look (position only) ranks them and the best two go on (the blend
        # fit that screens the hypotheses afterwards tells similar fonts apart far better); the
        # quick look and the second font only at the best-scoring coarse places (the most places
        # are chance matches; the others go on with the coarse grid's own font, and the best places
        # get every font on the finer grids below anyway)
        picks: list[tuple] = [(Path(f0) if len(fonts) > 1 else fonts[0], s0)]
        if len(fonts) > 1 and i < max_hypotheses:
            quick = []
            for fo in fonts:
                sf = s0 * w100 / _ink(text, fo)[0]  # match the coarse text width with this font
                m = _refine(pyr, text, str(fo), sf, a0, cx0, cy0, stages=(QUICK,))
                if m is not None:
                    quick.append((m.score, fo, sf, m))
            picks = [(fo, sf, m) for _, fo, sf, m in sorted(quick, key=lambda q: -q[0])[:2]]
        # the quick look's template is the medium grid's centre one, in the same window: not matched twice
        return [_refine(pyr, text, str(pick[0]), pick[1], a0, cx0, cy0, stages=(MEDIUM_ANGLE, MEDIUM_SIZE),
                        known=pick[2] if len(pick) > 2 else None) for pick in picks]

    medium = sorted((m for ms in _map(one_hypothesis, list(enumerate(top))) for m in ms if m is not None),
                    key=lambda m: -m.score)
    keep = _distinct(medium, max_hypotheses * min(2, len(fonts)))
    out = _distinct([m for m in _map(lambda m: _refine(pyr, text, str(m.font), m.size, m.angle, *m.center,
                                                        stages=(FINE,)), keep) if m is not None], len(keep))
    out.sort(key=lambda m: -m.score)
    if len(fonts) > 1:
        # The quick look ranks fonts by one template each, which often prefers a similar font to the
        # right one; the few best places get every other font on the finer grids too.
        extra = [(m, fo) for m in _places(out, FONT_PLACES) for fo in fonts
                 if not any(o.font == fo and same_place(o, m) for o in out)]
        more = _map(lambda t: _refine(pyr, text, str(t[1]), t[0].size * _ink(text, t[0].font)[0] / _ink(text, t[1])[0],
                                      t[0].angle, *t[0].center), extra)
        # as many as before: the screening that follows costs a blend fit per hypothesis
        out = sorted(out + [m for m in more if m is not None], key=lambda m: -m.score)[:len(keep)]
    return out


def least_alike(text: str, fonts: list[Path]) -> Path:
    """The font whose rendering of ``text`` correlates least with the first font's (both band-passed
    and stretched to the same box): the coarse grid's templates of the first font match it worst.

    Parameters
    ----------
    text : str
        The mark's text.
    fonts : list of Path
        Candidate fonts, the first the reference.

    Returns
    -------
    Path
        One of ``fonts[1:]`` (``fonts[0]`` when it is the only one).

    Examples
    --------
    >>> from odnn_sep.image.locate import least_alike
    >>> from odnn_sep.image.render import resolve_font
    >>> fonts = [resolve_font(n) for n in ("DejaVuSans-Bold", "DejaVuSans", "DejaVuSansMono-Bold")]
    >>> least_alike("Hi", fonts).name, least_alike("Hi", fonts[:1]).name
    ('DejaVuSansMono-Bold.ttf', 'DejaVuSans-Bold.ttf')
    """
    import cv2

    def look(font):
        m = render_text(text, str(font), 24.0).astype(np.float32)
        return m - cv2.GaussianBlur(m, (0, 0), 2.0)

    ref = look(fonts[0])
    corr = []
    for fo in fonts[1:]:
        t = cv2.resize(look(fo), (ref.shape[1], ref.shape[0]), interpolation=cv2.INTER_AREA)
        corr.append(float(np.sum(ref * t) / max(np.sqrt(np.sum(ref * ref) * np.sum(t * t)), 1e-12)))
    return fonts[1 + int(np.argmin(corr))] if corr else fonts[0]


def same_place(a: Match, b: Match) -> bool:
    """Whether two matches are the same place: centres within half the larger size, angles within 5 degrees.

    Parameters
    ----------
    a, b : Match
        The two placements.

    Returns
    -------
    bool

    Examples
    --------
    >>> from pathlib import Path
    >>> from odnn_sep.image.locate import Match, same_place
    >>> a = Match(Path("f.ttf"), 20.0, 0.0, (32.0, 24.0), 0.9)
    >>> same_place(a, Match(Path("g.ttf"), 20.0, 2.0, (35.0, 24.0), 0.5))
    True
    >>> same_place(a, Match(Path("f.ttf"), 20.0, 0.0, (52.0, 24.0), 0.7))
    False
    """
    return bool(np.hypot(a.center[0] - b.center[0], a.center[1] - b.center[1]) < 0.5 * max(a.size, b.size)
                and abs(a.angle - b.angle) < 5.0)


def _places(matches, n) -> list[Match]:
    """The first match at each of the first ``n`` distinct places."""
    out: list[Match] = []
    for m in matches:
        if len(out) >= n:
            break
        if not any(same_place(m, o) for o in out):
            out.append(m)
    return out


def _distinct(matches, n) -> list[Match]:
    """The first ``n`` of ``matches`` that are not the same placement as an earlier one."""
    out: list[Match] = []
    for m in matches:
        if len(out) >= n:
            break
        if not any(m.font == o.font and abs(np.log(m.size / o.size)) < 0.04 and abs(m.angle - o.angle) < 2.0
                   and np.hypot(m.center[0] - o.center[0], m.center[1] - o.center[1]) < 3.0 for o in out):
            out.append(m)
    return out


def _map(fn, items) -> list:
    """``[fn(x) for x in items]``, on a few threads where there are cores for them."""
    workers = max(1, min(4, os.cpu_count() or 1))
    if workers == 1:
        return [fn(x) for x in items]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(workers) as ex:
        return list(ex.map(fn, items))


def _select(cands, w100, max_hypotheses, per_size_bin):
    """Distinct hypotheses: the best ``per_size_bin`` of every half-octave of size first (maxima of
    small templates are inflated by the many positions they are tried at, so a purely global ranking
    starves the large sizes), then the next best overall."""
    top: list[tuple] = []

    def distinct(c):
        return all(abs(np.log(c[1] / t[1])) > 0.15 or abs(c[2] - t[2]) > 7
                   or np.hypot(c[3] - t[3], c[4] - t[4]) > 0.3 * w100 * c[1] / REF_SIZE for t in top)

    per_bin: dict[int, int] = {}
    for c in cands:
        b = int(np.floor(2 * np.log2(c[1])))
        # within a size bin, slots go to different places: a textured spot matches many angles
        if per_bin.get(b, 0) < per_size_bin and distinct(c) and all(
                int(np.floor(2 * np.log2(t[1]))) != b
                or np.hypot(c[3] - t[3], c[4] - t[4]) > 0.5 * w100 * c[1] / REF_SIZE for t in top):
            per_bin[b] = per_bin.get(b, 0) + 1
            top.append(c)
    top = sorted(top, key=lambda c: -c[0])[: max(max_hypotheses // 2, max_hypotheses - 2)]
    for c in cands:
        if len(top) >= max_hypotheses:
            break
        if distinct(c):
            top.append(c)
    return top


def _refine(pyr, text, font, s0, a0, cx0, cy0, stages=(MEDIUM, FINE), known=None) -> Match | None:
    """Finer (size, angle, position) grids (``stages``: size step, angle step, half-width) at a level
    where the glyphs are ~FINE_H px tall. ``known``: the match of the template (``s0``, ``a0``) in
    the first stage's window, found before (a ``QUICK`` look from the same centre).

    Why long (9 parameters): the search's pyramid, the text and font, the starting placement, then
    the grids."""
    h100 = max(_ink(text, font)[1], 1.0)
    R, E, f = pyr.bandpass(FINE_H / (h100 * s0 / REF_SIZE))
    best = None
    done = set()
    if known is not None and stages[0][3]:
        best = (known.score, known.size, known.angle, *known.center)
        done.add((s0, a0, True))
    for ds, da, n, wide in stages:
        for s in s0 * np.exp(np.arange(-n, n + 1) * ds) if ds else [s0]:
            for a in a0 + np.arange(-n, n + 1) * da if da else [a0]:
                if (s, a, wide) in done:  # a coordinate-wise stage's centre was the last stage's best
                    continue
                done.add((s, a, wide))
                T, band = bp_template(text, font, round(s * f, 2), round(float(a), 3))
                # search a window around the current centre (off by a few coarse pixels, each about
                # FINE_H / COARSE_H pixels here): a tenth of the template's width, never more than
                # WIDE_RAD (a long text's window was far wider than any coarse error)
                rad = min(WIDE_RAD, max(6, int(0.1 * T.shape[1]))) if wide else 3
                x0, y0 = _corner(cx0, cy0, T, f)
                x0, y0 = x0 - rad, y0 - rad
                xa, ya = max(0, x0), max(0, y0)
                xb = min(R.shape[2], x0 + T.shape[1] + 2 * rad + 1)
                yb = min(R.shape[1], y0 + T.shape[0] + 2 * rad + 1)
                # (cv2's own transform of each window: a transform of the windows' union shared by a
                # step's templates was 15 % faster, but its rounding moved a development mark)
                r = match_bandpass(R[:, ya:yb, xa:xb], E[ya:yb, xa:xb], T, band)
                if r is None:
                    continue
                i = int(np.argmax(r))
                yy, xx = divmod(i, r.shape[1])
                v = float(r[yy, xx])
                if best is None or v > best[0]:
                    dy, dx = _subpixel(r, yy, xx)
                    best = (v, float(s), float(a), *_centre(xa + xx + dx, ya + yy + dy, T, f))
        if best is None:
            return None
        _, s0, a0, cx0, cy0 = best
    return Match(Path(font), best[1], best[2], (best[3], best[4]), best[0])


def repeats(img: np.ndarray, text: str, best: Match, *, max_marks: int = 64, repeat_ratio: float = 0.6,
            min_score: float = 0.0) -> list[Match]:
    """Further copies of the mark ``best`` (same font, size, angle): tiled or repeated watermarks.

    Sign-free edge features here: once the template is known, a copy over a part of the photo
    lighter than the mark correlates as well as one over a darker part.

    Parameters
    ----------
    img : np.ndarray
        (H, W, C) float image in [0, 1].
    text : str
        The mark's text.
    best : Match
        The copy found first.
    max_marks : int, default 64
        Most copies returned (``best`` included).
    repeat_ratio : float, default 0.6
        A copy's edge correlation must reach this share of ``best``'s.
    min_score : float, default 0.0
        Absolute floor of a copy's correlation.

    Returns
    -------
    list of Match
        ``best`` first, then the other copies.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.locate import repeats, search
    >>> from odnn_sep.image.render import resolve_font
    >>> from odnn_sep.image.synth import add_text_watermark
    >>> clean = np.full((64, 96, 3), 90, np.uint8)
    >>> y, _ = add_text_watermark(clean, "Hi", size=16, center=(24, 20), alpha=0.5, tile=(48, 0))
    >>> best = search(y / 255.0, "Hi", [resolve_font("DejaVuSans-Bold")])[0]
    >>> sorted(round(m.center[0]) for m in repeats(y / 255.0, "Hi", best))
    [23, 71]
    """
    pyr = Pyramid(img)
    wfull = _ink(text, best.font)[0] * best.size / REF_SIZE
    e, f = pyr.level(256.0 / wfull, 0.7)
    t = edge_template(text, str(best.font), round(best.size * f, 2), round(best.angle, 3), 0.7)
    r = match_edges(e, t)
    out = [best]
    if r is None:
        return out
    x0, y0 = _corner(best.center[0], best.center[1], t, f)
    ya, xa = int(np.clip(y0, 2, r.shape[0] - 3)), int(np.clip(x0, 2, r.shape[1] - 3))
    ref = float(r[ya - 2:ya + 3, xa - 2:xa + 3].max())  # the found copy's own edge correlation
    floor = max(min_score, repeat_ratio * ref)
    radius = max(3, int(0.35 * min(t.shape[:2])))
    for v, yy, xx in peaks(r, max_marks + 1, radius, floor):
        cx, cy = _centre(xx, yy, t, f)
        if np.hypot(cx - best.center[0], cy - best.center[1]) < 0.35 * min(t.shape[:2]) / f:
            continue
        out.append(Match(best.font, best.size, best.angle, (cx, cy), v))
        if len(out) >= max_marks:
            break
    return out
