"""Edge and orientation maps of a photo and of a rendered logo, and their correlation: what the logo
search (``logo_search``) matches and the residual-mark check (``logo_residual``) measures.

A blended logo shows in the photo as edges: its outline (a step of ``alpha (L - I)``) and the colour
edges inside it. Edge magnitudes do not depend on whether the mark is lighter or darker than the
photo under it, so the photo's gradient magnitude (or its orientation field) is compared with the
logo's. Every map is band-passed first (upper scale ``BAND_SIGMA``): smooth photo shading is not a
logo.
"""
from __future__ import annotations

import numpy as np

# Upper scale (px) of the band-pass applied before the gradient.
BAND_SIGMA = 3.0


def luminance(a: np.ndarray) -> np.ndarray:
    """(h, w, C) float32 (colour kept: edges are summed over channels); (h, w) becomes (h, w, 1).

    Parameters
    ----------
    a : np.ndarray
        (h, w) or (h, w, C) image.

    Returns
    -------
    np.ndarray
        (h, w, C) float32.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import luminance
    >>> luminance(np.zeros((4, 5))).shape, luminance(np.zeros((4, 5, 3))).dtype
    ((4, 5, 1), dtype('float32'))
    """
    a = np.asarray(a, dtype=np.float32)
    return a[:, :, None] if a.ndim == 2 else a


