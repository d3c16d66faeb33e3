"""Find a rendered text in an image: position, size (px), rotation and repeats.

Matching is done on edges, not intensities: a blended mark changes the image's gradient
magnitude along the glyph outlines whatever its colour and opacity, so the normalised
cross-correlation (OpenCV ``TM_CCOEFF_NORMED``) of the template's gradient magnitude with the
image's is a contrast-invariant detector. The search is coarse-to-fine: every (size, angle) on a
log/linear grid at a pyramid level where the template is about 64 px wide, then a finer grid at a
level where it is about 256 px wide around the best candidates, for every candidate font. The
final sub-pixel fit minimises the blend model's residual (see ``estimate``).
"""
from __future__ import annotations

import dataclasses
import functools
import logging
from pathlib import Path

import numpy as np

from odnn_sep.image.render import render_text, rotated

log = logging.getLogger(__name__)

REF_SIZE = 100.0


@dataclasses.dataclass
class Match:
    font: Path
    size: float          # em size in px at full resolution
    angle: float         # degrees, counter-clockwise as displayed
    center: tuple[float, float]  # (x, y) of the ink-box centre, full-resolution px
    score: float         # NCC of gradient magnitudes at the refinement level


def edge_map(img: np.ndarray, blur: float = 0.0, normalize: bool = False) -> np.ndarray:
    """Edge features of a float image: (|g|, |g| cos 2t, |g| sin 2t) from the colour structure tensor.

    The doubled angle makes the orientation features sign-free: a mark lighter or darker than the
    photo under it (which varies along the mark) gives the same feature, while photo edges that
    cross the glyph outlines at other angles do not correlate.
    """
    import cv2

    img = np.asarray(img, dtype=np.float32)
    if img.ndim == 2:
        img = img[:, :, None]
    jxx = np.zeros(img.shape[:2], np.float32)
    jyy = np.zeros_like(jxx)
    jxy = np.zeros_like(jxx)
    for c in range(img.shape[2]):
        gx = cv2.Sobel(img[:, :, c], cv2.CV_32F, 1, 0, ksize=3)
        gy = cv2.Sobel(img[:, :, c], cv2.CV_32F, 0, 1, ksize=3)
        jxx += gx * gx
        jyy += gy * gy
        jxy += gx * gy
    mag = np.sqrt(jxx + jyy)
    inv = 1.0 / np.maximum(mag, 1e-12)
    # Saturate the edge strength: a faint mark's outlines must weigh as much as the photo's
    # high-contrast edges, or the correlation follows the photo.
    k = float(np.median(mag)) * 3.0 + 1e-3 * float(mag.max()) + 1e-12
    w = np.tanh(mag / k)
    f = np.stack([w, (jxx - jyy) * inv * inv * w, 2.0 * jxy * inv * inv * w], axis=2)
    if blur > 0:
        f = cv2.GaussianBlur(f, (0, 0), blur)
    if normalize:
        # local contrast normalisation: a faint mark over strong photo texture still counts
        loc = cv2.GaussianBlur(mag, (0, 0), 4.0) + 0.02 * float(mag.max() + 1e-12)
        f = f / loc[:, :, None]
    return np.ascontiguousarray(f)


class _Pyramid:
    """The image's edge maps at arbitrary downscale factors (computed once per factor)."""

    def __init__(self, img: np.ndarray, base_max: int = 768):
        import cv2

        self.H, self.W = img.shape[:2]
        self.base = min(1.0, base_max / max(self.H, self.W))
        if self.base < 1.0:
            img = cv2.resize(img.astype(np.float32), (max(1, round(self.W * self.base)),
                                                      max(1, round(self.H * self.base))),
                             interpolation=cv2.INTER_AREA)
        self.img = np.asarray(img, dtype=np.float32)
        self.cache: dict[float, np.ndarray] = {}

    def level(self, d: float, blur: float) -> tuple[np.ndarray, float]:
        """Edge map at full-resolution scale factor ~d (snapped to a half-octave grid); returns the
        map and the exact factor used."""
        import cv2

        k = int(np.clip(np.round(-2 * np.log2(max(d, 1e-6) / self.base)), 0, 40))
        f = self.base * 2 ** (-k / 2)
        key = (k, blur)
        if key not in self.cache:
            if k == 0:
                im = self.img
            else:
                h, w = self.img.shape[:2]
                im = cv2.resize(self.img, (max(1, round(w * 2 ** (-k / 2))), max(1, round(h * 2 ** (-k / 2)))),
                                interpolation=cv2.INTER_AREA)
            self.cache[key] = edge_map(im, blur)
        e = self.cache[key]
        return e, e.shape[1] / self.W if e.shape[1] > 1 else f


