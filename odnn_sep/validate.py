"""Cheap checks of command-line options, run before a command reads or computes anything.

Front-ends validate their own options too; these checks sit at the command boundary so that every
user-controlled size has a limit (:mod:`odnn_sep.limits`) and every nonsensical number gives one
clear line before any expensive work (a 2000-word ``--text`` must not be rendered first).
"""
from __future__ import annotations

import math

from odnn_sep import limits
from odnn_sep.errors import InputError, check_number


def _denoise(args) -> None:
    for flag, value, allow in (("--mains", args.mains, ("auto",)), ("--block-s", args.block_s, ("auto",)),
                               ("--max-hz", args.max_hz, ()), *(("--tone", t, ()) for t in args.tone or ())):
        if value is not None:
            check_number(flag, value, positive=True, allow=allow)
    h = str(args.harmonics).strip().lower()
    if h != "auto":
        parts = h.split(",")
        if not all(p.strip().isdigit() and int(p) >= 1 for p in parts):
            raise InputError(f"--harmonics must be auto, a count N >= 1, or a list of harmonic numbers such as "
                             f"1,3,5; got {args.harmonics!r}")
        top = max(int(p) for p in parts)
        limits.check("harmonics", top, f"--harmonics {args.harmonics!r}: the highest harmonic number")


def _text(text) -> None:
    if text is None:
        return
    if not text.strip():
        raise InputError("--text is empty; give the watermark's visible text")
    # line breaks separate the lines of a multi-line mark; other control characters are not text
    bad = sorted({repr(c) for c in text if (ord(c) < 32 and c not in "\n\r") or 0x7F <= ord(c) < 0xA0})
    if bad:
        raise InputError(f"--text contains control character(s) {', '.join(bad)}; give the watermark's visible "
                         "text (its lines separated by line breaks)")
    limits.check("text_chars", len(text), "--text length (characters)", hint="give the mark's visible text only")


def image_megapixels(path) -> float | None:
    """Pixel count of an image from its header, in millions (None if the header cannot be read).

    Only the header is read, so a huge image is judged before it is decoded.

    Parameters
    ----------
    path : str or path-like
        The image file.

    Returns
    -------
    float or None
        Width times height divided by 10**6, or None for a missing or unreadable file.

    Examples
    --------
    >>> import os, tempfile
    >>> from PIL import Image
    >>> with tempfile.TemporaryDirectory() as d:
    ...     Image.new("RGB", (2000, 500)).save(os.path.join(d, "a.png"))
    ...     image_megapixels(os.path.join(d, "a.png"))
    1.0
    >>> image_megapixels("no-such-image.png") is None
    True
    """
    import warnings

    try:
        from PIL import Image

        Image.MAX_IMAGE_PIXELS = None  # the size is judged here, against our own limit
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")  # a damaged header is reported by the image reader
            with Image.open(path) as im:
                w, h = im.size
    except Exception:  # noqa: BLE001 - any unreadable header: the image reader reports it properly
        return None
    return w * h / 1e6


def _unwatermark(args) -> None:
    _text(args.text)
    if args.min_score is not None and not math.isfinite(args.min_score):
        raise InputError(f"--min-score must be a finite number; got {args.min_score!r}")
    from odnn_sep.io_paths import check_input_path

    for flag, p in (("input image", args.input), ("--mask", args.mask)):
        if p is None:
            continue
        check_input_path(p, what=flag)  # never open a pipe or a device to read its header
        mp = image_megapixels(p)
        if mp is not None:
            limits.check("megapixels", mp, f"{flag} {str(p)!r} size in megapixels",
                         hint="crop or downscale the image first")


# Parameters that only make sense when positive, whatever the model.
POSITIVE_PARAMS = {"m": "a mass", "harmonics": "a count of harmonics", "alpha": "a diffusivity"}


def _mismatch(args) -> None:
    for flag in ("start", "duration"):
        v = getattr(args, flag)
        if v is not None and not math.isfinite(v):
            raise InputError(f"--{flag} must be a finite number of seconds; got {v!r}")
    if args.duration is not None and args.duration <= 0:
        raise InputError(f"--duration must be > 0 seconds; got {args.duration!r}")
    for item in args.param or ():
        name, _, value = str(item).partition("=")
        if not name.strip():
            raise InputError(f"--param expects NAME=VALUE; got {item!r}")
        if name.strip() == "sources" or not value.strip():
            continue
        try:
            v = float(value)
        except ValueError:
            raise InputError(f"--param {name.strip()} must be a number; got {value.strip()!r}") from None
        if not math.isfinite(v):
            raise InputError(f"--param {name.strip()} must be a finite number; got {value.strip()!r}")
        limits.check("magnitude", abs(v), f"--param {name.strip()}")
        if name.strip() in POSITIVE_PARAMS and v <= 0:
            raise InputError(f"--param {name.strip()} must be > 0 ({POSITIVE_PARAMS[name.strip()]}); got {value.strip()!r}")
    if args.effects is not None and not [e for e in args.effects.split(",") if e.strip()]:
        raise InputError(f"--effects {args.effects!r} names no effect; give a comma-separated list, or leave it out "
                         "to try every effect that applies")


def _simulate(args) -> None:
    # inf: noise-free data (the generators draw no noise), as make_dataset(snr_db=inf) allows
    if math.isnan(args.snr_db) or args.snr_db == -math.inf:
        raise InputError(f"--snr-db must be a number of dB, or inf for noise-free data; got {args.snr_db!r}")
    if math.isfinite(args.snr_db) and abs(args.snr_db) > 300:
        raise InputError(f"--snr-db {args.snr_db:g} is outside -300..300 dB")


CHECKS = {"denoise": _denoise, "unwatermark": _unwatermark, "mismatch": _mismatch, "simulate": _simulate}


def require_optional(module: str, extra: str, what: str) -> None:
    """One clear line when an optional dependency is missing, naming the extra that installs it.

    Parameters
    ----------
    module : str
        The module needed.
    extra : str
        The pip extra that installs it.
    what : str
        The option that needs it, for the message.

    Raises
    ------
    odnn_sep.errors.InputError
        When ``module`` is not installed.

    Examples
    --------
    >>> require_optional("json", "network", "--solver network")      # installed: nothing happens
    >>> require_optional("no_such_module_here", "dask", "--dask")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --dask needs no_such_module_here, which is not installed; install it with: pip install "odnn-sep[dask]"
    """
    import importlib.util

    if importlib.util.find_spec(module) is None:
        raise InputError(f"{what} needs {module}, which is not installed; install it with: "
                         f'pip install "odnn-sep[{extra}]"')


def validate(args) -> None:
    """Run the checks of ``args.command`` (nothing for commands without any).

    Also checks that the optional packages the options need (torch for ``--solver network``,
    distributed for ``--dask``) are installed.

    Parameters
    ----------
    args : argparse.Namespace
        The parsed command line, with ``command`` naming the subcommand.

    Raises
    ------
    odnn_sep.errors.InputError
        One line naming the first option that is out of range or needs a missing package.

    Examples
    --------
    >>> import argparse
    >>> validate(argparse.Namespace(command="simulate", snr_db=30.0))      # fine: nothing happens
    >>> validate(argparse.Namespace(command="simulate", snr_db=float("nan")))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --snr-db must be a number of dB, or inf for noise-free data; got nan
    """
    if getattr(args, "solver", None) == "network":
        require_optional("torch", "network", "--solver network")
    if getattr(args, "dask", None):
        require_optional("distributed", "dask", "--dask")
    check = CHECKS.get(args.command)
    if check is not None:
        check(args)
