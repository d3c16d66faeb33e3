"""`odnn-sep mismatch`: where a simulation and a recording disagree, and which physics is missing.

Imports only argparse at top level so `odnn-sep --help` stays fast.
"""
from __future__ import annotations


def register(subparsers) -> None:
    """Add the ``mismatch`` subcommand and its options to an argparse ``subparsers`` object.

    Parameters
    ----------
    subparsers : argparse._SubParsersAction
        What ``ArgumentParser.add_subparsers()`` returned.

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["mismatch", "run.csv", "--model", "cooling", "--param", "h=0.1"])
    >>> args.command, args.model, args.param, args.disturbance, args.data
    ('mismatch', 'cooling', ['h=0.1'], 'auto', ['run.csv'])
    """
    p = subparsers.add_parser(
        "mismatch", help="find where a simulation and data disagree and name the missing physics",
        description="Calibrate a model (preset) to the data, locate where the residual exceeds the noise, "
                    "try each effect of the physics vocabulary, and report the one the data support "
                    "(or that nothing is missing).")
    p.add_argument("data", nargs="+",
                   help="CSV (header; first column time), WAV, or NPZ with x, y, z (2D fields); several files are "
                        "several series of one system, fitted jointly")
    p.add_argument("--model", required=True,
                   help="preset: oscillator, pendulum, cooling, hum, heat2d, freefall. heat2d options: "
                        "--param continuous=1 (sources with constant power), --param ambient=1 (a fitted "
                        "ambient level T_amb); an NPZ with z (frames, ny, nx) and t (frame times) is fitted "
                        "over every frame")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="starting guess for a model parameter (repeatable), e.g. --param k=4")
    p.add_argument("--column", default=None, help="CSV value column (name or index; default: the second); "
                                                  "WAV channel (default 0). With --model hum the file's "
                                                  "other channels (WAV channels, other numeric CSV columns) "
                                                  "are aux channels for the channel_coupling effect")
    p.add_argument("--no-aux", action="store_true",
                   help="analyse the channel alone: do not use the file's other channels (no channel_coupling)")
    p.add_argument("--start", type=float, default=None,
                   help="use data from this time on (in the unit of the time column; seconds for WAV)")
    p.add_argument("--duration", type=float, default=None,
                   help="use this much time of data (in the unit of the time column; seconds for WAV)")
    p.add_argument("--effects", default=None,
                   help="comma-separated effects to consider (default: all that apply to the model)")
    p.add_argument("--disturbance", default="auto", metavar="KINDS",
                   help="known disturbances, comma-separated: auto (default: slow band for oscillatory "
                        "models), slow, none, periodic:HZ (a known line), lines (every significant line of "
                        "the residual). What is declared is absorbed and never named")
    p.add_argument("--keep-spikes", action="store_true",
                   help="do not repair isolated outliers: by default single samples more than 5 noise levels "
                        "off their neighbours' residual are replaced by that median before any effect is "
                        "tested, and reported")
    p.add_argument("--input", action="append", default=[], metavar="COLUMN",
                   help="measured input column (repeatable) driving the model: oscillator/pendulum "
                        "m x'' + c x' + k x = kd u(t); cooling dT/dt = -h (T - T_amb) + kd u(t)")
    p.add_argument("--units", default=None, choices=["degC", "degF", "K", "deg", "rad"],
                   help="unit of the data where the physics depends on it: temperatures (cooling; degF and K "
                        "are converted to degC for the vapour pressure and radiation, the report gives degC) "
                        "or angles (pendulum; deg is converted to rad for sin(theta), the report gives rad)")
    p.add_argument("--folds", type=int, default=4,
                   help="cross-validation folds of the held-out test (>= 2; default 4); fewer folds let short "
                        "series (16 points) be analysed, with less power")
    _add_shape_options(p)
    p.add_argument("--report", default=None, metavar="R.json", help="write the JSON report here")
    p.add_argument("--plot", default=None, metavar="P.png", help="write the figure here")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary on stdout")
    p.set_defaults(func=run)


def _add_shape_options(p):
    """Options of the data's shape: several series fitted jointly."""
    p.add_argument("--series", default=None, metavar="COLUMN",
                   help="CSV column naming the series (e.g. one mug per value): the series are fitted jointly, "
                        "some parameters shared (cooling: T_ambient; freefall: g; oscillator: k, c; pendulum: "
                        "w2, c), the others per series; at most 50 series")
    p.add_argument("--shared", default=None, metavar="NAMES",
                   help="comma-separated parameters shared by every series of a joint fit (overrides the "
                        "preset's default)")


def _parse_params(items):
    from odnn_sep.errors import InputError
    out = {}
    for it in items:
        if "=" not in it:
            raise InputError(f"--param expects NAME=VALUE; got {it!r}")
        k, v = it.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def _pick_inputs(names, columns, info):
    """{name: values} for each --input column (CSV header name or WAV channel ch<k>); clear errors."""
    from odnn_sep.errors import InputError
    out = {}
    for name in names:
        if name == info.get("column"):
            raise InputError(f"--input {name!r} is the analysed column itself; pick the drive's own column")
        bad = info.get("not_numeric", {}).get(name)
        if name not in columns and bad:
            raise InputError(f"--input {name!r} has a missing or non-numeric value at {bad}; an input needs a "
                             f"number on every row: fill that cell or drop the row")
        if name not in columns:
            import difflib
            close = difflib.get_close_matches(name, list(columns), n=1)
            hint = f"did you mean {close[0]!r}? " if close else ""
            raise InputError(f"--input {name!r} is not a numeric column of the data file; {hint}"
                             f"other columns: {', '.join(columns) or 'none'}")
        out[name] = columns[name]
    return out


