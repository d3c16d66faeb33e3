"""`odnn-sep mismatch`: where a simulation and a recording disagree, and which physics is missing.

Imports only argparse at top level so `odnn-sep --help` stays fast.
"""
from __future__ import annotations


def register(subparsers) -> None:
    p = subparsers.add_parser(
        "mismatch", help="find where a simulation and data disagree and name the missing physics",
        description="Calibrate a model (preset) to the data, locate where the residual exceeds the noise, "
                    "try each effect of the physics vocabulary, and report the one the data support "
                    "(or that nothing is missing).")
    p.add_argument("data", help="CSV (header; first column time), WAV, or NPZ with x, y, z (2D fields)")
    p.add_argument("--model", required=True,
                   help="preset: oscillator, pendulum, cooling, hum, heat2d, freefall")
    p.add_argument("--param", action="append", default=[], metavar="NAME=VALUE",
                   help="starting guess for a model parameter (repeatable), e.g. --param k=4")
    p.add_argument("--column", default=None, help="CSV value column (name or index; default: the second); "
                                                  "WAV channel (default 0). With --model hum the file's "
                                                  "other channels (WAV channels, other numeric CSV columns) "
                                                  "are aux channels for the channel_coupling effect")
    p.add_argument("--no-aux", action="store_true",
                   help="analyse the channel alone: do not use the file's other channels (no channel_coupling)")
    p.add_argument("--start", type=float, default=None, help="use data from this time on (s)")
    p.add_argument("--duration", type=float, default=None, help="use this many seconds of data")
    p.add_argument("--effects", default=None,
                   help="comma-separated effects to consider (default: all that apply to the model)")
    p.add_argument("--disturbance", default="auto", choices=["auto", "slow", "none"],
                   help="class the disturbance is confined to (default: slow band for oscillatory models)")
    p.add_argument("--report", default=None, metavar="R.json", help="write the JSON report here")
    p.add_argument("--plot", default=None, metavar="P.png", help="write the figure here")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no summary on stdout")
    p.set_defaults(func=run)


def _parse_params(items):
    from odnn_sep.errors import InputError
    out = {}
    for it in items:
        if "=" not in it:
            raise InputError(f"--param expects NAME=VALUE; got {it!r}")
        k, v = it.split("=", 1)
        out[k.strip()] = v.strip()
    return out


def run(args) -> int:
    import sys

    from odnn_sep.io_utils import check_output_path, write_json
    from odnn_sep.mismatch.explain import explain
    from odnn_sep.mismatch.io import load_data
    from odnn_sep.mismatch.model import make_model
    from odnn_sep.mismatch.report import plot, result_dict, summary_text

    params = _parse_params(args.param)
    model = make_model(args.model, params)  # validates the model and parameter names before reading
    for out in (args.report, args.plot):
        if out is not None:
            check_output_path(out, args.data)
    t, y, info, aux = load_data(args.data, column=args.column, start=args.start, duration=args.duration,
                                with_aux=True)
    if args.no_aux or model.family != "hum":
        # other channels only enter through the hum preset's channel_coupling effect
        aux = {}
        info["aux_channels"] = []
    effects = None if args.effects is None else [e.strip() for e in args.effects.split(",") if e.strip()]
    numeric = {k: v for k, v in model.start.items() if k in params and not isinstance(v, str)}
    res = explain(model, t, y, params=numeric, effects=effects, disturbance=args.disturbance, aux=aux or None,
                  progress=not args.quiet and sys.stderr.isatty())
    if args.report:
        d = result_dict(res)
        d["input"] = {"path": str(args.data), **info}
        write_json(args.report, d)
    if args.plot:
        plot(res, args.plot)
    if not args.quiet:
        print(summary_text(res))
    return 0
