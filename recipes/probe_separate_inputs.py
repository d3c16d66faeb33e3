"""Inputs a new user brings to ``separate``, ``simulate`` and the Python API: what each answers.

One row per case: the record or call as a user would make it, and what the installed version
answered (the line that matters, exit code). Run it with another version on ``PYTHONPATH`` to
compare two versions (the command line is run as ``python -m odnn_sep.cli``).

- ``simulate --snr-db inf`` (noise-free data) and the fit of what it wrote;
- three points for an even class (no point left for the noise), and the API's ``as_dict()`` as JSON;
- a field whose z is boolean (a mask saved in place of the data);
- the parts CSV (``-o``) of a record in epoch seconds, fitted again;
- a record pasted twice; the parts CSV of a 2-D field given back;
- a basis column of a far larger size than another (``x**10`` on [0, 10]);
- a convex class on data in small units (a coefficient of 2e-9);
- 48 hourly samples with a daily periodic class;
- a dataset and an expression basis sent to worker processes (pickled).

    python recipes/probe_separate_inputs.py              # prints the table
"""
from __future__ import annotations

import json
import os
import pickle
import subprocess
import sys
import tempfile
import warnings
from pathlib import Path

import numpy as np


def _cli(*args) -> tuple[int, str]:
    """Exit code and the summary or error line of ``odnn-sep ARGS``."""
    p = subprocess.run([sys.executable, "-m", "odnn_sep.cli", *args], capture_output=True, text=True,
                       env=dict(os.environ), timeout=600)
    lines = [ln.strip() for ln in (p.stdout + p.stderr).splitlines() if ln.strip()]
    keep = [ln for ln in lines if ("=" in ln and "separation" not in ln) or ln.startswith("Error")
            or "no point" in ln or "Traceback" in ln]
    return p.returncode, " / ".join(keep)[:230] or (lines[-1][:230] if lines else "")


def _csv(path, x, y, header="x,y"):
    np.savetxt(path, np.c_[x, y], delimiter=",", header=header, comments="", fmt="%.17g")


