"""The coarse grid's band-pass match with each pyramid level transformed once.

The coarse grid matches dozens of (size, angle) templates against the whole of each pyramid level.
``cv2.matchTemplate`` transforms the level again for every template (block by block); here the
level's channels and its energy are transformed once, and a template costs its own two forward
transforms and one inverse transform per channel: about a third less time on a 12-megapixel
photo's coarse grid. A valid correlation needs no padding beyond the level itself (the output at
offset y reads rows y to y + th - 1 < h, so the circular transform never wraps into it). The scores
equal ``features.match_bandpass``'s to float rounding (about 1e-5 of the best score).
"""
from __future__ import annotations

import numpy as np


class LevelSpectra:
    """Forward transforms of a level's band-passed channels ``R`` (C, h, w) and energy ``E`` (h, w)
    (``features.bandpass_map``), for :meth:`match` against many templates.

    Parameters
    ----------
    R : np.ndarray
        (C, h, w) float32 high-passed channels with their margin.
    E : np.ndarray
        (h, w) float32 floored energy.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.features import bandpass_map, bp_template, match_bandpass
    >>> from odnn_sep.image.render import render_text
    >>> from odnn_sep.image.spectra import LevelSpectra
    >>> m = render_text("Hi", "DejaVuSans-Bold", 12.0)
    >>> img = np.random.default_rng(0).random((40, 60, 3)) * 0.1
    >>> img[10:10 + m.shape[0], 20:20 + m.shape[1]] += 0.5 * m[:, :, None]
    >>> R, E = bandpass_map(img)
    >>> T, band = bp_template("Hi", "DejaVuSans-Bold", 12.0, 0.0)
    >>> s = LevelSpectra(R, E).match(T, band)
    >>> s.shape, bool(np.allclose(s, match_bandpass(R, E, T, band), rtol=1e-4, atol=1e-6))
    ((41, 57), True)
    """

    def __init__(self, R: np.ndarray, E: np.ndarray):
        import cv2

        C, h, w = R.shape
        self.shape = (h, w)
        # cv2's fast transform sizes, at least the level's
        self.size = (cv2.getOptimalDFTSize(h), cv2.getOptimalDFTSize(w))
        self.FR = [cv2.dft(self._padded(R[c])) for c in range(C)]  # real spectra, packed (CCS)
        self.FE = cv2.dft(self._padded(E))

    def _padded(self, a: np.ndarray) -> np.ndarray:
        import cv2

        return cv2.copyMakeBorder(np.ascontiguousarray(a, dtype=np.float32), 0, self.size[0] - a.shape[0], 0,
                                  self.size[1] - a.shape[1], cv2.BORDER_CONSTANT, value=0)

    @staticmethod
    def _corr(F: np.ndarray, Ft: np.ndarray, oh: int, ow: int) -> np.ndarray:
        import cv2

        P = cv2.mulSpectrums(F, Ft, 0, conjB=True)
        # (cv2.dft's nonzeroRows, meant to skip rows, made these transforms slower: not used)
        return cv2.dft(P, flags=cv2.DFT_INVERSE | cv2.DFT_SCALE | cv2.DFT_REAL_OUTPUT)[:oh, :ow]

    def match(self, T: np.ndarray, band: np.ndarray) -> np.ndarray | None:
        """``features.match_bandpass(R, E, T, band)`` from the stored spectra (None when ``T`` does
        not fit).

        Parameters
        ----------
        T : np.ndarray
            (th, tw) float32 template (``features.bp_template``).
        band : np.ndarray
            (th, tw) float32 edge band of the template.

        Returns
        -------
        np.ndarray or None
            (h - th + 1, w - tw + 1) float32 score at each top-left corner.
        """
        import cv2

        h, w = self.shape
        th, tw = T.shape
        if th >= h or tw >= w:
            return None
        oh, ow = h - th + 1, w - tw + 1
        FT = cv2.dft(self._padded(T))
        num = None
        for F in self.FR:
            r = self._corr(F, FT, oh, ow)
            if num is None:
                num = r * r
            else:
                num += r * r
        den = self._corr(self.FE, cv2.dft(self._padded(band)), oh, ow)
        # E is floored above zero, so only rounding in the transforms can bring den to ~0
        np.maximum(den, 1e-30, out=den)
        num /= den
        return num
