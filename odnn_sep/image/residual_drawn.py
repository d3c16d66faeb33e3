"""Letters the removal drew: parts of the rendering the input does not show, inverted all the same.

The text search registers the whole rendering of ``--text`` once most of it matches. A text with
characters the mark does not have ("SAMPLE 2024" for a mark that reads "SAMPLE", an emoji added)
was registered at a lower score but over the threshold, and the blend was inverted over the extra
characters too: where there was no mark, inverting it darkens (for a light mark) the photo in the
shape of those letters. The output then shows them in the opposite colour, with exit 0, while every
other residual measure looks for the mark left as it was.

Here each connected part of the coverage (a glyph, or glyphs that touch) is correlated, along the
mark's contrast with the photo, with the input and with the output over a window around it: a part
the input shows correlates positively with the input and about zero with the output; a part the
removal drew correlates about zero with the input and negatively with the output. Parts too small
or over a photo of nearly the mark's colour (where a missing letter changes nothing) are not judged.
"""
from __future__ import annotations

import numpy as np

# A part is drawn when the input correlates with it below IN_MAX and the output below OUT_MAX, along a
# contrast of at least MIN_LEVELS 8-bit levels. Set on the case of tests/image/test_image_drawn.py
# (letters added to the text: input about 0, output below -0.8; letters present: input 0.6-0.95, output
# within +-0.3 of 0). recipes/probe_image_drawn.py, no --font: development seed 1, no part called drawn
# in the 10 marks found with their own text, 2 of the 4 marks found with a letter added called drawn;
# seed 5 (4 photos, run once) 0 of 6 and 1 of 3. Missed: a letter added over a light photo under a
# white mark (its inversion clipped and was inpainted, so the output shows no dark letter) and a
# registration the added letter pulled off the mark; the image golden cases: no part called drawn.
IN_MAX = 0.25
OUT_MAX = -0.5
MIN_LEVELS = 12.0
MIN_PIXELS = 24       # pixels of a part over half coverage (smaller parts: too few to correlate)
RING = 3              # px of photo around a part taken into its window


def _corr(a: np.ndarray, m: np.ndarray) -> float:
    a = a - a.mean()
    m = m - m.mean()
    den = float(np.sqrt(np.sum(a * a) * np.sum(m * m)))
    return float(np.sum(a * m) / den) if den > 1e-12 else 0.0


def drawn_parts(out: np.ndarray, inp: np.ndarray, M: np.ndarray, alpha: float, color) -> list[dict]:
    """The parts of the coverage ``M`` that the input does not show and the output shows inverted.

    Parameters
    ----------
    out, inp : np.ndarray
        (h, w, C) float output and input crops in [0, 1] (the mark's box).
    M : np.ndarray
        (h, w) coverage the blend was inverted with.
    alpha : float
        Fitted opacity.
    color : array_like
        (C,) fitted mark colour in [0, 1].

    Returns
    -------
    list of dict
        Per part drawn: ``at`` (x, y of its centre in the crop), ``pixels``, ``input_corr``,
        ``output_corr`` and ``levels`` (the contrast a mark there would have had, 8-bit levels RMS over
        the channels).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.residual_drawn import drawn_parts
    >>> M = np.zeros((40, 80)); M[10:30, 10:18] = 1; M[10:30, 50:58] = 1       # two "letters"
    >>> photo = np.full((40, 80, 3), 0.3)
    >>> inp = photo.copy(); inp[10:30, 10:18] = 0.65                          # only the first is marked
    >>> out = (inp - 0.5 * M[..., None]) / (1 - 0.5 * M[..., None])           # both inverted (white, 0.5)
    >>> [p["at"] for p in drawn_parts(out, inp, M, 0.5, [1.0, 1.0, 1.0])]
    [(53.5, 19.5)]
    """
    import cv2

    out = out[:, :, None] if out.ndim == 2 else out
    inp = inp[:, :, None] if inp.ndim == 2 else inp
    c = np.asarray(color, dtype=np.float64).ravel()
    if c.size != out.shape[2]:
        return []
    M = np.asarray(M, dtype=np.float64)
    n, labels, stats, _ = cv2.connectedComponentsWithStats((M > 0.5).astype(np.uint8), connectivity=8)
    near = cv2.dilate((M > 0.02).astype(np.uint8), np.ones((3, 3), np.uint8))  # every part's soft edge
    found = []
    h, w = M.shape
    for k in range(1, n):
        x, y, bw, bh, area = (int(v) for v in stats[k])
        if area < MIN_PIXELS:
            continue
        x0, y0 = max(0, x - RING - 1), max(0, y - RING - 1)
        x1, y1 = min(w, x + bw + RING + 1), min(h, y + bh + RING + 1)
        own = cv2.dilate((labels[y0:y1, x0:x1] == k).astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
        # pixels of other parts in the window are left out: they carry their own answer
        use = own | (near[y0:y1, x0:x1] == 0)
        photo = (near[y0:y1, x0:x1] == 0)
        if photo.sum() < 8:
            continue
        bg = np.median(out[y0:y1, x0:x1][photo], axis=0)
        d = c - bg
        levels = 255.0 * alpha * float(np.linalg.norm(d)) / np.sqrt(d.size)  # RMS over the channels
        if levels < MIN_LEVELS:
            continue
        d = d / np.linalg.norm(d)
        m = np.where(own, M[y0:y1, x0:x1], 0.0)[use]
        ci = _corr((inp[y0:y1, x0:x1] @ d)[use], m)
        co = _corr((out[y0:y1, x0:x1] @ d)[use], m)
        if ci < IN_MAX and co < OUT_MAX:
            found.append({"at": (round(x + (bw - 1) / 2.0, 1), round(y + (bh - 1) / 2.0, 1)), "pixels": area,
                          "input_corr": round(ci, 3), "output_corr": round(co, 3), "levels": round(levels, 1)})
    return found


__all__ = ["drawn_parts", "IN_MAX", "OUT_MAX", "MIN_LEVELS"]
