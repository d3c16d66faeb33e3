"""The options a batch hands to its command (after ``--``) that name an output file.

Every file of a batch runs with the same options, so ``-- --plot p.png`` had every file write the
same figure (the last one kept, the summary silent about it), ``-- -o x.wav`` sent every denoised
file to ``x.wav`` while the summary listed outputs in OUT_DIR that were never written, and
``-- --report r.json`` did the same to mismatch's per-file reports. Now a figure or a side report
is written per file beside its output in OUT_DIR, and the options that would replace the output the
batch names itself are refused before anything runs.
"""
from __future__ import annotations

from pathlib import Path

# option destinations that name a file the command writes
# (separate's -o is its parts CSV: a side output there, since its report is the batch's output)
_SIDE = {"plot": ("plot", ".png"), "report": ("report", ".json"), "output": ("parts", ".csv")}


def _command_options(target: str) -> dict:
    """Option string -> argparse action of ``odnn-sep TARGET``."""
    import argparse

    from odnn_sep.cli import build_parser

    parser = build_parser(target)
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return dict(sub.choices[target]._option_string_actions)


def _resolve(token: str, actions: dict):
    """(action, value attached to the token or None) of an option token, abbreviations included."""
    if token.startswith("--"):
        name, eq, value = token.partition("=")
        act = actions.get(name)
        if act is None:   # argparse takes an unambiguous prefix of a long option
            found = {id(a): a for s, a in actions.items() if s.startswith("--") and s.startswith(name)}
            act = next(iter(found.values())) if len(found) == 1 else None
        return act, (value if eq else None)
    if token.startswith("-") and len(token) >= 2 and token[:2] in actions:
        return actions[token[:2]], (token[2:].lstrip("=") or None) if len(token) > 2 else None
    return None, None


def per_file_options(target: str, extra: list[str], dsts, *, own_output: str) -> tuple[list[list[str]], list]:
    """Each file's options: a ``--plot`` or ``--report`` path made that file's own, beside its output.

    Parameters
    ----------
    target : str
        ``"denoise"``, ``"unwatermark"``, ``"mismatch"`` or ``"separate"``.
    extra : list of str
        The options after ``--``.
    dsts : list of pathlib.Path
        Each file's output (planned by :func:`odnn_sep.batch.plan_outputs`).
    own_output : str
        The option the batch gives each file its output with (``"-o"``, or ``"--report"`` for mismatch and
        separate).

    Returns
    -------
    options : list of list of str
        The options for each file, in the order of ``dsts``.
    side : list of pathlib.Path
        The figures and reports these options write (to be checked against inputs and outputs).

    Raises
    ------
    odnn_sep.errors.InputError
        For an option that would replace the output the batch names for each file.

    Examples
    --------
    >>> from pathlib import Path
    >>> opts, side = per_file_options("mismatch", ["--model", "cooling", "--plot", "fig.png"],
    ...                               [Path("out/a.json"), Path("out/b.csv.json")], own_output="--report")
    >>> opts[1], [str(p) for p in side]
    (['--model', 'cooling', '--plot', 'out/b.csv.plot.png'], ['out/a.plot.png', 'out/b.csv.plot.png'])
    >>> opts, side = per_file_options("separate", ["--basis", "x", "-o", "parts.csv"], [Path("out/a.json")],
    ...                               own_output="--report")
    >>> opts[0]
    ['--basis', 'x', '--output', 'out/a.parts.csv']
    >>> per_file_options("denoise", ["-o", "clean.wav"], [Path("out/a.wav")], own_output="-o")
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: '-o clean.wav' after -- would send every file's output to one path; batch writes each file's output to OUT_DIR itself: remove it
    """
    from odnn_sep.errors import InputError

    actions = _command_options(target)
    own = actions[own_output]
    plain: list[str] = []
    side_opts: list[tuple[str, str, str]] = []      # (option, kind, extension)
    k = 0
    while k < len(extra):
        token = extra[k]
        act, value = _resolve(token, actions)
        if act is None or not act.option_strings or (act is not own and act.dest not in _SIDE):
            plain.append(token)
            k += 1
            continue
        given = token
        if value is None and k + 1 == len(extra):
            plain.append(token)     # no value: the command's own parser says so
            k += 1
            continue
        if value is None:
            value = extra[k + 1]
            given = f"{token} {value}"
            k += 1
        k += 1
        if act is own or (act.dest == "output" and own.dest == "output"):
            raise InputError(f"{given!r} after -- would send every file's output to one path; batch writes each "
                             "file's output to OUT_DIR itself: remove it")
        kind, default = _SIDE[act.dest]
        side_opts.append((act.option_strings[-1], kind, Path(value).suffix or default))
    options, side = [], []
    for d in dsts:
        base = d.with_suffix("") if own_output == "--report" else d    # mismatch, separate: d is the own .json
        mine = list(plain)
        for opt, kind, ext in side_opts:
            path = base.parent / f"{base.name}.{kind}{ext}"
            mine += [opt, str(path)]
            side.append(path)
        options.append(mine)
    return options, side
