"""``odnn-sep unwatermark``: the image front-end's subcommand (argparse only at import time)."""
from __future__ import annotations

import argparse

HELP = "remove a visible text watermark from an image (find it, estimate opacity and colour, invert the blend)"

DESCRIPTION = """\
Remove a visible, alpha-blended text watermark. The text is rendered with a TrueType font and
found in the image (position, size, rotation up to +-45 degrees, repeated copies); its opacity
and colour are estimated with the photo treated as a locally smooth disturbance that cannot
imitate sharp glyph edges. Without --font, the glyph coverage is then estimated from the image
around the rendering (another face, weight or spacing than the fonts tried). The blend is then
inverted, so the photo under the mark is recovered from the data rather than painted over. Only pixels whose data are really gone (nearly opaque
mark, clipping) are inpainted, and the report counts them. With --mask, the mark's shape is
estimated inside the marked area instead. Use it only on images you have the rights to.
"""

EXAMPLES = """\
examples:
  odnn-sep unwatermark photo.jpg --text "(c) ACME 2024" -o clean.png
  odnn-sep unwatermark photo.png --text "SAMPLE" --font DejaVuSans-Bold -o out.png --report r.json --plot p.png
  odnn-sep unwatermark photo.png --mask area.png -o out.png
  odnn-sep unwatermark photo.png --reference logo.png -o out.png

exit codes: 0 removed (the mark is no longer detected in the output); 3 the mark was found and inverted
but is still visible (the report's residual_mark says how much; no output unless --keep-partial);
1 not found or bad input; 2 bad usage
"""


# Exit code when the mark was found and inverted but is still visible in the output.
EXIT_MARK_VISIBLE = 3

# What to try when the mark is still visible, by mode (--font and --mask do not go with --reference).
ADVICE = {"text": "; try --font with the mark's font file, or --mask over the mark",
          "mask": "; try a mask that follows the mark's strokes more closely",
          "drawn": "; give --text with only the characters the mark shows",
          "reference": "; try a --reference image of the mark's own artwork (with its alpha channel), or --mask "
                       "over the mark instead of --reference"}


