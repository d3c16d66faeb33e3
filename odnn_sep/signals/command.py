"""``odnn-sep simulate``: write a synthetic dataset with known truth (for trying ``odnn-sep separate``)."""
from __future__ import annotations

# Basis/disturbance options for `odnn-sep separate` that match each 1-D linear dataset.
SEPARATE_HINTS = {
    "figure2": "--basis 'x**2*sin(5*x)' --disturbance even",
    "implicit_symmetric": "--basis 'x**2*sin(5*x)' --disturbance even",
    "implicit_periodic": "--basis 'x*sin(5*x)' --disturbance periodic:{period}",
    "implicit_convex": "--basis 'sin(5*x)' --disturbance convex",
    "implicit_monotone": "--basis 'sin(5*x)' --disturbance monotone",
    "population": "--basis 'x' --disturbance periodic:1",
}


def register(sub) -> None:
    """Add the ``simulate`` subcommand to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``odnn-sep`` parser (``parser.add_subparsers()``).

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["simulate", "figure2", "-o", "fig2.csv", "--seed", "3"])
    >>> args.dataset, args.output, args.seed, args.snr_db
    ('figure2', 'fig2.csv', 3, 30.0)
    >>> args.func is run
    True
    """
    from odnn_sep.signals import NAMES, SYSTEMS

    NAMES = NAMES + SYSTEMS  # noqa: N806

    p = sub.add_parser(
        "simulate",
        help="write a synthetic dataset with known truth (the paper's cases) to CSV or .npz",
        description="Generate one of the synthetic datasets (known physics + disturbance in a stated class + "
        "Gaussian noise at SNR_DB relative to the physics) and write it with its truth. 1-D cases: CSV with "
        "columns x, y, physics, disturbance, noise; 2-D cases: .npz with x (nx,), y (ny,), z (ny, nx) and the "
        "true parts. The true parameters go to --truth (JSON) and are printed.",
        epilog="example: odnn-sep simulate figure2 -o fig2.csv --seed 0 && "
        "odnn-sep separate fig2.csv --basis 'x**2*sin(5*x)' --disturbance even",
    )
    p.add_argument("dataset", choices=NAMES, metavar="DATASET", help="one of: " + ", ".join(NAMES))
    p.add_argument("-o", "--output", required=True, help="output file (.csv for 1-D cases, .npz for 2-D)")
    p.add_argument("--truth", help="JSON file for the true parameters and the description")
    p.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    p.add_argument("--snr-db", type=float, default=30.0, help="physics-to-noise power ratio in dB (default 30; "
                   "inf: no noise)")
    p.set_defaults(func=run)


