"""``odnn-sep batch``: run one command over every matching file of a folder.

Each file is processed by the same code path as the single-file command (``cli.main``), in a
worker process (local pool) or a Dask cluster (``--dask ADDRESS``, or ``--dask local`` for an
in-process LocalCluster). One file's failure never stops the batch; a summary JSON lists every
file with its exit status and message, and the exit code is 1 if any file failed.

Safety: every output path is checked against every input before anything runs (an output folder
inside the input folder is never searched for inputs, and never maps an output onto an input);
hidden files and this package's temporary folders are never inputs; Ctrl-C or SIGTERM stops the
queue, stops the workers (their unfinished outputs are removed), writes the summary of what
finished and exits 130 (143 for SIGTERM).
"""
from __future__ import annotations

import argparse
import collections

#: Failed files named one per line on the console; the summary lists them all.
MAX_FAILED_LINES = 20
# command -> (output option, output suffix or None to keep the input's, default patterns)
TARGETS = {
    "denoise": ("-o", None, "*.wav,*.flac,*.ogg,*.oga,*.aif,*.aiff,*.mp3,*.w64,*.caf"),
    "unwatermark": ("-o", None, "*.png,*.jpg,*.jpeg,*.tif,*.tiff,*.webp,*.bmp"),
    "mismatch": ("--report", ".json", "*.csv,*.wav,*.flac,*.npz"),
    # separate's result is its parameters and intervals: the report is the output; -o parts CSVs
    # and --plot figures after -- are written per file beside it (batch_options.py)
    "separate": ("--report", ".json", "*.csv,*.npz"),
}


def positive_int(text: str) -> int:
    """argparse type: an integer >= 1.

    Parameters
    ----------
    text : str
        The option's value.

    Returns
    -------
    int

    Raises
    ------
    argparse.ArgumentTypeError
        For a non-integer or a value below 1.

    Examples
    --------
    >>> positive_int("4")
    4
    >>> positive_int("0")
    Traceback (most recent call last):
    ...
    argparse.ArgumentTypeError: must be >= 1, got 0
    """
    try:
        v = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number >= 1, got {text!r}") from None
    if v < 1:
        raise argparse.ArgumentTypeError(f"must be >= 1, got {v}")
    return v