@functools.lru_cache(maxsize=4096)
def _template(text: str, font: str, size_lvl: float, angle: float, blur: float) -> np.ndarray:
    m = rotated(render_text(text, font, max(size_lvl, 1.0)), angle)
    return edge_map(m, blur)


def _ink_width(text: str, font) -> float:
    return render_text(text, font, REF_SIZE).shape[1] - 4


def _match(edges: np.ndarray, tmpl: np.ndarray) -> np.ndarray | None:
    import cv2

    if tmpl.shape[0] >= edges.shape[0] or tmpl.shape[1] >= edges.shape[1] or tmpl[:, :, 0].std() < 1e-9:
        return None
    r = cv2.matchTemplate(edges, tmpl, cv2.TM_CCOEFF_NORMED)
    return np.nan_to_num(r, nan=-1.0, posinf=-1.0, neginf=-1.0)


def _peaks(r: np.ndarray, n: int, radius: int, floor: float) -> list[tuple[float, int, int]]:
    """Up to ``n`` local maxima of ``r`` above ``floor``, at least ``radius`` apart (greedy NMS)."""
    out = []
    r = r.copy()
    for _ in range(n):
        i = int(np.argmax(r))
        yy, xx = divmod(i, r.shape[1])
        v = float(r[yy, xx])
        if v < floor:
            break
        out.append((v, yy, xx))
        r[max(0, yy - radius):yy + radius + 1, max(0, xx - radius):xx + radius + 1] = -1.0
    return out


