"""Matplotlib set-up shared by every command's ``--plot`` (headless backend, atomic PNG writes)."""
from __future__ import annotations


def pyplot():
    """Return matplotlib.pyplot on the non-interactive Agg backend (no display needed).

    Examples
    --------
    >>> pyplot().get_backend().lower()
    'agg'
    """
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, out) -> None:
    """Write ``fig`` to ``out`` atomically and close it.

    Examples
    --------
    >>> import os, tempfile
    >>> fig, ax = pyplot().subplots()
    >>> _ = ax.plot([0, 1], [1, 0])
    >>> out = os.path.join(tempfile.mkdtemp(), "line.png")
    >>> save_figure(fig, out)
    >>> open(out, "rb").read(4)
    b'\x89PNG'
    """
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output

    check_output_path(out)
    suffix = "." + str(out).rsplit(".", 1)[-1] if "." in str(out) else ".png"
    with atomic_output(out, suffix=suffix) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format=suffix.lstrip(".") or "png")
    pyplot().close(fig)