def register(sub) -> None:
    """Add the ``batch`` subcommand to ``sub``.

    Parameters
    ----------
    sub : argparse._SubParsersAction
        The sub-parsers of the ``odnn-sep`` parser (``parser.add_subparsers()``).

    Examples
    --------
    >>> import argparse
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> args = parser.parse_args(["batch", "denoise", "in", "-o", "out", "--jobs", "2"])
    >>> args.target, args.in_dir, args.out_dir, args.jobs, args.recursive
    ('denoise', 'in', 'out', 2, False)
    >>> args.func is run
    True
    """
    p = sub.add_parser(
        "batch",
        help="process every file of a folder with one command (locally or on Dask)",
        description="Run denoise, unwatermark, mismatch or separate on each matching file of IN_DIR, writing to OUT_DIR "
        "(mismatch and separate: one JSON report per file). Options after -- are passed to the command, e.g.: "
        "odnn-sep batch denoise in/ -o out/ -- --mains 50, or odnn-sep batch separate in/ -o out/ -- --basis "
        "'sin(5*x)' --disturbance even. "
        "Patterns are case-insensitive; hidden files are skipped.",
    )
    p.add_argument("target", choices=sorted(TARGETS), help="the command to run on each file")
    p.add_argument("in_dir", help="folder with the input files")
    p.add_argument("-o", "--out-dir", required=True, help="folder for outputs (created if missing; never IN_DIR)")
    p.add_argument("--pattern", help="comma-separated globs, case-insensitive (default: every format the "
                   "command reads)")
    p.add_argument("--recursive", action="store_true", help="also search sub-folders")
    p.add_argument("--jobs", type=positive_int, default=None, help="local worker processes (default: CPU count)")
    p.add_argument("--dask", metavar="ADDRESS", help="run on a Dask cluster: scheduler address, or 'local' "
                   '(needs pip install "odnn-sep[dask]")')
    p.add_argument("--summary", help="summary JSON path (default OUT_DIR/batch_summary.json)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    p.set_defaults(func=run)


def process_one(target: str, src: str, dst: str, extra: list[str]) -> dict:
    """Run one file through the single-file command; never raises (the batch must go on).

    Parameters
    ----------
    target : str
        The command, a key of :data:`TARGETS` (``"denoise"``, ``"unwatermark"``, ``"mismatch"``,
        ``"separate"``).
    src, dst : str
        Input file and its output path.
    extra : list of str
        Further options for the command (those after ``--`` on the batch's command line).

    Returns
    -------
    dict
        ``input``, ``output`` (None on failure), ``exit_code``, ``message`` (the last line the command
        wrote to stderr) and ``seconds``.

    Examples
    --------
    >>> r = process_one("mismatch", "in.csv", "out.json", [])    # mismatch needs --model: a usage error
    >>> r["exit_code"], r["output"], r["message"]
    (2, None, 'odnn-sep mismatch: error: the following arguments are required: --model')
    >>> sorted(r)
    ['exit_code', 'input', 'message', 'output', 'seconds']
    """
    import contextlib
    import io
    import os
    import tempfile
    import time
    from pathlib import Path

    from odnn_sep.cli import main

    out_opt = TARGETS[target][0]
    args = [target, src, out_opt, dst, *extra, "--quiet"]  # one progress bar for the batch
    report = dst if out_opt == "--report" else None
    if report is None and "--report" in extra[:-1]:
        report = extra[extra.index("--report") + 1]     # a report of each file asked for after --
    tmp_dir = None
    if report is None:
        # the report says what happened (batch_outcome.py): --quiet silences the summary line
        tmp_dir = tempfile.TemporaryDirectory(prefix="odnn-sep-batch-")
        report = str(Path(tmp_dir.name) / "report.json")
        args += ["--report", report]
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
    if code in (130, 143) and tmp_dir is not None:
        tmp_dir.cleanup()
    if code in (130, 143):
        import multiprocessing

        if multiprocessing.parent_process() is not None:
            # a pool worker told to stop: its file is rolled back; take no further job
            os._exit(code)
    msg = err.getvalue().strip().splitlines()
    rec = {"input": src, "output": dst if code == 0 else None, "exit_code": code,
           "message": msg[-1] if msg else "", "seconds": round(time.perf_counter() - t0, 3)}
    if report is not None and code in (0, 3):
        from odnn_sep.batch_outcome import outcome
        rec.update(outcome(target, report))
    if tmp_dir is not None:
        tmp_dir.cleanup()
    return rec


def _find(in_dir, patterns, recursive, unreadable=None):
    """Files under ``in_dir`` whose name matches a pattern (case-insensitive), hidden ones excluded.

    An output folder inside ``in_dir`` is searched too: its files may be the user's, so an output
    that would land on one of them is refused rather than written. Matching names that are not
    regular files (a broken link: a git-annex file whose content is not here; a pipe) go to the list
    ``unreadable``: they were left out without a word, and the batch said "2 of 2 processed".
    """
    import fnmatch
    import os
    from pathlib import Path

    from odnn_sep.io_utils import is_temporary

    root = Path(in_dir)
    pats = [p.lower() for p in patterns]
    found = []
    for dirpath, dirnames, filenames in os.walk(root):
        here = Path(dirpath)
        dirnames[:] = sorted(d for d in dirnames if not d.startswith("."))
        for name in filenames:
            f = here / name
            if not is_temporary(f.relative_to(root)) and any(fnmatch.fnmatchcase(name.lower(), p) for p in pats):
                if f.is_file():
                    found.append(f)
                elif unreadable is not None:
                    unreadable.append(f)
        if not recursive:
            break
    return sorted(found)


def plan_outputs(files, in_dir, out_dir, suffix):
    """Output path for each input; never an input, never the same for two inputs.

    Two inputs that would share an output name (``a.csv`` and ``a.wav`` -> ``a.json``) each keep
    their full name (``a.csv.json``, ``a.wav.json``).

    Parameters
    ----------
    files : list of pathlib.Path
        Input files, under ``in_dir``.
    in_dir, out_dir : pathlib.Path
        Input and output folders (the tree below ``in_dir`` is repeated under ``out_dir``).
    suffix : str or None
        Output suffix, or None to keep each input's name.

    Returns
    -------
    list of pathlib.Path

    Raises
    ------
    odnn_sep.errors.InputError
        When an output would land on an input.

    Examples
    --------
    >>> from pathlib import Path
    >>> files = [Path("in/a.csv"), Path("in/a.wav"), Path("in/b.csv")]
    >>> [str(p) for p in plan_outputs(files, Path("in"), Path("out"), ".json")]
    ['out/a.csv.json', 'out/a.wav.json', 'out/b.json']
    >>> [str(p) for p in plan_outputs(files + [Path("in/a.csv.npz")], Path("in"), Path("out"), ".json")]
    ['out/a.csv.json', 'out/a.wav.json', 'out/b.json', 'out/a.csv.npz.json']
    """
    from collections import Counter

    from odnn_sep.errors import InputError

    rels = [f.relative_to(in_dir) for f in files]
    dsts = [out_dir / (r.with_suffix(suffix) if suffix else r) for r in rels]
    full = [False] * len(dsts)
    while suffix:
        # a full name can meet another input's short one ('a.csv' and 'a.wav' -> 'a.csv.json', the
        # short name of 'a.csv.npz'): that one takes its full name too, until no two outputs meet
        counts = Counter(str(d).lower() for d in dsts)
        clash = [k for k, d in enumerate(dsts) if counts[str(d).lower()] > 1 and not full[k]]
        if not clash:
            break
        for k in clash:
            dsts[k], full[k] = out_dir / rels[k].parent / (rels[k].name + suffix), True
    inputs = {f.resolve() for f in files}
    for f, d in zip(files, dsts):
        if d.resolve() in inputs:
            raise InputError(f"output {str(d)!r} for {str(f)!r} would overwrite an input; choose an --out-dir "
                             "outside the input folder")
    return dsts


def _check_distinct(paths) -> None:
    """Refuse two files of one batch written to the same path (a figure named like another file's output)."""
    from collections import Counter

    from odnn_sep.errors import InputError

    counts = Counter(str(p.resolve()) for p in paths)
    same = next((p for p in paths if counts[str(p.resolve())] > 1), None)
    if same is not None:
        raise InputError(f"two files of this batch would be written to {str(same)!r}; rename one of the inputs")


def _check_not_inputs(files, outputs) -> None:
    """Refuse any output that is one of the input files (same path, link or hard link)."""
    import os

    from odnn_sep.errors import InputError

    def key(p):
        try:
            st = os.stat(p)
        except OSError:
            return None
        return st.st_dev, st.st_ino

    paths = {f.resolve() for f in files}
    nodes = {key(f) for f in files} - {None}
    for what, o in outputs:
        k = key(o)
        if o.resolve() in paths or (k is not None and k in nodes):
            raise InputError(f"{what} {str(o)!r} is an input file; choose an --out-dir / --summary outside the "
                             "inputs so they are never overwritten")


def run(args) -> int:
    """Run ``args.target`` on every matching file of ``args.in_dir``; write the summary JSON.

    Parameters
    ----------
    args : argparse.Namespace
        Options of ``odnn-sep batch`` (see :func:`register`), with ``passthrough`` the options after ``--``.

    Returns
    -------
    int
        0 if every file succeeded, 1 if any failed, 130 / 143 when interrupted / terminated.

    Raises
    ------
    odnn_sep.errors.InputError
        Before anything runs: a missing input folder, no matching file, or an output that is an input.

    Examples
    --------
    >>> import argparse, tempfile
    >>> parser = argparse.ArgumentParser(prog="odnn-sep")
    >>> register(parser.add_subparsers(dest="command"))
    >>> with tempfile.TemporaryDirectory() as d:
    ...     run(parser.parse_args(["batch", "mismatch", d, "-o", d + "/out"]))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: no files matching *.csv,*.wav,*.flac,*.npz in '...'; check the folder or --pattern
    """
    import os
    import sys
    from pathlib import Path

    from odnn_sep.batch_options import per_file_options
    from odnn_sep.errors import InputError
    from odnn_sep.io_paths import check_output_target

    in_dir, out_dir = Path(args.in_dir), Path(args.out_dir)
    if not in_dir.is_dir():
        raise InputError(f"input folder {str(in_dir)!r} does not exist or is not a folder")
    if out_dir.exists() and out_dir.resolve() == in_dir.resolve():
        raise InputError("the output folder is the input folder; choose a different --out-dir so inputs are never "
                         "overwritten")
    if out_dir.exists() and not out_dir.is_dir():
        raise InputError(f"--out-dir {str(out_dir)!r} exists and is not a folder")
    extra = list(getattr(args, "passthrough", []))
    patterns = [p.strip() for p in (args.pattern or TARGETS[args.target][2]).split(",") if p.strip()]
    if not patterns:
        raise InputError(f"--pattern {args.pattern!r} names no pattern; give e.g. '*.csv', or leave it out for every "
                         "format the command reads")
    pathlike = next((p for p in patterns if "/" in p or os.sep in p), None)
    if pathlike is not None:
        # '**/*.csv' or 'sub/*.csv' never matched (names are matched) and read as "no files in the folder"
        raise InputError(f"--pattern {pathlike!r} holds a path; patterns match file names only: give e.g. "
                         f"{pathlike.replace(os.sep, '/').rsplit('/', 1)[-1]!r}, with --recursive for sub-folders")
    unreadable: list = []
    files = _find(in_dir, patterns, args.recursive, unreadable)
    if not files:
        more = f", and {len(unreadable) - 1} more like it" if len(unreadable) > 1 else ""
        some = f" ({_not_a_file(unreadable[0])}{more})" if unreadable else ""
        raise InputError(f"no files matching {','.join(patterns)} in {str(in_dir)!r}{some}; check the folder or "
                         "--pattern")
    dsts = plan_outputs(files, in_dir, out_dir, TARGETS[args.target][1])
    # a --plot or --report after -- is written per file, beside its output
    options, side = per_file_options(args.target, extra, dsts, own_output=TARGETS[args.target][0])
    _check_distinct([*dsts, *side])
    summary = Path(args.summary) if args.summary else out_dir / "batch_summary.json"
    _check_not_inputs(files, [(f"output of {f}", d) for f, d in zip(files, dsts)] + [("--summary", summary)]
                      + [("figure or report", p) for p in side])
    if any(d.resolve() == summary.resolve() for d in [*dsts, *side]):
        raise InputError(f"--summary {str(summary)!r} is the output of an input file; choose another path")
    if args.summary:
        check_output_target(summary, "--summary")
    created = _make_dirs([out_dir, *sorted({d.parent for d in dsts})])
    jobs = [(args.target, str(f), str(d), o) for f, d, o in zip(files, dsts, options)]
    from odnn_sep.batch_runner import run_jobs
    from odnn_sep.io_utils import remove_temporaries_of

    stopped: list[int] = []
    # a worker killed after its grace time could not remove its own temporary folder
    sweep = lambda: remove_temporaries_of(stopped, {d.parent for d in dsts} | {summary.parent})  # noqa: E731
    try:
        results, interrupt = run_jobs(jobs, args, stopped)
    except BaseException:
        sweep()
        _remove_empty(created)  # e.g. the Dask scheduler could not be reached: leave nothing behind
        raise
    sweep()
    results += [{"input": str(f), "output": None, "exit_code": 1, "message": f"Error: {_not_a_file(f)}; not processed",
                 "seconds": 0.0} for f in unreadable]
    return _finish(args, jobs, results, interrupt, summary, sys.stderr, os)


def _not_a_file(path) -> str:
    """Why ``path``, which matched the pattern, is no input: a broken link, a pipe, a device.

    Examples
    --------
    >>> import os, tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     os.symlink("absent.wav", os.path.join(d, "take.wav"))
    ...     print(_not_a_file(os.path.join(d, "take.wav")).split(" is ")[1])
    a broken link (its target 'absent.wav' does not exist)
    """
    import os

    if os.path.islink(path) and not os.path.exists(path):
        return f"{str(path)!r} is a broken link (its target {os.readlink(path)!r} does not exist)"
    return f"{str(path)!r} is not a regular file"


def _make_dirs(dirs):
    """Create ``dirs``; return the folders that did not exist before (deepest last)."""
    created = []
    for d in dirs:
        missing = [p for p in [d, *d.parents] if not p.exists()]
        d.mkdir(parents=True, exist_ok=True)
        created += reversed(missing)
    return created


def _remove_empty(created) -> None:
    for d in reversed(created):
        try:
            d.rmdir()
        except OSError:
            pass  # not empty: something was written there


def _finish(args, jobs, results, interrupt, summary, stream, os) -> int:
    from odnn_sep.io_utils import write_json

    results.sort(key=lambda r: r["input"])
    failed = [r for r in results if r["exit_code"] != 0]
    finished = {r["input"] for r in results}
    not_run = sorted(j[1] for j in jobs if j[1] not in finished)
    body = {"command": args.target, "files": len(results), "failed": len(failed), "results": results}
    if interrupt:
        body.update({"interrupted": True, "not_run": not_run})
    write_json(summary, body)
    if interrupt:
        print(f"{interrupt}: {len(results)} of {len(jobs)} file(s) finished ({len(failed)} failed), "
              f"{len(not_run)} not run; summary in {summary}", file=stream)
        return 143 if interrupt == "Terminated" else 130
    if not args.quiet or failed:
        print(f"{len(results) - len(failed)} of {len(results)} file(s) processed; summary in {summary}", file=stream)
        kinds = collections.Counter(str(r["outcome"]).split(":")[0][:48] for r in results if r.get("outcome"))
        if kinds:
            print("  outcomes: " + ", ".join(f"{k} {n}" for k, n in kinds.most_common()), file=stream)
        warned = sum(1 for r in results if r.get("warnings"))
        if warned:
            print(f"  {warned} file(s) with warnings (see 'warnings' in the summary)", file=stream)
    for r in failed[:MAX_FAILED_LINES]:
        print(f"  failed: {r['input']}: {r['message']}", file=stream)
    if len(failed) > MAX_FAILED_LINES:
        # a folder of 10 000 unreadable files printed 10 000 lines
        print(f"  ... and {len(failed) - MAX_FAILED_LINES} more failed file(s); see the summary", file=stream)
    return 1 if failed else 0
