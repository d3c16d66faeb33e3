"""Golden outputs: numeric fingerprints of every front-end's results, recorded once, checked after changes.

A restructuring must not change what the package computes. This recipe runs a fixed, deterministic
set of cases quickly and compares compact fingerprints of their outputs (array norms, sums and a few
sample values, and the numbers of each report, all at full float precision) with
``tests/golden/golden.json``:

- ``audio``: ``denoise`` on the real room recording (../shared/data/pyenf_hum_recordings) and on two
  synthetic mixes (``odnn_sep.audio.synth.make_hum_mix``, one case of ``recipes/_audio_cases.py``);
- ``image``: ``unwatermark`` on six generated images: text mode with the default font, mask mode, and
  reference-logo mode (logos as in ``recipes/bench_logo.py``), two each;
- ``mismatch``: the concealed-effect benchmark at ``--quick`` (``recipes/bench_mismatch.py``:
  disturbance-kind population and strength sweep);
- ``table1``: Table 1 at ``--quick`` size for the exact solver, OLS and SINDy on every synthetic
  dataset, the network solver and the DNN baselines on two datasets, and the noise sweep
  (``recipes/table1.py``).

    python recipes/golden.py                    # check (exit 1 and every difference listed if any)
    python recipes/golden.py --only table1      # one group
    python recipes/golden.py --record           # re-record after an intended change of the methods

Numbers are compared with a relative tolerance of 1e-9 (absolute 1e-12 for values near zero) on the
machine that recorded them; on another CPU, whose BLAS kernels sum in another order, check with
``--rtol 1e-5`` (optimised parameters move by up to about 1e-6 there).
Re-record only for a change of a method, and say in the commit why the outputs moved.
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).parent))

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = ROOT / "tests" / "golden" / "golden.json"
DATA = ROOT.parent / "shared" / "data"
RTOL, ATOL = 1e-9, 1e-12
GROUPS = ("audio", "image", "mismatch", "table1")
SKIP_KEYS = {"seconds", "time_s", "runtime_s", "elapsed_s", "odnn_sep_version"}   # wall time is not an output


# ------------------------------------------------------------------------------------ fingerprints
def array_print(a) -> dict:
    """Shape, sum, 2-norm, NaN count and seven evenly spaced sample values of an array."""
    a = np.asarray(a)
    if a.dtype.kind == "c":
        return {"real": array_print(a.real), "imag": array_print(a.imag)}
    a = a.astype(np.float64)
    flat = a.ravel()
    ok = flat[np.isfinite(flat)]
    idx = np.unique(np.linspace(0, flat.size - 1, 7).astype(int)) if flat.size else []
    return {"shape": list(a.shape), "sum": float(ok.sum()), "norm": float(np.sqrt(np.sum(ok * ok))),
            "nonfinite": int(flat.size - ok.size), "samples": [float(flat[i]) for i in idx]}


def flatten(obj, prefix: str = "") -> dict:
    """``{path: value}`` of the numbers, strings and booleans in a nested result; arrays and long
    numeric lists become :func:`array_print` fingerprints."""
    out = {}
    if isinstance(obj, dict):
        for k, v in obj.items():
            if str(k) not in SKIP_KEYS:
                out.update(flatten(v, f"{prefix}.{k}" if prefix else str(k)))
        return out
    if isinstance(obj, (list, tuple)) and len(obj) > 8:
        try:
            arr = np.asarray(obj, dtype=np.float64)
            if arr.dtype == np.float64:
                obj = arr
        except (TypeError, ValueError):
            pass
    if isinstance(obj, np.ndarray) and obj.ndim > 0:
        return flatten(array_print(obj), prefix + "#")
    if isinstance(obj, (list, tuple)):
        for i, v in enumerate(obj):
            out.update(flatten(v, f"{prefix}[{i}]"))
        return out
    if isinstance(obj, (bool, np.bool_)) or obj is None or isinstance(obj, str):
        out[prefix] = None if obj is None else (bool(obj) if isinstance(obj, (bool, np.bool_)) else obj)
    elif isinstance(obj, (int, float, np.integer, np.floating)):
        out[prefix] = float(obj)
    else:
        out[prefix] = repr(obj)
    return out


def differences(golden: dict, new: dict, rtol: float = RTOL) -> list[str]:
    """Every difference between two ``{item: {path: value}}`` maps, one line each (numbers farther
    apart than ``rtol`` relative, ``ATOL`` absolute)."""
    lines = []
    for item in sorted(set(golden) | set(new)):
        if item not in new:
            lines.append(f"{item}: not computed this time")
            continue
        if item not in golden:
            lines.append(f"{item}: not in the golden file (record it)")
            continue
        g, n = golden[item], new[item]
        for path in sorted(set(g) | set(n)):
            a, b = g.get(path, "<missing>"), n.get(path, "<missing>")
            if isinstance(a, float) and isinstance(b, float):
                same = (math.isnan(a) and math.isnan(b)) or a == b or abs(a - b) <= rtol * max(abs(a), abs(b)) + ATOL
            else:
                same = a == b
            if not same:
                rel = (f" (rel {abs(a - b) / max(abs(a), abs(b)):.2e})"
                       if isinstance(a, float) and isinstance(b, float) and max(abs(a), abs(b)) > 0 else "")
                lines.append(f"{item}: {path}: golden {a!r} now {b!r}{rel}")
    return lines


# ------------------------------------------------------------------------------------------ runs
def items(groups=GROUPS) -> dict:
    """``{item name: zero-argument function returning its nested result}`` for the chosen groups."""
    from _golden_cases import audio_items, image_items, mismatch_items, table1_items

    makers = {"audio": audio_items, "image": image_items, "mismatch": mismatch_items, "table1": table1_items}
    out = {}
    for g in groups:
        out.update({f"{g}/{k}": fn for k, fn in makers[g]().items()})
    return out


def compute(selected: dict, log=None) -> dict:
    """Run the chosen items; ``{item: {path: value}}``."""
    import importlib.util
    import warnings

    torch = importlib.import_module("torch") if importlib.util.find_spec("torch") else None
    threads = torch.get_num_threads() if torch else None
    if torch:
        torch.set_num_threads(1)   # one thread: torch training is reproducible bit for bit on one machine
    out = {}
    try:
        for name, fn in selected.items():
            t0 = time.time()
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                out[name] = flatten(fn())
            if log:
                log(f"{name}: {len(out[name])} numbers in {time.time() - t0:.1f} s")
    finally:
        if torch:
            torch.set_num_threads(threads)
    return out


def load_golden() -> dict:
    return json.loads(GOLDEN.read_text())["items"] if GOLDEN.exists() else {}


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--record", action="store_true", help="run and write tests/golden/golden.json")
    mode.add_argument("--check", action="store_true", help="run and compare with the golden file (default)")
    ap.add_argument("--only", choices=GROUPS, action="append", help="run only this group (repeatable)")
    ap.add_argument("--rtol", type=float, default=RTOL,
                    help=f"relative tolerance of the check (default {RTOL:g}: the recording machine; another "
                         "CPU's BLAS sums in another order and moves optimised values by about 1e-6)")
    args = ap.parse_args(argv)
    groups = tuple(args.only or GROUPS)
    log = lambda s: print(s, file=sys.stderr, flush=True)  # noqa: E731
    t0 = time.time()
    new = compute(items(groups), log)
    log(f"{len(new)} items in {time.time() - t0:.0f} s")
    golden = load_golden()
    if args.record:
        golden = {k: v for k, v in golden.items() if k.split("/")[0] not in groups}
        golden.update(new)
        GOLDEN.parent.mkdir(parents=True, exist_ok=True)
        tmp = GOLDEN.with_suffix(".tmp")
        tmp.write_text(json.dumps({"rtol": RTOL, "atol": ATOL, "items": dict(sorted(golden.items()))},
                                  indent=0, sort_keys=True, allow_nan=True) + "\n")
        tmp.replace(GOLDEN)
        print(f"recorded {len(new)} items ({sum(len(v) for v in new.values())} numbers) in {GOLDEN}")
        return 0
    golden = {k: v for k, v in golden.items() if k.split("/")[0] in groups}
    diff = differences(golden, new, args.rtol)
    for line in diff:
        print(line)
    print(f"{len(new)} items, {sum(len(v) for v in new.values())} numbers: "
          + (f"{len(diff)} difference(s)" if diff else "identical to the golden outputs"))
    return 1 if diff else 0


if __name__ == "__main__":
    sys.exit(main())