def cases(d: Path):
    rng = np.random.default_rng(0)
    rows = []

    rows.append(("simulate figure2 --snr-db inf", *_cli("simulate", "figure2", "-o", str(d / "f.csv"),
                                                        "--snr-db", "inf", "--quiet")))
    if (d / "f.csv").exists():
        rows.append(("  ... then separate (true theta 0.727721)",
                     *_cli("separate", str(d / "f.csv"), "--basis", "x**2*sin(5*x)", "--disturbance", "even")))

    x3 = np.array([-1.0, 0.0, 1.0])
    _csv(d / "three.csv", x3, 2 * np.sin(5 * x3) + np.cos(2 * x3) + [0.01, 0.0, -0.02])
    rows.append(("3 points, --disturbance even", *_cli("separate", str(d / "three.csv"), "--basis", "sin(5*x)",
                                                       "--disturbance", "even")))
    try:
        from odnn_sep.core import Basis, Even, Separator

        r = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x3, 2 * x3 + np.cos(x3)).result_
        json.dumps(r.as_dict(), allow_nan=False)
        rows.append(("  API: json.dumps(as_dict(), allow_nan=False)", 0, "strict JSON"))
    except ValueError as exc:
        rows.append(("  API: json.dumps(as_dict(), allow_nan=False)", 1, f"ValueError: {exc}"))

    xa, ya = np.linspace(-1, 1, 30), np.linspace(-1, 1, 20)
    X, _ = np.meshgrid(xa, ya)
    np.savez(d / "mask.npz", x=xa, y=ya, z=X > 0)
    rows.append(("field with boolean z", *_cli("separate", str(d / "mask.npz"), "--basis", "x", "--disturbance",
                                               "even")))

    xe = 1.7e9 + np.arange(400) * 0.01
    te = xe - xe[0]
    _csv(d / "epoch.csv", xe, 3 * np.sin(2 * np.pi * 1.3 * te) + np.cos(2 * np.pi * 0.25 * te)
         + 0.02 * rng.standard_normal(400))
    opts = ["--basis", "sin(2*pi*1.3*(x-1.7e9))", "--disturbance", "band:0:0.5"]
    _cli("separate", str(d / "epoch.csv"), *opts, "-o", str(d / "parts.csv"))
    xs = np.genfromtxt(d / "parts.csv", delimiter=",", names=True)["x"]
    rows.append(("-o parts of epoch-second x: distinct x", 0, f"{np.unique(xs).size} of 400"))
    rows.append(("  ... parts fitted again", *_cli("separate", str(d / "parts.csv"), *opts)))

    xr = np.linspace(-1, 1, 200)
    yr = 2 * np.sin(5 * xr) + np.cos(2 * xr) + 0.02 * rng.standard_normal(200)
    _csv(d / "once.csv", xr, yr)
    _csv(d / "twice.csv", np.r_[xr, xr], np.r_[yr, yr])
    rows.append(("a record of 200 rows", *_cli("separate", str(d / "once.csv"), "--basis", "sin(5*x)")))
    rows.append(("  ... pasted twice (400 rows)", *_cli("separate", str(d / "twice.csv"), "--basis", "sin(5*x)")))

    Xf, Yf = np.meshgrid(np.linspace(-1, 1, 31), np.linspace(-1, 1, 21))
    np.savez(d / "field.npz", x=Xf[0], y=Yf[:, 0], z=2 * Xf * Yf**2 + np.cos(Xf) + np.cos(2 * Yf))
    _cli("separate", str(d / "field.npz"), "--basis", "x*y**2", "--disturbance", "even", "-o", str(d / "fp.csv"))
    rows.append(("-o parts of a field, given back (--basis x)", *_cli("separate", str(d / "fp.csv"), "--basis", "x")))

    x10 = np.linspace(0, 10, 500)
    _csv(d / "poly.csv", x10, 2 * np.sin(3 * x10) + 3e-10 * x10**10 + 0.01 * rng.standard_normal(500))
    rows.append(("--basis sin(3*x) --basis x**10 on [0, 10] (true 2, 3e-10)",
                 *_cli("separate", str(d / "poly.csv"), "--basis", "sin(3*x)", "--basis", "x**10")))

    xc = np.linspace(-1, 1, 400)
    _csv(d / "nano.csv", xc, 1e-9 * (2 * np.sin(5 * xc) + np.exp(xc) + 0.02 * rng.standard_normal(400)))
    rows.append(("convex, y in units where theta = 2e-9",
                 *_cli("separate", str(d / "nano.csv"), "--basis", "sin(5*x)", "--disturbance", "convex")))

    th = np.arange(48.0)
    _csv(d / "hourly.csv", th, 0.05 * th + np.where(th % 24 < 8, 1.0, 0.0) + 0.01 * rng.standard_normal(48),
         header="hour,load")
    rows.append(("48 hourly samples, periodic:24 (true 0.05)",
                 *_cli("separate", str(d / "hourly.csv"), "--basis", "hour", "--disturbance", "periodic:24")))

    from odnn_sep.signals import NAMES, make_dataset

    bad = []
    for name in NAMES:
        try:
            pickle.dumps(make_dataset(name, random_state=0))
        except (AttributeError, pickle.PicklingError, TypeError):
            bad.append(name)
    rows.append(("pickle.dumps(make_dataset(name)) for the 12 datasets", int(bool(bad)),
                 f"{12 - len(bad)} of 12 pickle" + (f" ({', '.join(bad)} fail)" if bad else "")))
    try:
        from odnn_sep.fit.expr import basis_from_expressions

        pickle.dumps(basis_from_expressions(["sin(5*x)"]))
        rows.append(("pickle an expression basis (--basis 'sin(5*x)')", 0, "pickles"))
    except (AttributeError, pickle.PicklingError) as exc:
        rows.append(("pickle an expression basis (--basis 'sin(5*x)')", 1, f"{type(exc).__name__}: {exc}"[:120]))
    return rows


def main() -> int:
    warnings.simplefilter("ignore")
    with tempfile.TemporaryDirectory() as tmp:
        rows = cases(Path(tmp))
    print("| input | exit | answer |\n|---|---|---|")
    for what, code, answer in rows:
        print(f"| {what} | {code} | {answer.replace('|', '/')} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())
