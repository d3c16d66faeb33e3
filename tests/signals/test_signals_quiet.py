"""``simulate --quiet`` prints nothing, also for the engineering systems (power grid, humanoid),
which printed their description regardless."""
import pytest

from odnn_sep.cli import main


@pytest.mark.parametrize("dataset", ["power_grid", "humanoid", "figure2"])
def test_simulate_quiet_prints_nothing(tmp_path, capsys, dataset):
    out = tmp_path / ("d.csv" if dataset == "figure2" else "d.npz")
    assert main(["simulate", dataset, "-o", str(out), "--quiet"]) == 0
    assert out.exists()
    assert capsys.readouterr().out == ""
