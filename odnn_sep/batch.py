"""``odnn-sep batch``: run one command over every matching file of a folder.

Each file is processed by the same code path as the single-file command (``cli.main``), in a
worker process (local pool) or a Dask cluster (``--dask ADDRESS``, or ``--dask local`` for an
in-process LocalCluster). One file's failure never stops the batch; a summary JSON lists every
file with its exit status and message, and the exit code is 1 if any file failed.
"""
from __future__ import annotations

# command -> (output option, output suffix or None to keep the input's, default glob)
TARGETS = {
    "denoise": ("-o", None, "*.wav,*.flac,*.ogg"),
    "unwatermark": ("-o", None, "*.png,*.jpg,*.jpeg,*.tif,*.tiff,*.webp"),
    "mismatch": ("--report", ".json", "*.csv,*.wav,*.npz"),
}


def register(sub) -> None:
    p = sub.add_parser(
        "batch",
        help="process every file of a folder with one command (locally or on Dask)",
        description="Run denoise, unwatermark or mismatch on each matching file of IN_DIR, writing to OUT_DIR. "
        "Options after -- are passed to the command, e.g.: odnn-sep batch denoise in/ -o out/ -- --mains 50",
    )
    p.add_argument("target", choices=sorted(TARGETS), help="the command to run on each file")
    p.add_argument("in_dir", help="folder with the input files")
    p.add_argument("-o", "--out-dir", required=True, help="folder for outputs (created if missing; never IN_DIR)")
    p.add_argument("--pattern", help="comma-separated globs (default depends on the command)")
    p.add_argument("--recursive", action="store_true", help="also search sub-folders")
    p.add_argument("--jobs", type=int, default=None, help="local worker processes (default: CPU count)")
    p.add_argument("--dask", metavar="ADDRESS", help="run on a Dask cluster: scheduler address, or 'local'")
    p.add_argument("--summary", help="summary JSON path (default OUT_DIR/batch_summary.json)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def process_one(target: str, src: str, dst: str, extra: list[str]) -> dict:
    """Run one file through the single-file command; never raises (the batch must go on)."""
    import contextlib
    import io
    import time

    from odnn_sep.cli import main

    out_opt = TARGETS[target][0]
    args = [target, src, out_opt, dst, *extra]
    if target == "denoise" and "--quiet" not in extra:
        args.append("--quiet")  # one progress bar for the batch, not one per file
    err = io.StringIO()
    t0 = time.perf_counter()
    try:
        with contextlib.redirect_stderr(err):
            code = main(args)
    except SystemExit as exc:  # argparse usage errors
        code = int(exc.code or 0)
    except Exception as exc:  # a bug on one file must not kill the batch; it is reported per file
        code = 3
        err.write(f"internal error: {type(exc).__name__}: {exc}")
    msg = err.getvalue().strip().splitlines()
    return {"input": src, "output": dst if code == 0 else None, "exit_code": code,
            "message": msg[-1] if msg else "", "seconds": round(time.perf_counter() - t0, 3)}


def _find(in_dir, patterns, recursive):
    from pathlib import Path

    files = set()
    for pat in patterns:
        files.update(Path(in_dir).rglob(pat) if recursive else Path(in_dir).glob(pat))
    return sorted(f for f in files if f.is_file())


def run(args) -> int:
    import os
    import sys
    from pathlib import Path

    from tqdm import tqdm

    from odnn_sep.errors import InputError
    from odnn_sep.io_utils import write_json

    in_dir, out_dir = Path(args.in_dir), Path(args.out_dir)
    if not in_dir.is_dir():
        raise InputError(f"input folder {str(in_dir)!r} does not exist or is not a folder")
    if out_dir.exists() and out_dir.resolve() == in_dir.resolve():
        raise InputError("the output folder is the input folder; choose a different --out-dir so inputs are never overwritten")
    extra = list(getattr(args, "passthrough", []))
    patterns = (args.pattern or TARGETS[args.target][2]).split(",")
    files = _find(in_dir, [p.strip() for p in patterns if p.strip()], args.recursive)
    if not files:
        raise InputError(f"no files matching {','.join(patterns)} in {str(in_dir)!r}; check the folder or --pattern")
    out_dir.mkdir(parents=True, exist_ok=True)
    suffix = TARGETS[args.target][1]
    jobs = []
    for f in files:
        rel = f.relative_to(in_dir)
        dst = out_dir / (rel.with_suffix(suffix) if suffix else rel)
        dst.parent.mkdir(parents=True, exist_ok=True)
        jobs.append((args.target, str(f), str(dst), extra))
    show = not args.quiet and sys.stderr.isatty()
    bar = tqdm(total=len(jobs), desc=f"batch {args.target}", unit="file", disable=not show, file=sys.stderr)
    results = []
    if args.dask:
        from dask.distributed import Client, LocalCluster, as_completed

        cluster = LocalCluster(n_workers=args.jobs or os.cpu_count(), threads_per_worker=1,
                               processes=True) if args.dask == "local" else None
        with Client(cluster if cluster is not None else args.dask) as client:
            futures = [client.submit(process_one, *j, pure=False) for j in jobs]
            for fut in as_completed(futures):
                results.append(fut.result())
                bar.update(1)
        if cluster is not None:
            cluster.close()
    else:
        from concurrent.futures import ProcessPoolExecutor, as_completed

        n = max(1, min(args.jobs or os.cpu_count() or 1, len(jobs)))
        if n == 1:
            for j in jobs:
                results.append(process_one(*j))
                bar.update(1)
        else:
            with ProcessPoolExecutor(max_workers=n) as pool:
                for fut in as_completed([pool.submit(process_one, *j) for j in jobs]):
                    results.append(fut.result())
                    bar.update(1)
    bar.close()
    results.sort(key=lambda r: r["input"])
    failed = [r for r in results if r["exit_code"] != 0]
    summary = Path(args.summary) if args.summary else out_dir / "batch_summary.json"
    write_json(summary, {"command": args.target, "files": len(results), "failed": len(failed), "results": results})
    print(f"{len(results) - len(failed)} of {len(results)} file(s) processed; summary in {summary}", file=sys.stderr)
    for r in failed:
        print(f"  failed: {r['input']}: {r['message']}", file=sys.stderr)
    return 1 if failed else 0