def _checked_options(args):
    """(params, model) once every option is checked, before anything is read (clear one-line errors)."""
    from odnn_sep.errors import InputError
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.mismatch.disturbances import parse_disturbance
    from odnn_sep.mismatch.model import make_model
    params = _parse_params(args.param)
    parse_disturbance(args.disturbance)
    if not 2 <= args.folds <= 20:
        raise InputError(f"--folds must be between 2 and 20 (cross-validation folds); got {args.folds}")
    model = make_model(args.model, params)  # validates the model and parameter names
    if args.units in ("degC", "degF", "K") and model.family != "cooling":
        raise InputError(f"--units {args.units} is for temperatures (--model cooling); model {args.model!r} has no "
                         f"temperature physics")
    if args.units in ("deg", "rad") and (model.family != "pendulum" or float(model.start.get("L", 0.0)) > 0):
        raise InputError(f"--units {args.units} is for angle records (--model pendulum without L); "
                         + ("with L given the record is a tangential acceleration, in m/s^2"
                            if model.family == "pendulum" else f"model {args.model!r} has no angle physics"))
    for out in (args.report, args.plot):
        if out is not None:
            for path in args.data:
                check_output_path(out, path)
    return params, model


def _frame_params(args, params, model, info):
    """Several frames of a field: the file gives the frame times (see presets_heat2d)."""
    from odnn_sep.errors import InputError
    from odnn_sep.mismatch.model import make_model
    if model.family != "heat2d":
        raise InputError(f"{args.data!r} holds {info['frames']} frames of a field; use --model heat2d")
    params = {**params, "t": info["frame_t0"], "frame_dt": info["frame_dt"], "frame_dx": info["frame_dx"]}
    return params, make_model(args.model, params)


def _load_series(args, params, model):
    """The data of one file with its aux channels, inputs and temperature unit (degC for the physics)."""
    import os
    import sys

    from odnn_sep.mismatch.io import load_data
    from odnn_sep.mismatch.units import to_celsius, to_radians
    t, y, info, aux = load_data(args.data, column=args.column, start=args.start, duration=args.duration,
                                with_aux=True)
    if info.get("frames"):
        params, model = _frame_params(args, params, model, info)
    if "row_index_column" in info and not args.quiet:
        print(f"Note: the first column ({info['row_index_column']!r}) counts the rows (a table's index): left out; "
              f"time is column {info['time']!r}", file=sys.stderr)
    if info.get("read_as") and not args.quiet:
        print(f"Note: {os.path.basename(str(args.data))} {info['read_as']}", file=sys.stderr)
    if info.get("time_origin") and not args.quiet:
        print(f"Note: column {info['time']!r} holds date-times: time is in seconds since {info['time_origin']}",
              file=sys.stderr)
    inputs = _pick_inputs(args.input, aux, info)
    info.pop("not_numeric", None)      # (only for the message above; the report lists the columns used)
    if args.no_aux or model.family != "hum":
        # other channels only enter through the hum preset's channel_coupling effect
        aux = {}
        info["aux_channels"] = []
    unit = ""
    note = None
    if model.family == "cooling":
        y, unit, note = to_celsius(y, args.units)
    elif model.family == "pendulum" and float(model.start.get("L", 0.0)) <= 0:
        y, unit, note = to_radians(y, args.units)
    if note:
        print(note, file=sys.stderr)
    return t, y, info, aux, inputs, unit, params, model


def _explain_target(args, params, model, inputs, info):
    """What explain() is given: the model (or its preset name when inputs drive it) and the numeric starts."""
    numeric = {k: v for k, v in model.start.items() if k in params and not isinstance(v, str)}
    if not inputs:
        return model, numeric
    # a driven preset is built inside explain (its gains kd_<column> join the parameters)
    structural = {k: v for k, v in params.items() if k in ("harmonics", "sources")}
    info["inputs"] = list(inputs)
    return args.model, {**numeric, **structural}


def run(args) -> int:
    """Run ``odnn-sep mismatch``: load the data, explain the mismatch, print and write the report.

    Parameters
    ----------
    args : argparse.Namespace
        Parsed options of the subcommand (see :func:`register`).

    Returns
    -------
    int
        Exit status (0 on success).

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["mismatch", "run.csv", "--model", "freefall", "--effects", "quadratic_drag"])
    >>> args.data, args.effects, callable(run)
    (['run.csv'], 'quadratic_drag', True)
    """
    import sys

    from odnn_sep.io_utils import write_json
    from odnn_sep.mismatch.explain import explain
    from odnn_sep.mismatch.report import plot, result_dict, summary_text

    params, model = _checked_options(args)
    if args.series is not None or len(args.data) > 1 or args.shared is not None:
        from odnn_sep.mismatch.joint_command import run_joint
        return run_joint(args, params)
    args.data = args.data[0]
    t, y, info, aux, inputs, unit, params, model = _load_series(args, params, model)
    effects = None if args.effects is None else [e.strip() for e in args.effects.split(",") if e.strip()]
    target, numeric = _explain_target(args, params, model, inputs, info)
    res = explain(target, t, y, params=numeric, effects=effects, disturbance=args.disturbance,
                  aux=aux or None, inputs=inputs or None, unit=unit, folds=args.folds,
                  progress=not args.quiet and sys.stderr.isatty(), despike=not args.keep_spikes)
    if args.report:
        d = result_dict(res)
        d["input"] = {"path": str(args.data), **info}
        write_json(args.report, d)
    if args.plot:
        plot(res, args.plot)
    if not args.quiet:
        print(summary_text(res))
    return 0