def edges(img: np.ndarray, sigma: float) -> np.ndarray:
    """Gradient magnitude after a Gaussian blur of ``sigma`` px, summed over channels (float32 (h, w)).

    Parameters
    ----------
    img : np.ndarray
        (h, w) or (h, w, C) float image.
    sigma : float
        Gaussian blur in px (the band-pass's upper scale is ``BAND_SIGMA``).

    Returns
    -------
    np.ndarray
        (h, w) float32 edge magnitude.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import edges
    >>> img = np.zeros((32, 48)); img[8:24, 10:30] = 1.0
    >>> e = edges(img, 1.0)
    >>> e.shape, bool(e[8, 20] > 10 * e[16, 20])
    ((32, 48), True)
    """
    import cv2

    a = np.asarray(img, np.float32)
    a = a[:, :, None] if a.ndim == 2 else a
    out = np.zeros(a.shape[:2], np.float32)
    for c in range(a.shape[2]):
        g = cv2.GaussianBlur(np.ascontiguousarray(a[:, :, c]), (0, 0), sigma)
        g -= cv2.GaussianBlur(g, (0, 0), BAND_SIGMA)  # band-pass: smooth photo shading is not a logo
        out += cv2.magnitude(cv2.Sobel(g, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(g, cv2.CV_32F, 0, 1, ksize=3))
    return out


def orientation(img: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Doubled-angle gradient field (re, im) = |g| (cos 2t, sin 2t) of the band-passed image, summed
    over channels: an edge's orientation without its sign (a mark lighter or darker than the photo
    under it gives the same field), and photo edges of random orientation cancel in a correlation.

    Parameters
    ----------
    img : np.ndarray
        (h, w) or (h, w, C) float image.
    sigma : float
        Gaussian blur in px.

    Returns
    -------
    re, im : np.ndarray
        (h, w) float32 components of the doubled-angle field.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import orientation
    >>> img = np.zeros((32, 48)); img[8:24, 10:30] = 1.0
    >>> re, im = orientation(img, 1.0)
    >>> bool(re[16, 10] > 0), bool(re[8, 20] < 0)      # vertical edge, horizontal edge
    (True, True)
    """
    import cv2

    a = np.asarray(img, np.float32)
    a = a[:, :, None] if a.ndim == 2 else a
    re = np.zeros(a.shape[:2], np.float32)
    im = np.zeros(a.shape[:2], np.float32)
    for c in range(a.shape[2]):
        g = cv2.GaussianBlur(np.ascontiguousarray(a[:, :, c]), (0, 0), sigma)
        g -= cv2.GaussianBlur(g, (0, 0), BAND_SIGMA)
        gx, gy = cv2.Sobel(g, cv2.CV_32F, 1, 0, ksize=3), cv2.Sobel(g, cv2.CV_32F, 0, 1, ksize=3)
        mag = np.sqrt(gx * gx + gy * gy) + 1e-12
        re += (gx * gx - gy * gy) / mag
        im += 2 * gx * gy / mag
    return re, im


def logo_orientation(M: np.ndarray, L: np.ndarray, sigma: float) -> tuple[np.ndarray, np.ndarray]:
    """Doubled-angle field of a placed logo: outline plus colour edges (as ``logo_edges``).

    Parameters
    ----------
    M : np.ndarray
        (h, w) coverage of the placed logo.
    L : np.ndarray
        (h, w[, C]) its colours.
    sigma : float
        Gaussian blur in px.

    Returns
    -------
    re, im : np.ndarray
        (h, w) float32 components of the field.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import logo_orientation
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> [f.shape for f in logo_orientation(M, L, 1.0)]
    [(19, 19), (19, 19)]
    """
    r1, i1 = orientation(M, sigma)
    r2, i2 = orientation(M[:, :, None] * luminance(L), sigma)
    k = 1.0 / max(1, luminance(L).shape[2])
    return r1 + k * r2, i1 + k * i2


def match_orientation(G, T) -> np.ndarray:
    """Normalised correlation of template field T = (re, im) with image field G at every position:
    Re(sum conj(T) G) / (|T| |G window|) (OpenCV's FFT correlation, window energy from a box sum).

    Parameters
    ----------
    G : tuple of np.ndarray
        (re, im) field of the image (:func:`orientation`).
    T : tuple of np.ndarray
        (re, im) field of the template (:func:`logo_orientation`).

    Returns
    -------
    np.ndarray
        Correlation at every top-left corner, (H - h + 1, W - w + 1).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import logo_orientation, match_orientation, orientation
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> R = match_orientation(orientation(photo, 1.0), logo_orientation(M, L, 1.0))
    >>> R.shape, tuple(int(v) for v in np.unravel_index(np.argmax(R), R.shape)), round(float(R.max()), 2)
    ((46, 78), (21, 31), 0.98)
    """
    import cv2

    num = cv2.matchTemplate(G[0], T[0], cv2.TM_CCORR) + cv2.matchTemplate(G[1], T[1], cv2.TM_CCORR)
    e = G[0] * G[0] + G[1] * G[1]
    h, w = T[0].shape
    win = cv2.boxFilter(e, -1, (w, h), anchor=(0, 0), normalize=False, borderType=cv2.BORDER_CONSTANT)
    win = win[: num.shape[0], : num.shape[1]]
    tn = float(np.sqrt(np.sum(T[0] ** 2 + T[1] ** 2)))
    return num / (tn * np.sqrt(np.maximum(win, 1e-12)))


def logo_edges(M: np.ndarray, L: np.ndarray, sigma: float) -> np.ndarray:
    """Edge map of a placed logo: its outline (whatever the photo's colour under it) plus the edges of
    its colours.

    Parameters
    ----------
    M : np.ndarray
        (h, w) coverage of the placed logo.
    L : np.ndarray
        (h, w[, C]) its colours.
    sigma : float
        Gaussian blur in px.

    Returns
    -------
    np.ndarray
        (h, w) float32 edge magnitude.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.logo_features import logo_edges
    >>> from odnn_sep.image.logo import Placement, prepare_logo, render
    >>> a = np.zeros((20, 20), np.uint8); a[4:16, 4:8] = 255; a[4:8, 4:16] = 255
    >>> logo = prepare_logo(a, (64, 96), 1)
    >>> M, L, b = render(logo, Placement(40, 30, 1.0, 0.0), (64, 96))
    >>> photo = np.full((64, 96), 0.3); photo[b[1]:b[3], b[0]:b[2]] = 0.3 + 0.5 * M * (L[..., 0] - 0.3)
    >>> logo_edges(M, L, 1.0).shape
    (19, 19)
    """
    return edges(M, sigma) + edges(M[:, :, None] * luminance(L), sigma) / max(1, luminance(L).shape[2])
