"""Every command x every kind of bad input: one clear line (exit 1) or a usage error (exit 2), never a
traceback, a hang, a changed input or a left-over file. Files are generated in tmp_path."""
from __future__ import annotations

import corpus
import corpus_options  # noqa: F401  (adds its cases to corpus.CASES)
import pytest
from runner import run_case, verdict

# Cases whose fix belongs to another part of the package (they pass once it lands).
KNOWN: dict[str, str] = {}  # case id -> reason, for a failure that is known and tracked


def _param(c):
    marks = [pytest.mark.xfail(reason=KNOWN[c.id], strict=False)] if c.id in KNOWN else []
    return pytest.param(c, id=c.id, marks=marks)


def test_corpus_is_large_and_distinct():
    ids = [c.id for c in corpus.CASES]
    assert len(ids) == len(set(ids))
    assert len(ids) >= 305
    commands = {c.id.split("-")[0] for c in corpus.CASES}
    assert {"denoise", "unwatermark", "mask", "mismatch", "separate", "simulate", "batch"} <= commands


@pytest.mark.parametrize("case", [_param(c) for c in corpus.CASES])
def test_bad_input_gives_one_clear_error(case, tmp_path):
    rec = run_case(case, tmp_path)
    assert not verdict(rec), f"{verdict(rec)}\n{rec['stderr'][-2000:]}"
