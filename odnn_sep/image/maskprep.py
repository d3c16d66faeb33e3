"""A user's mask read as what it means: one plane in [0, 1], its polarity, hard region or soft mask.

Masks come as grey, RGB or RGBA images, white-on-black or black-on-white, binary with anti-aliased
edges or truly soft. A mask whose marked part covers most of the image is almost surely inverted
(black marks the watermark): it is inverted with a warning, unless the caller says which polarity
it has. A mask with many intermediate values (not only an anti-aliased edge) is soft: its support
(values above ``SOFT_SUPPORT``) is the region, where mask mode reads the coverage M from the data.
"""
from __future__ import annotations

import dataclasses
import logging

import numpy as np

from odnn_sep.errors import InputError

log = logging.getLogger(__name__)

# A mask marking more than this share of the image is read as inverted (unless told otherwise).
INVERTED_SHARE = 0.5
# A mask is soft when more than this share of its support holds values strictly between 0.1 and 0.9;
# an anti-aliased binary mask has intermediate values on its one-pixel edge only.
SOFT_SHARE = 0.3
# Support of a soft mask (values above this are where the mark may be).
SOFT_SUPPORT = 0.02


@dataclasses.dataclass
class PreparedMask:
    """``prior``: (H, W) float in [0, 1] (1 = watermark); ``region``: its support (bool);
    ``soft``: a soft mask, whose support is the region; ``inverted``: the input was inverted;
    ``note``: what was decided, for the report (empty if nothing).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.maskprep import PreparedMask
    >>> p = PreparedMask(np.zeros((32, 48)), np.zeros((32, 48), bool), soft=False, inverted=False)
    >>> p.prior.shape, p.note
    ((32, 48), '')
    """

    prior: np.ndarray
    region: np.ndarray
    soft: bool
    inverted: bool
    note: str = ""


def mask_plane(mask) -> np.ndarray:
    """(H, W) float in [0, 1] from a grey, grey+alpha, RGB or RGBA mask array (uint8/uint16/float/bool).

    With an alpha channel that varies, the alpha channel is the mask (transparent = not marked);
    otherwise the brightest colour channel. Scaled so that its largest value is 1.

    Parameters
    ----------
    mask : array_like
        (H, W) or (H, W, C) mask image; bool, uint8, uint16 or float.

    Returns
    -------
    np.ndarray
        (H, W) float64 in [0, 1].

    Raises
    ------
    InputError
        For an empty mask, a mask of another rank, or non-finite values.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.maskprep import mask_plane
    >>> mk = np.zeros((32, 48), np.uint8); mk[10:20, 5:30] = 128
    >>> p = mask_plane(np.dstack([mk, mk, mk]))
    >>> p.shape, float(p.max()), float(p.sum())
    ((32, 48), 1.0, 250.0)
    """
    mk = np.asarray(mask)
    if mk.dtype == bool:
        mk = mk.astype(np.uint8)
    if mk.size == 0 or mk.ndim not in (2, 3):
        raise InputError(f"mask must be an (H, W) or (H, W, C) image with pixels; got shape {mk.shape}")
    scale = 255.0 if mk.dtype == np.uint8 else 65535.0 if mk.dtype == np.uint16 else 1.0
    if mk.dtype.kind == "f":
        from odnn_sep.errors import check_finite

        check_finite("mask", mk)
        scale = max(1.0, float(np.max(mk)))  # a 0/1 or 0/255 float mask
    if mk.ndim == 3:
        has_alpha = mk.shape[2] in (2, 4)
        a = mk[:, :, -1] if has_alpha else None
        colour = mk[:, :, :-1] if has_alpha else mk
        if a is not None and a.min() != a.max():
            mk = a
        else:
            mk = colour.max(axis=2)
    p = np.clip(mk.astype(np.float64) / scale, 0.0, 1.0)
    top = float(p.max())
    # a 0/1 integer mask, or a dim one, marks what is brightest in it
    return p / top if 0.0 < top < 1.0 else p


def prepare_mask(mask, shape: tuple[int, int], *, invert: bool | None = None) -> PreparedMask:
    """Check the mask against the image ``shape`` (H, W) and settle its polarity and kind.

    Parameters
    ----------
    mask : array, nonzero over the watermark (or, inverted, zero over it)
    shape : (H, W) of the image
    invert : True: the mask is black on white (invert it); False: use it as it is; None: decide
        from the marked share (more than ``INVERTED_SHARE`` of the image: inverted, with a warning)

    Returns
    -------
    PreparedMask
        The plane (1 = watermark), its region and what was decided.

    Raises
    ------
    InputError
        For a mask of another size, an empty or uniform mask, or one that marks no pixel or all of them.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.image.maskprep import prepare_mask
    >>> mk = np.zeros((32, 48), np.uint8); mk[10:20, 5:30] = 255
    >>> p = prepare_mask(mk, (32, 48))
    >>> p.soft, p.inverted, int(p.region.sum())
    (False, False, 250)
    >>> q = prepare_mask(255 - mk, (32, 48), invert=True)
    >>> q.inverted, bool((q.region == p.region).all())
    (True, True)
    """
    p = mask_plane(mask)
    H, W = shape
    if p.shape != (H, W):
        raise InputError(f"mask size {p.shape[1]}x{p.shape[0]} differs from the image size {W}x{H}; "
                         f"pass a mask of the same size as the image")
    if p.max() - p.min() < 1e-6:
        what = "empty (all zero)" if p.max() < 1e-6 else "uniform (the same value everywhere)"
        raise InputError(f"mask is {what}; mark the watermark's area with white on black")
    share = float(np.mean(p > 0.5))
    note = ""
    if invert is None and share > INVERTED_SHARE:
        invert = True
        note = (f"mask marks {100 * share:.0f}% of the image: read as inverted (black marks the watermark); "
                f"pass --mask-invert to say so, or --mask-as-is to keep it")
        log.warning(note)
    if invert:
        p = 1.0 - p
    soft_vals = (p > 0.1) & (p < 0.9)
    support = p > SOFT_SUPPORT
    soft = bool(soft_vals.sum() > SOFT_SHARE * max(int(support.sum()), 1))
    region = support if soft else p > 0.5
    if not region.any():
        raise InputError("mask marks no pixel after inversion; check its polarity (--mask-invert / --mask-as-is)")
    if region.all():
        raise InputError("mask marks the whole image; mark only the watermark's area")
    return PreparedMask(p, region, soft, bool(invert), note)
