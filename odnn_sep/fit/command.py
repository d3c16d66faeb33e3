"""``odnn-sep separate``: identify physics coefficients in a 1-D signal or 2-D field."""
from __future__ import annotations


def register(sub) -> None:
    """Add the ``separate`` subcommand to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``odnn-sep`` parser (``parser.add_subparsers()``).

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["separate", "data.csv", "--basis", "sin(5*x)", "--disturbance", "even"])
    >>> args.basis, args.disturbance, args.solver
    (['sin(5*x)'], 'even', 'exact')
    >>> args.func is run
    True
    """
    p = sub.add_parser(
        "separate",
        help="fit known physics terms to a 1-D signal (CSV) or 2-D field (.npz) with a constrained disturbance",
        description="Model DATA as sum_j theta_j f_j + g + noise, with the basis f_j written as expressions in the "
        "coordinates (x, or x and y for .npz fields) and g confined to a class that cannot imitate them. "
        "Prints theta with 95% intervals (identified sets for convex/monotone classes).",
        epilog="example: odnn-sep separate data.csv --basis 'x**2*sin(5*x)' --disturbance even",
    )
    p.add_argument("data", help="CSV (header; first column x) or .npz with x, y, z")
    p.add_argument("--basis", action="append", required=True, metavar="EXPR",
                   help="a physics term, e.g. 'sin(5*x)' (repeat for several)")
    p.add_argument("--name", action="append", help="names for the --basis terms, in order")
    p.add_argument("--disturbance", default="orthogonal",
                   help="orthogonal | even[:center] | periodic:PERIOD | band:LO:HI | convex | monotone[:dec] "
                   "(default: orthogonal)")
    p.add_argument("--column", help="value column of a CSV: a header name, or an index counted from 0 where 0 is "
                   "x (default 1, the second column); the same rule as mismatch")
    p.add_argument("--x-column", metavar="COLUMN", help="coordinate column of a CSV, a header name or an index from "
                   "0 (default: the first); --column then defaults to the first other column")
    p.add_argument("--solver", choices=["exact", "network"], default="exact",
                   help="exact projection (default, milliseconds) or the paper's constrained network (torch, the "
                        "'network' extra): 1500 Adam epochs plus L-BFGS, seconds for 1000 points on one "
                        "core, with a progress bar")
    p.add_argument("--seed", type=int, default=0, help="random seed for the network solver")
    p.add_argument("-o", "--output", help="CSV with x, y, physics, disturbance, residual")
    p.add_argument("--report", help="JSON report path")
    p.add_argument("--plot", help="figure path (PNG): data, physics with its 95%% interval band, disturbance, "
                   "residual")
    p.add_argument("--quiet", action="store_true", help="no summary on stdout (warnings still go to stderr)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Fit the ``--basis`` terms to ``args.data``; print the summary and write the requested outputs.

    Parameters
    ----------
    args : argparse.Namespace
        Options of ``odnn-sep separate`` (see :func:`register`).

    Returns
    -------
    int
        The exit code, 0.

    Raises
    ------
    odnn_sep.errors.InputError
        On inconsistent options or an unreadable data file.

    Examples
    --------
    >>> import argparse, os, tempfile
    >>> import numpy as np
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     x = np.linspace(-1, 1, 41)
    ...     np.savetxt(os.path.join(d, "data.csv"), np.c_[x, 2 * np.sin(5 * x) + x**2], delimiter=",",
    ...                header="x,y", comments="")
    ...     args = parser.parse_args(["separate", os.path.join(d, "data.csv"), "--basis", "sin(5*x)",
    ...                               "--disturbance", "even", "--quiet", "-o", os.path.join(d, "parts.csv")])
    ...     code = run(args)
    ...     parts = np.genfromtxt(os.path.join(d, "parts.csv"), delimiter=",", names=True)
    >>> code, parts.dtype.names[:3], len(parts)
    (0, ('x', 'y', 'physics'), 41)
    >>> bool(np.allclose(parts["physics"], 2 * np.sin(5 * x), atol=1e-8))  # the even x**2 is set apart
    True
    """
    import sys
    import warnings

    from odnn_sep.core import Separator
    from odnn_sep.core.solvers import NetworkSolver
    from odnn_sep.errors import InputError
    from odnn_sep.fit.data import copied_rows, load_signal, write_components
    from odnn_sep.fit.expr import basis_from_expressions, parse_disturbance
    from odnn_sep.fit.residual import residual_warning
    from odnn_sep.fit.size import check_shape_points
    from odnn_sep.io_utils import write_json

    if args.name and len(args.name) != len(args.basis):
        raise InputError(f"{len(args.name)} --name value(s) for {len(args.basis)} --basis term(s); give one each")
    if args.name and not all(str(n).strip() for n in args.name):
        # a blank name printed an unlabelled line and keyed the report's parameter by ''
        raise InputError(f"--name {args.name[[str(n).strip() for n in args.name].index('')]!r} is blank; name each "
                         "--basis term, or leave --name out to name the terms by their expressions")
    if args.plot and not str(args.plot).lower().endswith((".png", ".pdf", ".svg", ".jpg", ".jpeg")):
        raise InputError(f"--plot path {args.plot!r} must end in .png, .pdf, .svg or .jpg")
    if args.seed < 0:
        raise InputError(f"--seed must be >= 0; got {args.seed}")
    value_name: list = []
    x, y, coords, grid = load_signal(args.data, args.column, value_name=value_name, x_column=args.x_column)
    # a record pasted twice: refused; copies spread out: a warning (see copied_rows)
    copies = copied_rows(args.data, x, y) if grid is None else None
    basis = basis_from_expressions(args.basis, coords, args.name)
    dist = parse_disturbance(args.disturbance, ndim=len(coords))
    # (the network solver's intervals come from the exact analysis too: the bound holds for both)
    check_shape_points(dist, len(y), args.disturbance)
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        # the network trains for minutes: show its epochs unless asked to be quiet
        solver = NetworkSolver(progress=not args.quiet) if args.solver == "network" else args.solver
        res = Separator(basis, disturbance=dist, solver=solver, random_state=args.seed).fit(x, y).result_
    messages = [str(w.message) for w in caught] + ([copies] if copies else [])
    if res.diagnostics.get("dof") == 0:
        # the fit is exact: every point went to the physics or the class, none is left to see the noise
        messages.append(f"no interval: the {len(y)} points are all taken by the {len(args.basis)} basis term(s) and "
                        f"the {res.disturbance_class} class (rank {res.diagnostics.get('disturbance_rank')}), so "
                        "no point is left to estimate the noise; use more points")
    # a class that cannot hold the disturbance (or correlated noise) leaves a smooth residual and
    # confidently wrong intervals: say so
    structure = residual_warning(x, y, res.residual, res.disturbance_class, grid)
    if structure:
        messages.append(structure)
    if not args.quiet:
        print(res.summary())
    for m in messages:  # warnings go to stderr, also with --quiet
        print(f"Warning: {m}", file=sys.stderr)
    if args.output:
        write_components(args.output, x, y, res)
    if args.report:
        write_json(args.report, {"input": args.data, "basis": args.basis, "disturbance": args.disturbance,
                                 **res.as_dict(), "warnings": messages})
    if args.plot:
        from odnn_sep.report.separation import plot_separation

        F = basis.evaluate(x) if not getattr(basis, "phi_names", ()) else None
        plot_separation(x, y, res, grid, args.plot, F=F, x_name=coords[0] if len(coords) == 1 else "x",
                        y_name=value_name[0] if value_name else "value")
    return 0