def search(img: np.ndarray, text: str, fonts: list[Path], *, angle_range: float = 45.0,
           min_height_px: float = 8.0, max_hypotheses: int = 8, coarse_h: float = 10.0,
           per_size_bin: int = 1) -> list[Match]:
    """Coarse-to-fine search for ``text`` (any of ``fonts``); returns distinct hypotheses, best first."""
    H, W = img.shape[:2]
    pyr = _Pyramid(img)
    f0 = str(fonts[0])
    w100 = _ink_width(text, f0)
    h100 = render_text(text, f0, REF_SIZE).shape[0] - 4
    # size range: glyph height >= min_height_px, text width <= 1.05 x the image diagonal
    s_min = max(4.0, min_height_px / max(h100, 1) * REF_SIZE * 1.4)
    # the search pyramid starts at <= 768 px: text must be at least ~8 px tall there (on a 12-MP
    # photo, ~40 px); smaller templates only match noise
    s_min = max(s_min, 0.8 * coarse_h / max(h100, 1) * REF_SIZE / pyr.base)
    s_max = 1.05 * np.hypot(H, W) / max(w100, 1) * REF_SIZE
    if s_max <= s_min:
        s_max = s_min * 1.01
    # coarse level: glyph height ~8 px; the grid steps then keep the template's ends within ~1.5 px
    w_lvl = coarse_h * w100 / max(h100, 1)
    da = float(np.clip(np.rad2deg(2 * 1.5 / (w_lvl / 2)), 1.5, 5.0))
    ratio = float(np.clip(1 + 2 * 1.5 / (w_lvl / 2), 1.04, 1.1))
    sizes = np.exp(np.arange(np.log(s_min), np.log(s_max) + 1e-9, np.log(ratio)))
    n_a = int(np.ceil(angle_range / da))
    angles = np.linspace(-angle_range, angle_range, 2 * n_a + 1) if n_a else np.zeros(1)
    cands: list[tuple[float, float, float, float, float]] = []  # (score, size, angle, cx, cy)
    for s in sizes:
        hfull = h100 * s / REF_SIZE
        e, f = pyr.level(coarse_h / hfull, 1.0)
        for a in angles:
            t = _template(text, f0, round(s * f, 2), float(a), 1.0)
            r = _match(e, t)
            if r is None:
                continue
            for v, yy, xx in _peaks(r, 2, max(2, min(t.shape[:2]) // 2), -1.0):
                cx = (xx + (t.shape[1] - 1) / 2) / f
                cy = (yy + (t.shape[0] - 1) / 2) / f
                cands.append((v, s, float(a), cx, cy))
    if not cands:
        return []
    cands.sort(key=lambda c: -c[0])
    # Keep distinct hypotheses: the best ``per_size_bin`` of every half-octave of size first
    # (correlation maxima of small templates on large levels are inflated by the many positions they
    # are tried at, so a purely global ranking starves the large sizes; and a faint or partly hidden
    # mark's correct placement is often only the second or third peak of its size), then the next
    # best overall.
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
    out: list[Match] = []
    for _, s0, a0, cx0, cy0 in top:
        best = None
        for font in fonts:
            # match the coarse text width with this font
            s1 = s0 * w100 / _ink_width(text, font)
            m = _refine(pyr, text, str(font), s1, a0, cx0, cy0, H, W)
            if m is not None and (best is None or m.score > best.score):
                best = m
        if best is not None and not any(
                abs(np.log(best.size / o.size)) < 0.04 and abs(best.angle - o.angle) < 2.0
                and np.hypot(best.center[0] - o.center[0], best.center[1] - o.center[1]) < 3.0 for o in out):
            out.append(best)
    out.sort(key=lambda m: -m.score)
    return out


def repeats(img: np.ndarray, text: str, best: Match, *, max_marks: int = 64, repeat_ratio: float = 0.6,
            min_score: float = 0.0) -> list[Match]:
    """Further copies of the mark ``best`` (same font, size, angle): tiled or repeated watermarks."""
    H, W = img.shape[:2]
    return _repeats(_Pyramid(img), text, best, H, W, max_marks, repeat_ratio, min_score)


def _refine(pyr, text, font, s0, a0, cx0, cy0, H, W) -> Match | None:
    """Finer (size, angle, position) grid at a level where the template is ~256 px wide."""
    wfull = _ink_width(text, font) * s0 / REF_SIZE
    e, f = pyr.level(256.0 / wfull, 0.7)
    best = None
    for stage, (ds, da, n) in enumerate(((0.05, 1.8, 2), (0.02, 0.7, 1))):
        ss = s0 * np.exp(np.arange(-n, n + 1) * ds)
        aa = a0 + np.arange(-n, n + 1) * da
        for s in ss:
            for a in aa:
                t = _template(text, font, round(s * f, 2), round(float(a), 3), 0.7)
                # search a window around the current centre
                rad = max(8, int(0.15 * t.shape[1])) if stage == 0 else 4
                x0 = int(round(cx0 * f - (t.shape[1] - 1) / 2)) - rad
                y0 = int(round(cy0 * f - (t.shape[0] - 1) / 2)) - rad
                xa, ya = max(0, x0), max(0, y0)
                xb = min(e.shape[1], x0 + t.shape[1] + 2 * rad + 1)
                yb = min(e.shape[0], y0 + t.shape[0] + 2 * rad + 1)
                win = e[ya:yb, xa:xb]
                r = _match(win, t)
                if r is None:
                    continue
                i = int(np.argmax(r))
                yy, xx = divmod(i, r.shape[1])
                v = float(r[yy, xx])
                if best is None or v > best[0]:
                    best = (v, float(s), float(a), (xa + xx + (t.shape[1] - 1) / 2) / f,
                            (ya + yy + (t.shape[0] - 1) / 2) / f)
        if best is None:
            return None
        _, s0, a0, cx0, cy0 = best
    return Match(Path(font), best[1], best[2], (best[3], best[4]), best[0])


def _repeats(pyr, text, best: Match, H, W, max_marks, repeat_ratio, min_score) -> list[Match]:
    wfull = _ink_width(text, best.font) * best.size / REF_SIZE
    e, f = pyr.level(256.0 / wfull, 0.7)
    t = _template(text, str(best.font), round(best.size * f, 2), round(best.angle, 3), 0.7)
    r = _match(e, t)
    out = [best]
    if r is None:
        return out
    floor = max(min_score, repeat_ratio * best.score)
    radius = max(3, int(0.35 * min(t.shape)))
    for v, yy, xx in _peaks(r, max_marks + 1, radius, floor):
        cx, cy = (xx + (t.shape[1] - 1) / 2) / f, (yy + (t.shape[0] - 1) / 2) / f
        if np.hypot(cx - best.center[0], cy - best.center[1]) < 0.35 * min(t.shape) / f:
            continue
        out.append(Match(best.font, best.size, best.angle, (cx, cy), v))
        if len(out) >= max_marks:
            break
    return out
