"""``--series`` with ``--column``: the same column rule as a single record, and clear refusals.

Before: ``--column 2`` (an index, as the help allows) was refused; ``--column t`` analysed the time
column as temperatures (exit 0, "up to 595 look like degF"); ``--series t`` (the time column) was
refused as "'mug' must be numbers"; an empty series cell made a series named ''.
"""
import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.errors import FormatError, InputError
from odnn_sep.mismatch.series_io import read_series_csv


@pytest.fixture
def mugs(tmp_path):
    t = np.arange(0, 600, 5.0)
    rng = np.random.default_rng(0)
    rows = ["t,mug,T"]
    for mug, h in (("a", 0.004), ("b", 0.006)):
        T = 20 + 60 * np.exp(-h * t) + rng.normal(0, 0.05, t.size)
        rows += [f"{a},{mug},{b}" for a, b in zip(t, T, strict=True)]
    path = tmp_path / "mugs.csv"
    path.write_text("\n".join(rows) + "\n")
    return path


def test_column_by_index(mugs):
    by_index, by_name = read_series_csv(mugs, "mug", column="2"), read_series_csv(mugs, "mug", column="T")
    assert list(by_index) == ["a", "b"]
    for k in by_name:
        np.testing.assert_array_equal(by_index[k][1], by_name[k][1])


@pytest.mark.parametrize("column, words", [("t", "is the coordinate column"), ("0", "is the coordinate column"),
                                           ("mug", "is the --series column"), ("1", "is the --series column")])
def test_column_that_is_not_the_values_refused(mugs, column, words):
    with pytest.raises(InputError, match=words):
        read_series_csv(mugs, "mug", column=column)


def test_series_on_the_time_column_refused(mugs):
    with pytest.raises(InputError, match="--series 't' is the time column"):
        read_series_csv(mugs, "t")


def test_empty_series_cell_named_by_its_line(mugs):
    lines = mugs.read_text().splitlines()
    lines[6] = lines[6].replace(",a,", ",,")
    mugs.write_text("\n".join(lines) + "\n")
    with pytest.raises(FormatError, match="line 7: the --series column 'mug' is empty"):
        read_series_csv(mugs, "mug")


def test_cli_joint_fit_with_column_index(mugs):
    assert main(["mismatch", str(mugs), "--model", "cooling", "--series", "mug", "--column", "2", "--quiet"]) == 0
