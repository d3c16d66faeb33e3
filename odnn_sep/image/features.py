"""Matching features for the text search: band-pass correlation maps and sign-free edge maps.

Band-pass matching is the search's primary detector. A blended mark adds ``a M (c - I)`` to the
photo; after removing what is smooth at the scale of a stroke (a Gaussian high-pass, the same
"locally smooth photo" model the opacity fit uses), what is left is photo texture plus the glyph
edges scaled by ``a (c - I)``. The score of a placement is the share of that band-passed energy,
counted only on the template's edge band, that the template explains (summed over channels, sign
free per channel). Unlike a normalised correlation over the whole template window, the photo's
texture between the letters does not dilute it, so faint marks still stand out.

Edge maps (structure-tensor magnitude and doubled-angle orientation) are kept for the repeat search:
they are sign-free along the mark, which matters once the template is known to be right.
"""
from __future__ import annotations

import functools

import numpy as np

from odnn_sep.image.render import render_text, rotated

BP_SIGMA = 1.5     # px at the matching level: high-pass scale (a stroke at ~10 px glyph height)
PAD = 8            # px of zero margin around every level: marks may run off the image's edge


def edge_map(img: np.ndarray, blur: float = 0.0) -> np.ndarray:
    """Edge features of a float image: (|g|, |g| cos 2t, |g| sin 2t) from the colour structure tensor.

    The doubled angle makes the orientation features sign-free: a mark lighter or darker than the
    photo under it (which varies along the mark) gives the same feature, while photo edges that
    cross the glyph outlines at other angles do not correlate.

    Parameters
    ----------
    img : np.ndarray
        (h, w) or (h, w, C) float image.
    blur : float, default 0.0
        Gaussian blur (px) of the features; 0 for none.

    Returns
    -------
    np.ndarray
        (h, w, 3) float32: saturated edge strength and its doubled-angle orientation.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import edge_map
    >>> img = np.zeros((32, 48)); img[8:24, 10:30] = 1.0
    >>> e = edge_map(img)
    >>> e.shape, float(e[16, 16, 0]), bool(e[8, 20, 0] > 0.9)
    ((32, 48, 3), 0.0, True)
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
    return np.ascontiguousarray(f)


def bandpass_map(img: np.ndarray, levels: int = 255) -> tuple[np.ndarray, np.ndarray]:
    """(R, E): high-passed channels (C, h, w) float32, channel first so that each is one contiguous
    plane for the correlations, and their energy summed over channels (h, w), floored so that flat or
    clipped areas (no texture at all) cannot give a near-zero denominator.

    Parameters
    ----------
    img : np.ndarray
        (h, w) or (h, w, C) float image in [0, 1].
    levels : int, default 255
        Quantisation steps (sets the energy floor).

    Returns
    -------
    R : np.ndarray
        (C, h + 2 PAD, w + 2 PAD) float32 high-passed channels with a zero margin.
    E : np.ndarray
        (h + 2 PAD, w + 2 PAD) float32 floored energy.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import bandpass_map
    >>> R, E = bandpass_map(np.zeros((32, 48, 3)))
    >>> R.shape, E.shape, bool(E.min() > 0)
    ((3, 48, 64), (48, 64), True)
    """
    import cv2

    img = np.asarray(img, dtype=np.float32)
    if img.ndim == 2:
        img = img[:, :, None]
    C = img.shape[2]
    R = np.empty((C, img.shape[0] + 2 * PAD, img.shape[1] + 2 * PAD), np.float32)
    E = np.zeros(img.shape[:2], np.float32)
    for c in range(C):
        # the margin carries no signal and the floor energy, so a template hanging over the image's
        # edge is scored on the part that is inside
        r = img[:, :, c] - cv2.GaussianBlur(img[:, :, c], (0, 0), BP_SIGMA)
        R[c] = cv2.copyMakeBorder(r, PAD, PAD, PAD, PAD, cv2.BORDER_CONSTANT, value=0)
        E += r * r
    floor = C / (12.0 * levels**2) + 0.05 * float(np.median(E))
    E = cv2.copyMakeBorder(E + floor, PAD, PAD, PAD, PAD, cv2.BORDER_CONSTANT, value=floor)
    return R, np.ascontiguousarray(E)


# Longest side (px) of a pyramid's finest level: larger images are reduced first.
BASE_MAX = 768


class Pyramid:
    """The image at arbitrary downscale factors (snapped to a half-octave grid), with its feature
    maps computed once per factor.

    Parameters
    ----------
    img : np.ndarray
        (H, W) or (H, W, C) float image.
    base_max : int, default 768
        Longest side of the finest level (larger images are reduced first).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import Pyramid
    >>> pyr = Pyramid(np.zeros((32, 48, 3)))
    >>> e, f = pyr.level(0.5, 0.7)
    >>> e.shape, f
    ((32, 40, 3), 0.5)
    >>> R, E, f = pyr.bandpass(1.0)
    >>> R.shape, f
    ((3, 48, 64), 1.0)
    >>> S, f = pyr.spectra(1.0)
    >>> S.shape, f
    ((48, 64), 1.0)
    """

    def __init__(self, img: np.ndarray, base_max: int = BASE_MAX):
        import cv2

        self.H, self.W = img.shape[:2]
        self.base = min(1.0, base_max / max(self.H, self.W))
        img = np.asarray(img, dtype=np.float32)
        if self.base < 1.0:
            img = cv2.resize(img, (max(1, round(self.W * self.base)), max(1, round(self.H * self.base))),
                             interpolation=cv2.INTER_AREA)
        self.img = img if img.ndim == 3 else img[:, :, None]
        self.cache: dict = {}
        import threading

        self._lock = threading.RLock()  # levels are filled lazily, possibly from worker threads

    def _image(self, k: int) -> np.ndarray:
        import cv2

        if ("img", k) not in self.cache:
            h, w = self.img.shape[:2]
            im = self.img if k == 0 else cv2.resize(
                self.img, (max(1, round(w * 2 ** (-k / 2))), max(1, round(h * 2 ** (-k / 2)))),
                interpolation=cv2.INTER_AREA)
            self.cache[("img", k)] = im if im.ndim == 3 else im[:, :, None]
        return self.cache[("img", k)]

    def _k(self, d: float) -> int:
        return int(np.clip(np.round(-2 * np.log2(max(d, 1e-6) / self.base)), 0, 40))

    def level(self, d: float, blur: float) -> tuple[np.ndarray, float]:
        """Edge map (with a ``PAD`` margin) at full-resolution scale factor ~d, and the exact factor."""
        import cv2

        k = self._k(d)
        with self._lock:
            if ("edge", k, blur) not in self.cache:
                e = edge_map(self._image(k), blur)
                self.cache[("edge", k, blur)] = cv2.copyMakeBorder(e, PAD, PAD, PAD, PAD, cv2.BORDER_CONSTANT,
                                                                   value=0)
            e = self.cache[("edge", k, blur)]
        return e, self._image(k).shape[1] / self.W

    def bandpass(self, d: float):
        """(R, E, factor) band-pass maps (with a ``PAD`` margin) at full-resolution scale factor ~d."""
        k = self._k(d)
        with self._lock:
            if ("bp", k) not in self.cache:
                self.cache[("bp", k)] = bandpass_map(self._image(k))
            R, E = self.cache[("bp", k)]
        return R, E, self._image(k).shape[1] / self.W

    def spectra(self, d: float):
        """(``spectra.LevelSpectra`` of the band-pass maps, factor) at full-resolution scale factor ~d:
        the coarse grid matches many templates against each level."""
        from odnn_sep.image.spectra import LevelSpectra

        R, E, f = self.bandpass(d)
        k = self._k(d)
        with self._lock:
            if ("spectra", k) not in self.cache:
                self.cache[("spectra", k)] = LevelSpectra(R, E)
            return self.cache[("spectra", k)], f


@functools.lru_cache(maxsize=4096)
def edge_template(text: str, font: str, size_lvl: float, angle: float, blur: float) -> np.ndarray:
    """Edge features (:func:`edge_map`) of ``text`` rendered at ``size_lvl`` px and rotated by ``angle``
    degrees (cached).

    Parameters
    ----------
    text : str
        The mark's text.
    font : str
        Font file or name.
    size_lvl : float
        Font size at the pyramid level, px (at least 1).
    angle : float
        Rotation in degrees, counter-clockwise.
    blur : float
        Gaussian blur (px) of the features.

    Returns
    -------
    np.ndarray
        (h, w, 3) float32 template.

    Examples
    --------
    >>> from odnn_sep.image.features import edge_template
    >>> edge_template("Hi", "DejaVuSans-Bold", 12.0, 0.0, 0.7).shape
    (16, 20, 3)
    """
    m = rotated(render_text(text, font, max(size_lvl, 1.0)), angle)
    return edge_map(m, blur)


@functools.lru_cache(maxsize=4096)
def bp_template(text: str, font: str, size_lvl: float, angle: float) -> tuple[np.ndarray, np.ndarray]:
    """(T, band): high-passed coverage (normalised to unit energy) and its edge band (0/1).

    Parameters
    ----------
    text : str
        The mark's text.
    font : str
        Font file or name.
    size_lvl : float
        Font size at the pyramid level, px (at least 1).
    angle : float
        Rotation in degrees, counter-clockwise.

    Returns
    -------
    T : np.ndarray
        (h, w) float32, read-only, unit energy.
    band : np.ndarray
        (h, w) float32, read-only, 1 on the edge band.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import bp_template
    >>> T, band = bp_template("Hi", "DejaVuSans-Bold", 12.0, 0.0)
    >>> T.shape, round(float((T * T).sum()), 3), sorted(np.unique(band).tolist())
    ((16, 20), 1.0, [0.0, 1.0])
    """
    import cv2

    m = rotated(render_text(text, font, max(size_lvl, 1.0)), angle).astype(np.float32)
    T = m - cv2.GaussianBlur(m, (0, 0), BP_SIGMA)
    T /= max(float(np.sqrt(np.sum(T * T))), 1e-12)
    band = (np.abs(T) > 0.05 * float(np.abs(T).max())).astype(np.float32)
    T.setflags(write=False)
    band.setflags(write=False)
    return T, band


def match_edges(edges: np.ndarray, tmpl: np.ndarray) -> np.ndarray | None:
    """Normalised cross-correlation map of edge features (None when the template does not fit).

    Parameters
    ----------
    edges : np.ndarray
        (h, w, 3) float32 edge map of the image (with its margin).
    tmpl : np.ndarray
        (th, tw, 3) float32 edge template.

    Returns
    -------
    np.ndarray or None
        (h - th + 1, w - tw + 1) correlation in [-1, 1] at each top-left corner.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import PAD, edge_map, edge_template, match_edges
    >>> from odnn_sep.image.render import render_text
    >>> m = render_text("Hi", "DejaVuSans-Bold", 12.0)
    >>> img = np.full((40, 60), 0.3); img[10:10 + m.shape[0], 20:20 + m.shape[1]] += 0.5 * m
    >>> e = np.pad(edge_map(img, 0.7), ((PAD, PAD), (PAD, PAD), (0, 0)))
    >>> r = match_edges(e, edge_template("Hi", "DejaVuSans-Bold", 12.0, 0.0, 0.7))
    >>> r.shape, tuple(int(v) for v in np.unravel_index(np.argmax(r), r.shape)), round(float(r.max()), 2)
    ((41, 57), (17, 27), 0.98)
    """
    import cv2

    if tmpl.shape[0] >= edges.shape[0] or tmpl.shape[1] >= edges.shape[1] or tmpl[:, :, 0].std() < 1e-9:
        return None
    r = cv2.matchTemplate(edges, tmpl, cv2.TM_CCOEFF_NORMED)
    return np.nan_to_num(r, nan=-1.0, posinf=-1.0, neginf=-1.0)


def match_bandpass(R: np.ndarray, E: np.ndarray, T: np.ndarray, band: np.ndarray) -> np.ndarray | None:
    """Share of the band-passed energy on the template's edge band that the template explains
    (``R`` channel first, (C, h, w), as ``bandpass_map`` gives it, or a window of it).

    Parameters
    ----------
    R : np.ndarray
        (C, h, w) float32 high-passed channels.
    E : np.ndarray
        (h, w) float32 floored energy.
    T : np.ndarray
        (th, tw) float32 template (:func:`bp_template`).
    band : np.ndarray
        (th, tw) float32 edge band of the template.

    Returns
    -------
    np.ndarray or None
        (h - th + 1, w - tw + 1) score at each top-left corner; None when the template does not fit.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import bandpass_map, bp_template, match_bandpass
    >>> from odnn_sep.image.render import render_text
    >>> m = render_text("Hi", "DejaVuSans-Bold", 12.0)
    >>> img = np.full((40, 60), 0.3); img[10:10 + m.shape[0], 20:20 + m.shape[1]] += 0.5 * m
    >>> s = match_bandpass(*bandpass_map(img), *bp_template("Hi", "DejaVuSans-Bold", 12.0, 0.0))
    >>> s.shape, tuple(int(v) for v in np.unravel_index(np.argmax(s), s.shape)), round(float(s.max()), 2)
    ((41, 57), (17, 27), 1.0)
    """
    import cv2

    C, h, w = R.shape
    if T.shape[0] >= h or T.shape[1] >= w:
        return None
    # the channels stacked into one tall image, one correlation: the template is transformed once
    # instead of once per channel (the rows that straddle two channels are dropped)
    Rs = R.reshape(C * h, w) if R.flags["C_CONTIGUOUS"] else np.ascontiguousarray(R).reshape(C * h, w)
    r = cv2.matchTemplate(Rs, T, cv2.TM_CCORR)
    oh = h - T.shape[0] + 1
    num = r[:oh] * r[:oh]
    for c in range(1, C):
        rc = r[c * h:c * h + oh]
        num += rc * rc
    den = cv2.matchTemplate(E, band, cv2.TM_CCORR)
    # E is floored above zero, so only rounding in the correlation can bring den to ~0
    np.maximum(den, 1e-30, out=den)
    num /= den
    return num


def peaks(r: np.ndarray, n: int, radius: int, floor: float) -> list[tuple[float, int, int]]:
    """Up to ``n`` local maxima of ``r`` above ``floor``, at least ``radius`` apart (greedy NMS).

    Parameters
    ----------
    r : np.ndarray
        (h, w) score map.
    n : int
        Most peaks.
    radius : int
        Half-width (px) of the square cleared around each peak.
    floor : float
        Smallest score kept.

    Returns
    -------
    list of tuple
        (value, row, column), best first.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import peaks
    >>> r = np.zeros((10, 10)); r[2, 3] = 1.0; r[3, 3] = 0.9; r[7, 8] = 0.5
    >>> peaks(r, 5, 2, 0.1)
    [(1.0, 2, 3), (0.5, 7, 8)]
    """
    out: list[tuple[float, int, int]] = []
    cleared = []  # (window, its values): ``r`` is restored afterwards instead of copied whole first
    try:
        for _ in range(n):
            i = int(np.argmax(r))
            yy, xx = divmod(i, r.shape[1])
            v = float(r[yy, xx])
            if v < floor:
                break
            out.append((v, yy, xx))
            if len(out) == n:
                break
            win = (slice(max(0, yy - radius), yy + radius + 1), slice(max(0, xx - radius), xx + radius + 1))
            cleared.append((win, r[win].copy()))
            r[win] = -1.0
    finally:
        for win, vals in reversed(cleared):
            r[win] = vals
    return out
