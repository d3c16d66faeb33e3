"""Image front-end: remove visible text watermarks (``odnn-sep unwatermark``).

The watermark is the physics (glyph coverage rendered from the user's text and font, blended with
opacity ``alpha`` and colour ``c``); the photo is the disturbance, confined to be locally smooth
relative to glyph edges so that it cannot imitate the mark. Heavy imports happen lazily.
"""
from __future__ import annotations

__all__ = ["unwatermark", "UnwatermarkResult", "make_watermark_demo", "add_text_watermark", "read_image",
           "write_image"]


def __getattr__(name):
    if name in ("unwatermark", "UnwatermarkResult"):
        from odnn_sep.image import api

        return getattr(api, name)
    if name in ("make_watermark_demo", "add_text_watermark"):
        from odnn_sep.image import synth

        return getattr(synth, name)
    if name in ("read_image", "write_image"):
        from odnn_sep.image import io

        return getattr(io, name)
    raise AttributeError(f"module 'odnn_sep.image' has no attribute {name!r}")