def register(subparsers) -> None:
    """Add the ``unwatermark`` subcommand and its options to ``subparsers``.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers()`` returned.

    Examples
    --------
    >>> import argparse
    >>> from odnn_sep.image import command
    >>> ap = argparse.ArgumentParser(); command.register(ap.add_subparsers())
    >>> a = ap.parse_args(["unwatermark", "in.png", "-o", "out.png", "--text", "SAMPLE", "--mask-as-is"])
    >>> a.text, a.output, a.mask_invert, a.func is command.run
    ('SAMPLE', 'out.png', False, True)
    """
    p = subparsers.add_parser("unwatermark", help=HELP, description=DESCRIPTION, epilog=EXAMPLES,
                              formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("input", metavar="IMG", help="input image (PNG, JPEG, TIFF, WebP; grey/RGB/RGBA; 8/16-bit)")
    p.add_argument("-o", "--output", metavar="OUT", required=True,
                   help="output image (format from its extension); never the input")
    p.add_argument("--text", default=None, help="the watermark's visible text; the lines of a mark of several lines "
                                                "separated by line breaks (e.g. $'Studio 2024\\nJohn Doe' in bash)")
    p.add_argument("--font", default=None, metavar="PATH|NAME",
                   help="font file or name (e.g. DejaVuSans-Bold); default: try the common fonts found")
    p.add_argument("--reference", default=None, metavar="LOGO.png",
                   help="a logo or watermark image you own (with or without alpha channel): found at any position, "
                        "scale 0.25-4x, rotation, single or tiled, and removed")
    p.add_argument("--mask", default=None, metavar="MASK.png",
                   help="image of the same size, nonzero over the watermark's area (rough box or stroke)")
    pol = p.add_mutually_exclusive_group()
    pol.add_argument("--mask-invert", dest="mask_invert", action="store_const", const=True, default=None,
                     help="the mask is black on white (black marks the watermark); default: a mask marking most "
                          "of the image is read as inverted, with a warning")
    pol.add_argument("--mask-as-is", dest="mask_invert", action="store_const", const=False,
                     help="use the mask's polarity as it is, even when it marks most of the image")
    p.add_argument("--report", metavar="R.json", help="write a JSON report (alpha, colour, box, angle, font, ...)")
    p.add_argument("--plot", metavar="P.png", help="write a figure: input, found mark, output, difference")
    p.add_argument("--min-score", type=float, default=None, metavar="S",
                   help="detection threshold on the match score, in (0, 2] (default 0.19; lower finds fainter marks and "
                        "risks false alarms on busy photos)")
    p.add_argument("--keep-partial", action="store_true",
                   help=f"write the output even when the mark is still visible after removal (exit code "
                        f"{EXIT_MARK_VISIBLE} all the same)")
    p.add_argument("--no-inpaint", action="store_true", help="leave lost pixels as inverted instead of inpainting")
    p.add_argument("--quiet", action="store_true", help="no summary line")
    p.set_defaults(func=run)


def run(args) -> int:
    """Run ``odnn-sep unwatermark`` on parsed arguments: read, remove the mark, write output and report.

    Parameters
    ----------
    args : argparse.Namespace
        The options :func:`register` defines.

    Returns
    -------
    int
        Exit code: 0 removed, ``EXIT_MARK_VISIBLE`` (3) found and inverted but still visible.

    Raises
    ------
    InputError
        Without ``--text``, ``--mask`` or ``--reference``, or with ``--reference`` and another mode.

    Examples
    --------
    >>> import argparse
    >>> from odnn_sep.image import command
    >>> ap = argparse.ArgumentParser(); command.register(ap.add_subparsers())
    >>> command.run(ap.parse_args(["unwatermark", "in.png", "-o", "out.png"]))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: give the watermark's text (--text) or a mask of its area (--mask), ...
    """

    from odnn_sep.errors import InputError
    from odnn_sep.image.io import read_image, read_image_meta, write_image
    from odnn_sep.io_utils import write_json

    if not args.text and not args.mask and not args.reference:
        raise InputError("give the watermark's text (--text) or a mask of its area (--mask), or a logo image "
                         "(--reference); got none")
    if args.reference and (args.text or args.mask):
        raise InputError("--reference is used on its own; drop --text/--mask")
    inp = _checked_paths(args)
    args.text = typed_line_breaks(args.text)
    _import_ahead(bool(args.text))
    img, meta = read_image_meta(inp)  # upright (EXIF orientation); EXIF/ICC/text written back
    from odnn_sep.image.api import unwatermark
    mask = read_image(args.mask, what="--mask image") if args.mask else None  # its size is checked by unwatermark
    if args.reference:
        _check_reference_size(args.reference, img.shape[:2])
    reference = read_image(args.reference, what="--reference image") if args.reference else None
    res = unwatermark(img, text=args.text, font=args.font, mask=mask,
                      min_score=args.min_score,  # None: the default threshold
                      inpaint_lost=not args.no_inpaint, mask_invert=args.mask_invert, reference=reference)
    residual = res.report.get("residual_mark") or {}
    visible = bool(residual.get("visible"))
    written = not visible or args.keep_partial
    if written:
        write_image(args.output, res.image, inp, meta=meta)
    report = {"input": str(inp), "output": str(args.output) if written else None,
              "outcome": "mark still visible" if visible else "removed", **res.report}
    if args.report:
        write_json(args.report, report)
    if args.plot:
        from odnn_sep.image.plot import plot_unwatermark

        plot_unwatermark(img, res, args.plot)
    if visible:
        import sys

        drawn = bool(residual.get("drawn"))
        print(("the removal drew letters the image does not show" if drawn else "mark still visible after removal")
              + f": {_residual_text(residual)}; "
              + (f"partial result written to {args.output}" if written else "no output written (--keep-partial "
                 "writes it)")
              + (ADVICE["drawn"] if drawn else ADVICE.get(report.get("mode"), ADVICE["text"])), file=sys.stderr)
        return EXIT_MARK_VISIBLE
    if not args.quiet:
        where = f"font {_font_text(report['font'])} {report['font_size_px']:.1f} px, angle " \
            f"{report['angle_deg']:.1f} deg, " if "font" in report else ""
        lines = f"{len(report['lines'])} lines, " if report.get("lines") else ""
        print(f"removed watermark: {lines}alpha {res.alpha:.3f}, colour {report.get('color_hex', report['color'])}, {where}"
              f"{report['lost_pixels']} lost pixel(s) inpainted, residual mark score "
              f"{float(residual.get('score') or 0.0):.3f} -> {args.output}")
    return 0


def typed_line_breaks(text):
    r"""``--text`` with the two characters backslash and ``n`` read as a line break, with a warning.

    In a shell, ``--text "Studio 2024\nJohn Doe"`` passes a backslash and an ``n`` (bash needs
    ``$'...'`` for a line break): the search then looked for one line with a backslash in it and
    reported "not found (best match score 0.000)". A watermark holding a backslash followed by ``n``
    is far less likely than that typing, so the pair is read as the line break meant. A text that
    already holds a real line break is left as it is.

    Examples
    --------
    >>> typed_line_breaks("Studio 2024\\nJohn Doe")
    'Studio 2024\nJohn Doe'
    >>> typed_line_breaks("A\\r\\nB"), typed_line_breaks("C:\\temp"), typed_line_breaks(None)
    ('A\nB', 'C:\\temp', None)
    """
    if not text or "\\n" not in text or "\n" in text or "\r" in text:
        return text
    import logging

    logging.getLogger(__name__).warning(
        "--text holds '\\n' typed as two characters: read as a line break (in bash, $'line 1\\nline 2' "
        "gives a real one)")
    return text.replace("\\r\\n", "\n").replace("\\n", "\n")


# What a run imports after reading its input (SciPy's optimisers and linear algebra among them).
_AHEAD = ("odnn_sep.image.api", "scipy.optimize")
_AHEAD_TEXT = ("odnn_sep.image.textmode", "odnn_sep.image.locate", "odnn_sep.image.register",
               "odnn_sep.image.screening", "odnn_sep.image.coverage", "odnn_sep.image.residual",
               "odnn_sep.image.residual_copies", "odnn_sep.image.residual_rims")


def _import_ahead(text: bool) -> None:
    """Import the modules the run needs on a second thread while the input is read and decoded.

    Decoding a large photo (a 12-megapixel PNG: about 0.3 s) lets go of the interpreter; importing
    (about 0.7 s) holds it: side by side, the command starts its work about 0.3 s sooner. An import
    that fails here fails again, with its message, where the run needs the module.
    """
    import importlib
    import threading

    def work():
        for name in _AHEAD + (_AHEAD_TEXT if text else ()):
            try:
                importlib.import_module(name)
            except Exception:  # noqa: BLE001 - reported where the run imports it itself
                return

    threading.Thread(target=work, name="odnn-sep-imports", daemon=True).start()


def _font_text(font) -> str:
    """The font's file name for the summary line, with its letter spacing or moved glyphs in words.

    Examples
    --------
    >>> from odnn_sep.image.command import _font_text
    >>> _font_text("/fonts/DejaVuSans.ttf@glyphs=0.01:0,0.2:0")
    'DejaVuSans.ttf (glyphs moved to the image)'
    >>> _font_text("/fonts/DejaVuSans.ttf@tracking=0.18")
    'DejaVuSans.ttf (letter-spaced 0.18 em)'
    """
    from pathlib import Path

    from odnn_sep.image.layout import split_layout
    from odnn_sep.image.render import split_tracking

    base, shifts = split_layout(font)
    base, tracking = split_tracking(base)
    name = Path(base).name
    if shifts is not None:
        return f"{name} (glyphs moved to the image)"
    return f"{name} (letter-spaced {tracking:g} em)" if tracking else name


def _checked_paths(args):
    """The input path, once the input, output, report and plot paths are checked (one-line errors)."""
    from pathlib import Path

    from odnn_sep.errors import InputError
    from odnn_sep.image.io import EXTENSIONS
    from odnn_sep.io_paths import check_input_path, check_output_path, check_run_paths

    inp = check_input_path(args.input, what="input image")
    # the logo and a font file are inputs too: a report or figure written over one destroyed it
    font_file = args.font if args.font and Path(args.font).is_file() else None
    check_run_paths({"the input": inp, "--mask": args.mask, "--reference": args.reference, "--font": font_file},
                    {"--output": args.output, "--report": args.report, "--plot": args.plot})
    if Path(args.output).suffix.lower() not in EXTENSIONS:
        raise InputError(f"output {args.output!r} must end in one of {', '.join(EXTENSIONS)}")
    check_output_path(args.output, inp, args.mask, args.reference)
    outs = {"--output": Path(args.output)}
    for flag, p in (("--report", args.report), ("--plot", args.plot)):
        if p:
            check_output_path(p, inp, args.mask)
            for other_flag, other in outs.items():
                if Path(p).resolve() == other.resolve():
                    raise InputError(f"{flag} path {p!r} is the same as {other_flag}; choose different paths")
            outs[flag] = Path(p)
    if args.plot and Path(args.plot).suffix.lower() not in (".png", ".pdf", ".svg", ".jpg", ".jpeg"):
        raise InputError(f"--plot path {args.plot!r} must end in .png, .pdf, .svg or .jpg")
    return inp


def _check_reference_size(path, photo_shape) -> None:
    """Refuse a --reference logo with more pixels than the photo from its header, before it is decoded.

    A logo must fit inside the photo (``logo.py`` checks its sides once decoded); a logo file whose
    header claims 15000x15000 pixels was decoded first (half a gigabyte) to be refused. The areas
    are compared, which an EXIF turn does not change.

    Examples
    --------
    >>> import os, tempfile
    >>> from PIL import Image
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.new("L", (400, 300)).save(os.path.join(d, "logo.png"))
    ...     _check_reference_size(os.path.join(d, "logo.png"), (240, 360))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --reference image '...logo.png' is 400x300, more pixels than the photo (360x240); crop ...
    """
    from odnn_sep.errors import InputError
    from odnn_sep.validate import image_megapixels

    mp = image_megapixels(path)  # header only; None when Pillow cannot read it (the decoder then reports)
    H, W = photo_shape
    if mp is not None and round(mp * 1e6) > H * W:
        from PIL import Image

        with Image.open(path) as im:
            w, h = im.size
        raise InputError(f"--reference image {str(path)!r} is {w}x{h}, more pixels than the photo ({W}x{H}); crop "
                         f"or scale the logo to at most the photo's size")


def _copies_text(copy: dict | None) -> str:
    """The clause on copies of the mark the removal left (``residual_copies.copies_left``), or "".

    Examples
    --------
    >>> _copies_text({"at": [302, -49], "score": 1.64, "contrast_levels": 81.1, "count": 2,
    ...               "positions": [[302, -49], [91, 340]]})[:80]
    '; 2 other copies of the mark left, at x 302, y -49; x 91, y 340 (cut by the bord'
    >>> _copies_text(None)
    ''
    """
    if not copy:
        return ""
    at = copy.get("positions") or [copy["at"]]
    n = copy.get("count", len(at))
    where = "; ".join(f"x {x}, y {y}" for x, y in at)
    what = "another copy of the mark left" if n == 1 else f"{n} other copies of the mark left"
    return (f"; {what}, at {where} (cut by the border or not found, top-left corners; best detection score "
            f"{copy['score']:.3f}, contrast {copy['contrast_levels']:.1f} grey levels; a tiled mark: give --mask "
            f"over every copy)")


def _residual_text(residual: dict) -> str:
    """One clause saying how much of the mark is left (text marks: edges and score; logos: edge correlation).

    Examples
    --------
    >>> _residual_text({"lines_not_found": ["John Doe"], "lines_still_visible": []})
    "line 'John Doe' not found (left as it was)"
    >>> _residual_text({"drawn": [{"at": (305.0, 120.0), "input_corr": -0.14, "output_corr": -0.85}]})[:45]
    'the part of the rendered text at x 305, y 120'
    """
    missing, left = residual.get("lines_not_found", []), residual.get("lines_still_visible", [])
    if missing or left:   # a text of several lines (textlines.py)
        parts = [f"line {t!r} not found (left as it was)" for t in missing]
        if left:
            rest = {k: v for k, v in residual.items() if k not in ("lines_not_found", "lines_still_visible")}
            parts.append(f"line {left[0]!r} still visible: {_residual_text(rest)}")
        return "; ".join(parts)
    drawn = residual.get("drawn")
    if drawn:  # parts of the text the input does not show (residual_drawn.py)
        x, y = drawn[0]["at"]
        more = f" and {len(drawn) - 1} more part(s)" if len(drawn) > 1 else ""
        return (f"the part of the rendered text at x {x:.0f}, y {y:.0f}{more} is not in the input (correlation "
                f"{drawn[0]['input_corr']:.2f}) and came out in the opposite colour (correlation "
                f"{drawn[0]['output_corr']:.2f}): --text has characters the mark does not have")
    if "edge_left" in residual:
        second = residual.get("second_colour")
        beside = (f"; a second colour (outline or shadow, {second['shape']}) left beside the letters at "
                  f"{second['contrast_levels']:.1f} grey levels, which one opacity and colour cannot remove"
                  if second else "")
        beside += _copies_text(residual.get("copies_left"))
        rims = (f", {residual['rim_levels']:.1f} grey levels of rims along the letters' contours "
                f"({100 * residual['rim_left']:.0f} % of the mark's)" if "rim_levels" in residual else "")
        return (f"{100 * residual['edge_left']:.0f} % of its edge energy left{rims}, detection score on the output "
                f"{residual['score']:.3f} (threshold {residual['threshold']:g}), contrast "
                f"{residual['contrast_levels']:.1f} grey levels{beside}")
    rims = (f", {residual['rim_levels']:.1f} grey levels of rims along its contours "
            f"({100 * residual['rim_left']:.0f} % of the logo's)" if "rim_levels" in residual else "")
    return (f"edge correlation with the registered logo {residual.get('score')}, "
            f"z {residual.get('z')} against chance{rims}")
