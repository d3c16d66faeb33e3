"""Write one recipe's section of BENCHMARKS.md without touching the others.

Each recipe owns the block between ``<!-- BEGIN name -->`` and ``<!-- END name -->``. A file lock
keeps concurrent recipes from clobbering each other.
"""
from __future__ import annotations

import fcntl
import platform
import re
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BENCH = ROOT / "BENCHMARKS.md"
HEADER = "# Benchmarks\n\nEvery table below is written by the recipe named in its section, with the command that reproduces it.\n"


def machine() -> str:
    import os
    return f"{platform.machine()}, {os.cpu_count()} CPU cores, Python {platform.python_version()}"


def write_section(name: str, title: str, command: str, body: str) -> None:
    block = (
        f"<!-- BEGIN {name} -->\n## {title}\n\n"
        f"Reproduce: `{command}`  \nMeasured {time.strftime('%Y-%m-%d')} on {machine()}.\n\n"
        f"{body.rstrip()}\n<!-- END {name} -->\n"
    )
    lock = BENCH.with_suffix(".lock")
    with open(lock, "w") as lk:
        fcntl.flock(lk, fcntl.LOCK_EX)
        text = BENCH.read_text() if BENCH.exists() else HEADER
        pat = re.compile(rf"<!-- BEGIN {re.escape(name)} -->.*?<!-- END {re.escape(name)} -->\n?", re.S)
        text = pat.sub(lambda m: block, text) if pat.search(text) else text.rstrip() + "\n\n" + block
        BENCH.write_text(text)


def md_table(header: list[str], rows: list[list]) -> str:
    out = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    out += ["| " + " | ".join(str(c) for c in r) + " |" for r in rows]
    return "\n".join(out) + "\n"
