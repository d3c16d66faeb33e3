"""Run one corpus case in-process with a time cap and judge it (used by the tests and the recipe)."""
from __future__ import annotations

import contextlib
import io
import os
import signal
import time
import traceback
from pathlib import Path

from robustness_helpers import snapshot

TIME_CAP_S = 60


class CaseTimeout(BaseException):
    """Raised by the alarm when a case runs past its time cap (a hang)."""


def _alarm(signum, frame):
    raise CaseTimeout()


@contextlib.contextmanager
def _env(extra):
    old = {k: os.environ.get(k) for k in extra}
    os.environ.update(extra)
    try:
        yield
    finally:
        for k, v in old.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v


def _listing(folder: Path) -> set[str]:
    return {str(p.relative_to(folder)) for p in folder.rglob("*")} if folder.exists() else set()


def run_case(case, d: Path, cap_s: float = TIME_CAP_S) -> dict:
    """Build ``case`` under ``d`` and run it; return what happened."""
    from odnn_sep.cli import main

    (d / "in").mkdir(parents=True, exist_ok=True)
    (d / "out").mkdir(exist_ok=True)
    argv = [str(a) for a in case.build(d)]
    before_in, before_all = snapshot(d / "in"), _listing(d)
    err, out = io.StringIO(), io.StringIO()
    rec = {"id": case.id, "exit": None, "traceback": False, "hang": False, "stderr": ""}
    old = signal.signal(signal.SIGALRM, _alarm)
    signal.setitimer(signal.ITIMER_REAL, cap_s)
    t0 = time.perf_counter()
    try:
        with _env(case.env), contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            rec["exit"] = main(argv)
    except SystemExit as exc:
        rec["exit"] = exc.code if isinstance(exc.code, int) else 2
    except CaseTimeout:
        rec["hang"] = True
    except Exception:  # a traceback a user would have seen
        rec["traceback"] = True
        err.write(traceback.format_exc())
    finally:
        signal.setitimer(signal.ITIMER_REAL, 0)
        signal.signal(signal.SIGALRM, old)
    rec["seconds"] = time.perf_counter() - t0
    rec["stderr"] = err.getvalue()
    rec["traceback"] = rec["traceback"] or "Traceback" in rec["stderr"]
    lines = [ln for ln in rec["stderr"].splitlines() if ln.strip()]
    rec["error_lines"] = sum(ln.startswith("Error:") for ln in lines)
    rec["inputs_changed"] = snapshot(d / "in") != before_in if (d / "in").exists() else True
    rec["debris"] = sorted(_listing(d) - before_all)
    return rec


def verdict(rec: dict) -> list[str]:
    """What is wrong with a case's outcome (empty: it passed)."""
    bad = []
    if rec["hang"]:
        bad.append("hang")
    if rec["traceback"]:
        bad.append("traceback")
    if rec["exit"] not in (1, 2):
        bad.append(f"exit {rec['exit']}")
    if rec["exit"] == 1 and rec["error_lines"] != 1:
        bad.append(f"{rec['error_lines']} Error: lines")
    if rec["inputs_changed"]:
        bad.append("input changed")
    if rec["debris"]:
        bad.append(f"left {rec['debris'][:3]}")
    return bad
