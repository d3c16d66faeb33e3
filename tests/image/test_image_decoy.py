"""Target-decoy detection rule: decoy texts and the decision."""
import pytest

from odnn_sep.image.decoy import FLOOR, KAPPA, decide, decoy_texts


@pytest.mark.parametrize("text", ["SAMPLE", "(c) Studio 2024", "odnn", "photo by J. Doe", "PROOF"])
def test_decoys_reorder_the_characters(text):
    ds = decoy_texts(text, 3)
    assert 1 <= len(ds) <= 3 and len(set(ds)) == len(ds)
    for d in ds:
        assert d != text and sorted(d) == sorted(text)
        assert [i for i, c in enumerate(d) if c == " "] == [i for i, c in enumerate(text) if c == " "]
        assert sum(a != b for a, b in zip(d, text)) >= len(text.replace(" ", "")) / 2
    assert decoy_texts(text, 3) == ds  # deterministic


def test_no_decoys_for_a_repeated_character():
    assert decoy_texts("aaa", 3) == []


def test_decide_paths():
    calls = []

    v = FLOOR  # a decoy score whose bar (KAPPA * v) lies above the floor

    def score_of(t):
        calls.append(t)
        return v

    d = decide(0.5, 0.28, score_of, "SAMPLE")
    assert d.detected and d.rule == "threshold" and not calls  # confident: no decoy cost
    d = decide(FLOOR - 0.01, 0.28, score_of, "SAMPLE")
    assert not d.detected and not calls and d.compared == "needs >= 0.28"
    d = decide(KAPPA * v + 0.001, 1.0, score_of, "SAMPLE")
    assert d.detected and d.rule == "decoys" and len(calls) == len(d.decoys) >= 1
    assert d.as_report()["decoys"][0]["score"] == round(v, 4)
    d = decide(KAPPA * v - 0.001, 1.0, score_of, "SAMPLE")
    assert not d.detected and "decoy texts" in d.compared
    assert not decide(0.2, 0.28, lambda t: 0.0, "aaa").detected  # no decoy: the global threshold decides
