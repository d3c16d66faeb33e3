"""``--plot`` figure for unwatermark: input, found mark, output, difference."""
from __future__ import annotations

import numpy as np

# Height of the figure's panels (inches; the figure is 10 inches wide) for the thinnest and tallest images.
MIN_HEIGHT_IN = 2.5
MAX_HEIGHT_IN = 30.0


def _show(img):
    a = np.asarray(img)
    if a.dtype.kind == "u":
        a = a.astype(float) / np.iinfo(a.dtype).max
    if a.ndim == 3 and a.shape[2] == 4:
        a = a[:, :, :3]
    elif a.ndim == 3 and a.shape[2] == 2:
        a = a[:, :, 0]  # grey+alpha: the grey plane (matplotlib draws no two-channel image)
    return a


def plot_unwatermark(image, res, out) -> None:
    """Write a 2x2 figure: input, found mark coverage (with opacity), restored output, |difference|.

    Parameters
    ----------
    image : np.ndarray
        The input image (uint or float in [0, 1]; grey, RGB or RGBA).
    res : UnwatermarkResult
        What :func:`odnn_sep.image.unwatermark` returned for ``image``.
    out : str or Path
        Figure file to write.

    Examples
    --------
    >>> import os, tempfile
    >>> from types import SimpleNamespace
    >>> img = np.full((24, 32), 0.5)
    >>> res = SimpleNamespace(image=img, alpha=0.4, mask=np.zeros((24, 32)), report={})
    >>> with tempfile.TemporaryDirectory() as d:
    ...     plot_unwatermark(img, res, os.path.join(d, "mark.png"))
    ...     os.path.getsize(os.path.join(d, "mark.png")) > 5_000
    True
    """
    from odnn_sep.report.figures import pyplot, save_figure

    plt = pyplot()
    a, b = _show(image), _show(res.image)
    diff = np.abs(b - a)
    if diff.ndim == 3:
        diff = diff.max(axis=2)
    # the panels follow the image's shape within bounds: a 60 x 3000 px strip made a 54000 px tall
    # figure (1.7 GB, 13 s)
    tall = min(max(10 * a.shape[0] / max(a.shape[1], 1), MIN_HEIGHT_IN), MAX_HEIGHT_IN)
    fig, ax = plt.subplots(2, 2, figsize=(10, tall + 0.8))
    cm = "gray" if a.ndim == 2 else None
    ax[0, 0].imshow(a, cmap=cm, vmin=0, vmax=1)
    ax[0, 0].set_title("input")
    ax[0, 1].imshow(res.alpha * res.mask, cmap="magma", vmin=0, vmax=1)
    r = res.report
    title = f"found mark: alpha {res.alpha:.3f}"
    if "match_score" in r:
        title += f", score {r['match_score']:.2f}"
    if "font_size_px" in r:  # text mode only (mask mode has a match score and no font)
        title += f", {r['font_size_px']:.1f} px, {r['angle_deg']:.1f} deg"
    ax[0, 1].set_title(title, fontsize=9)
    ax[1, 0].imshow(b, cmap=cm, vmin=0, vmax=1)
    ax[1, 0].set_title(f"output ({r.get('lost_pixels', 0)} lost pixels inpainted)")
    ax[1, 1].imshow(diff, cmap="viridis")
    ax[1, 1].set_title("|output - input|")
    for x in ax.ravel():
        x.set_axis_off()
    fig.tight_layout()
    save_figure(fig, out)