def run(args) -> int:
    """Write dataset ``args.dataset`` to ``args.output`` (and its truth to ``args.truth``); print the truth.

    Parameters
    ----------
    args : argparse.Namespace
        Options of ``odnn-sep simulate`` (see :func:`register`); ``quiet`` silences the printout.

    Returns
    -------
    int
        The exit code, 0.

    Raises
    ------
    odnn_sep.errors.InputError
        On a negative seed, an output of the wrong kind (.csv for 1-D cases, .npz for 2-D and
        engineering systems) or a ``--truth`` path equal to the output.

    Examples
    --------
    >>> import argparse, json, os, tempfile
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     args = parser.parse_args(["simulate", "figure2", "-o", os.path.join(d, "fig2.csv"),
    ...                               "--truth", os.path.join(d, "truth.json")])
    ...     code = run(args)
    ...     with open(os.path.join(d, "fig2.csv")) as fh:
    ...         header = fh.readline().strip()
    ...     with open(os.path.join(d, "truth.json")) as fh:
    ...         truth = json.load(fh)
    ...
    Figure 2: y = theta x^2 sin 5x + cos x; class Even(0)
    true parameters: theta = 0.727721
    try: odnn-sep separate ...fig2.csv --basis 'x**2*sin(5*x)' --disturbance even
    >>> code, header, truth["dataset"], truth["seed"]
    (0, 'x,y,physics,disturbance,noise', 'figure2', 0)
    """
    from pathlib import Path

    import numpy as np

    from odnn_sep.errors import InputError
    from odnn_sep.io_paths import check_output_path
    from odnn_sep.io_utils import atomic_output, write_json
    from odnn_sep.signals import make_dataset

    out = Path(args.output)
    check_output_path(out)
    if args.truth:
        check_output_path(args.truth)
        if Path(args.truth).resolve() == out.resolve():
            raise InputError(f"--truth {args.truth!r} is the same file as --output; choose another path")
    if args.seed < 0:
        raise InputError(f"--seed must be >= 0; got {args.seed}")
    ds = make_dataset(args.dataset, snr_db=args.snr_db, random_state=args.seed)
    if hasattr(ds, "arrays"):  # engineering systems: several arrays, written as .npz
        return _write_system(ds, out, args)
    two_d = ds.x.ndim == 2
    want = ".npz" if two_d else ".csv"
    if out.suffix.lower() != want:
        raise InputError(f"--output {str(out)!r}: dataset {args.dataset!r} is {'2-D' if two_d else '1-D'}; "
                         f"write it to a {want} file")
    if two_d:
        gx, gy = np.unique(ds.x[:, 0]), np.unique(ds.x[:, 1])
        shape = (gx.size, gy.size)  # generators flatten their grids with indexing="ij"

        def grid(v):
            return v.reshape(shape).T

        with atomic_output(out, suffix=".npz") as tmp:
            with open(tmp, "wb") as fh:
                np.savez(fh, x=gx, y=gy, z=grid(ds.y), physics=grid(ds.physics),
                         disturbance=grid(ds.disturbance_true), noise=grid(ds.noise))
    else:
        table = np.c_[ds.x, ds.y, ds.physics, ds.disturbance_true, ds.noise]
        with atomic_output(out, suffix=".csv") as tmp:
            np.savetxt(tmp, table, delimiter=",", header="x,y,physics,disturbance,noise", comments="",
                       fmt="%.17g")
    # noise_sigma: 0 for --snr-db inf, whose snr_db a strict JSON writes as null
    truth = {"dataset": ds.name, "seed": args.seed, "snr_db": ds.snr_db, "noise_sigma": ds.noise_sigma,
             "theta_true": ds.theta_true,
             "basis": list(ds.basis.names), "phi": list(ds.basis.phi_names),
             "disturbance_class": repr(ds.disturbance), "identified": ds.identified,
             "description": ds.description,
             "extras": {k: (list(v) if isinstance(v, tuple) else v) for k, v in ds.extras.items()}}
    if args.truth:
        write_json(args.truth, truth)
    if getattr(args, "quiet", False):
        return 0
    print(ds.description)
    print("true parameters: " + ", ".join(f"{k} = {v:.6g}" for k, v in ds.theta_true.items()))
    hint = SEPARATE_HINTS.get(ds.name)
    if hint:
        period = getattr(ds.disturbance, "period", None)
        print(f"try: odnn-sep separate {out} " + hint.format(period=f"{period:.12g}" if period else ""))
    return 0


def _write_system(ds, out, args) -> int:
    """Write a power_grid / humanoid record: its arrays to .npz, its truth to --truth."""
    import numpy as np

    from odnn_sep.errors import InputError
    from odnn_sep.io_utils import atomic_output, write_json

    if out.suffix.lower() != ".npz":
        raise InputError(f"--output {str(out)!r}: dataset {args.dataset!r} has several arrays; write it to a .npz file")
    with atomic_output(out, suffix=".npz") as tmp:
        with open(tmp, "wb") as fh:
            np.savez(fh, **ds.arrays())
    truth = {"dataset": ds.name, "seed": args.seed, "snr_db": ds.snr_db, "description": ds.description,
             **ds.truth()}
    if args.truth:
        write_json(args.truth, truth)
    if not getattr(args, "quiet", False):
        print(ds.description)
    return 0
