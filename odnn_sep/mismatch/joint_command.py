"""`odnn-sep mismatch` on several series (``--series COLUMN`` or several data files): the joint fit."""
from __future__ import annotations


def run_joint(args, params) -> int:
    """Read the series, fit them jointly (:func:`~odnn_sep.mismatch.joint.explain_joint`), print and write.

    Parameters
    ----------
    args : argparse.Namespace
        The subcommand's options (``data`` is a list of paths).
    params : dict
        ``--param`` values as strings.

    Returns
    -------
    int
        Exit status (0 on success).

    Examples
    --------
    >>> import argparse, os, tempfile
    >>> import numpy as np
    >>> from odnn_sep.mismatch.command import register
    >>> d = tempfile.mkdtemp(); path = os.path.join(d, "mugs.csv"); t = np.arange(0, 200, 10.0)
    >>> with open(path, "w") as fh:
    ...     _ = fh.write("t,mug,T\\n" + "".join(f"{x},{m},{21 + 70 * np.exp(-h * x):.4f}\\n"
    ...                                        for m, h in (("A", 0.02), ("B", 0.03)) for x in t))
    >>> parser = argparse.ArgumentParser(); register(parser.add_subparsers())
    >>> args = parser.parse_args(["mismatch", path, "--model", "cooling", "--series", "mug", "--quiet"])
    >>> run_joint(args, {})
    0
    """
    import sys

    from odnn_sep.mismatch.joint import explain_joint, joint_estimates
    from odnn_sep.mismatch.model import make_model
    from odnn_sep.mismatch.units import to_celsius

    series = _read(args)
    unit = ""
    if args.model == "cooling":
        notes = []
        for name, (t, y) in series.items():
            y, unit, note = to_celsius(y, args.units)
            series[name] = (t, y)
            notes.append(note)
        if any(notes):
            print(next(n for n in notes if n), file=sys.stderr)
    model = make_model(args.model, params)
    numeric = {k: v for k, v in model.start.items() if k in params and not isinstance(v, str)}
    shared = None if args.shared is None else [s.strip() for s in args.shared.split(",") if s.strip()]
    effects = None if args.effects is None else [e.strip() for e in args.effects.split(",") if e.strip()]
    res = explain_joint(args.model, series, params=numeric, shared=shared, effects=effects,
                        disturbance=args.disturbance, folds=args.folds, unit=unit,
                        progress=not args.quiet and sys.stderr.isatty(), despike=not args.keep_spikes)
    _write_outputs(args, res, joint_estimates(res), series)
    return 0


def _write_outputs(args, res, est, series):
    """The JSON report (with the joint estimates), the figure and the summary, as asked."""
    from odnn_sep.io_utils import write_json
    from odnn_sep.mismatch.joint import joint_text
    from odnn_sep.mismatch.report import plot, result_dict, summary_text
    if args.report:
        d = result_dict(res)
        d["joint"] = est
        d["input"] = {"paths": [str(p) for p in args.data], "series_column": args.series,
                      "series": {k: len(v[0]) for k, v in series.items()}}
        write_json(args.report, d)
    if args.plot:
        plot(res, args.plot)
    if not args.quiet:
        print(summary_text(res))
        print(joint_text(est))


def _read(args):
    """{series name: (t, y)} from one CSV with --series, or from one file per series."""
    from odnn_sep.errors import InputError
    from odnn_sep.mismatch.io import load_data
    from odnn_sep.mismatch.series_io import read_series_csv, read_series_files
    if args.input:
        raise InputError("--input is not available with joint series (--series or several files); fit each "
                         "driven series on its own")
    if args.series is None:
        return read_series_files(args.data, load=load_data, column=args.column, start=args.start,
                                 duration=args.duration)
    if len(args.data) != 1:
        raise InputError(f"--series reads one CSV file; got {len(args.data)} files (several files are "
                         f"already one series each: drop --series)")
    return _time_range(read_series_csv(args.data[0], args.series, args.column), args.start, args.duration)


def _time_range(series, start, duration):
    """Each series restricted to [start, start + duration] (seconds), as --start/--duration do."""
    if start is None and duration is None:
        return series
    out = {}
    for name, (t, y) in series.items():
        lo = t[0] if start is None else start
        keep = (t >= lo) & (t <= (lo + duration if duration is not None else t[-1]))
        out[name] = (t[keep], y[keep])
    return out
