"""Run the bad-input corpus of tests/robustness and count what went wrong, per command.

    python recipes/robustness_report.py            # print the table
    python recipes/robustness_report.py --write    # also record it in docs/robustness.md
    python recipes/robustness_report.py --quick    # every 10th case (smoke run)

Each case runs in-process under a 60 s cap (a case past it counts as a hang); the run itself is
started under an 8 GB address-space limit so that a runaway case fails instead of exhausting the
machine. The same cases run in CI as tests/robustness/test_bad_input_corpus.py.
"""
from __future__ import annotations

import argparse
import collections
import resource
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path[:0] = [str(ROOT / "tests" / "robustness"), str(ROOT)]

MEMORY_CAP_BYTES = 8 << 30
COLUMNS = ("cases", "passed", "tracebacks", "inputs changed", "debris", "hangs", "wrong exit / lines")


def run(quick: bool):
    import corpus
    import corpus_options  # noqa: F401
    from runner import run_case, verdict

    cases = corpus.CASES[::10] if quick else corpus.CASES
    counts = collections.defaultdict(collections.Counter)
    failures = []
    with tempfile.TemporaryDirectory() as t:
        for k, c in enumerate(cases):
            rec = run_case(c, Path(t) / f"c{k}")
            bad = verdict(rec)
            for key in (c.id.split("-")[0], "all"):
                row = counts[key]
                row["cases"] += 1
                row["passed"] += not bad
                row["tracebacks"] += rec["traceback"]
                row["inputs changed"] += rec["inputs_changed"]
                row["debris"] += bool(rec["debris"])
                row["hangs"] += rec["hang"]
                row["wrong exit / lines"] += any(b.startswith(("exit", "0 Error", "2 Error")) for b in bad)
            if bad:
                failures.append((c.id, bad))
    return counts, failures


def table(counts) -> str:
    keys = sorted(k for k in counts if k != "all") + ["all"]
    lines = ["| command | " + " | ".join(COLUMNS) + " |", "|---" * (len(COLUMNS) + 1) + "|"]
    for k in keys:
        lines.append(f"| {k} | " + " | ".join(str(counts[k][c]) for c in COLUMNS) + " |")
    return "\n".join(lines)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--quick", action="store_true", help="every 10th case")
    ap.add_argument("--write", action="store_true", help="record the table in docs/robustness.md")
    a = ap.parse_args()
    soft, hard = resource.getrlimit(resource.RLIMIT_AS)
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY_CAP_BYTES, hard))
    t0 = time.perf_counter()
    counts, failures = run(a.quick)
    text = table(counts)
    print(text)
    print(f"\n{counts['all']['cases']} cases in {time.perf_counter() - t0:.0f} s", file=sys.stderr)
    for cid, bad in failures:
        print(f"  {cid}: {', '.join(bad)}", file=sys.stderr)
    if a.write and not a.quick:
        doc = ROOT / "docs" / "robustness.md"
        head, sep, _ = doc.read_text().partition("<!-- table -->") if doc.exists() else ("", "", "")
        if not sep:
            raise SystemExit("docs/robustness.md lacks the '<!-- table -->' marker")
        fail_txt = "\n".join(f"- `{cid}`: {', '.join(bad)}" for cid, bad in failures) or "- none"
        doc.write_text(head + sep + "\n\n" + text + "\n\nCases that did not pass:\n\n" + fail_txt + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
