"""``batch --pattern`` values that can never match: said as such, not as "no files in the folder".

Patterns are matched against file names: ``**/*.csv`` (recursion as a shell writes it) answered
"no files matching **/*.csv in 'in'" for a folder full of CSV files, and ``,`` "no files matching  in".
"""
import pytest

from odnn_sep.cli import main


@pytest.mark.parametrize("pattern, words", [("**/*.csv", "patterns match file names only: give e.g. '*.csv'"),
                                            ("sub/*.csv", "with --recursive for sub-folders"),
                                            (",", "names no pattern")])
def test_pattern_that_cannot_match(tmp_path, capsys, pattern, words):
    src = tmp_path / "in"
    (src / "sub").mkdir(parents=True)
    (src / "sub" / "a.csv").write_text("t,T\n0,1\n1,2\n")
    assert main(["batch", "mismatch", str(src), "-o", str(tmp_path / "out"), "--pattern", pattern,
                 "--", "--model", "cooling"]) == 1
    assert words in capsys.readouterr().err
    assert not (tmp_path / "out").exists()
