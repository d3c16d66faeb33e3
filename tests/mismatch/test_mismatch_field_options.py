"""Options of time series given with a 2-D field (.npz): refused, not ignored.

``mismatch field.npz --model heat2d --column 3`` or ``--start 1 --duration 3`` and
``separate field.npz --column 3`` ran on the whole array z as if the options were not there.
"""
import numpy as np
import pytest

from odnn_sep.cli import main


@pytest.fixture
def field(tmp_path):
    path = tmp_path / "field.npz"
    x, y = np.linspace(-1, 1, 12), np.linspace(-1, 1, 10)
    X, Y = np.meshgrid(x, y)
    np.savez(path, x=x, y=y, z=np.exp(-(X**2 + Y**2)) + 0.01 * np.random.default_rng(0).normal(size=X.shape))
    return path


@pytest.mark.parametrize("opts, words", [(["--column", "3"], "--column is for time series"),
                                         (["--start", "1", "--duration", "3"], "--start and --duration are for")])
def test_mismatch_field_refuses_series_options(field, capsys, opts, words):
    assert main(["mismatch", str(field), "--model", "heat2d", "--quiet", *opts]) == 1
    assert words in capsys.readouterr().err


def test_separate_field_refuses_column(field, capsys):
    assert main(["separate", str(field), "--basis", "x", "--column", "3", "--quiet"]) == 1
    assert "leave --column out" in capsys.readouterr().err
    assert main(["separate", str(field), "--basis", "x", "--quiet"]) == 0
