"""Matplotlib set-up shared by every command's ``--plot`` (headless backend, atomic PNG writes)."""
from __future__ import annotations


def pyplot():
    """Return matplotlib.pyplot on the non-interactive Agg backend (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=True)
    import matplotlib.pyplot as plt

    return plt


def save_figure(fig, out) -> None:
    """Write ``fig`` to ``out`` atomically and close it."""
    from odnn_sep.io_utils import atomic_output, check_output_path

    check_output_path(out)
    suffix = "." + str(out).rsplit(".", 1)[-1] if "." in str(out) else ".png"
    with atomic_output(out, suffix=suffix) as tmp:
        fig.savefig(tmp, dpi=110, bbox_inches="tight", format=suffix.lstrip(".") or "png")
    pyplot().close(fig)
