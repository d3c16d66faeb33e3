"""A record of exactly two whole periods (48 hourly samples, period 24 h) is fitted, not refused."""
import numpy as np
import pytest

from odnn_sep.cli import main
from odnn_sep.core import Basis, Periodic, Separator
from odnn_sep.errors import InputError
from odnn_sep.signals import make_dataset


def test_two_days_of_hourly_samples_take_a_daily_class(tmp_path):
    t = np.arange(48.0)                                   # span 47 h: two whole days of samples
    g = np.where((t % 24) < 8, 1.0, 0.0) + 0.3 * np.sin(2 * np.pi * t / 24)
    y = 0.05 * t + g + 0.01 * np.random.default_rng(0).standard_normal(48)
    r = Separator(Basis([lambda t: t], names=["trend"]), disturbance=Periodic(24)).fit(t, y).result_
    lo, hi = r.interval[0]
    assert lo < 0.05 < hi and hi - lo < 0.01
    f = tmp_path / "hourly.csv"
    np.savetxt(f, np.c_[t, y], delimiter=",", header="hour,load", comments="")
    assert main(["separate", str(f), "--basis", "hour", "--disturbance", "periodic:24", "--quiet"]) == 0


def test_less_than_two_periods_is_still_refused():
    t = np.arange(47.0)
    with pytest.raises(InputError, match="fewer than two periods"):
        Separator(Basis([lambda t: t], names=["trend"]), disturbance=Periodic(24)).fit(t, np.sin(t))


@pytest.mark.parametrize("name, size", [("population", {"years": 2, "per_year": 12}),
                                        ("biology", {"days": 2, "per_day": 24}),
                                        ("pendulum", {"periods": 2, "per_period": 20})])
def test_generators_at_two_periods_give_data_their_class_takes(name, size):
    ds = make_dataset(name, random_state=1, **size)
    Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y)
