"""Parameters that only enter a model as a combination get no interval and a warning, never tight ones."""
import warnings

import numpy as np
import pytest

from odnn_sep.mismatch import custom_model, explain


def _record():
    t = np.linspace(0, 10, 300)
    return t, 6.0 * np.exp(-0.3 * t) + 0.01 * np.random.default_rng(3).normal(size=t.size)


@pytest.mark.parametrize("func, start, group", [
    (lambda t, a, b, k: a * b * np.exp(-k * t), {"a": 1.0, "b": 1.0, "k": 0.5}, {"a", "b"}),
    (lambda t, a, k1, k2: a * np.exp(-(k1 + k2) * t), {"a": 1.0, "k1": 0.1, "k2": 0.3}, {"k1", "k2"}),
    (lambda t, a, k, c: a * np.exp(-k * t), {"a": 1.0, "k": 0.5, "c": 3.0}, {"c"}),
])
def test_a_combination_is_not_reported_with_tight_intervals(func, start, group):
    t, y = _record()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain(custom_model(func, start), t, y)
    params = res.as_dict()["fit"]["after"]["parameters"]
    # a product of 6 split as 2.63 x 2.28 was reported as a = 2.6286 [2.6277, 2.6296]
    assert all(params[k]["interval95"] is None and params[k]["stderr"] is None for k in group)
    # the determined parameters keep theirs, and cover the truth
    others = [k for k in start if k not in group]
    assert all(params[k]["interval95"] is not None for k in others)
    assert any("not identifiable" in w and all(k in w for k in group) for w in res.warnings)
    assert res.effects == []


def test_an_ill_conditioned_but_identified_model_is_not_flagged():
    t, y = _record()
    # two exponentials, one of them with almost no amplitude: condition ~1e3, every parameter determined
    m = custom_model(lambda t, a, k, b, k2: a * np.exp(-k * t) + b * np.exp(-k2 * t),
                     {"a": 3.0, "k": 0.5, "b": 3.0, "k2": 0.2})
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain(m, t, y)
    assert not any("not identifiable" in w for w in res.warnings)
    params = res.as_dict()["fit"]["after"]["parameters"]
    assert all(params[k]["interval95"] is not None for k in ("a", "k"))


def test_a_constant_input_column_leaves_ambient_and_gain_without_intervals(tmp_path, capsys):
    from odnn_sep.cli import main
    t = np.linspace(0, 3000, 300)
    y = 20 + 60 * np.exp(-0.001 * t) + 0.05 * np.random.default_rng(5).normal(size=t.size)
    f = tmp_path / "cool_u.csv"
    f.write_text("t,T,P\n" + "".join(f"{a!r},{b!r},5.0\n" for a, b in zip(t.tolist(), y.tolist())))
    assert main(["mismatch", str(f), "--model", "cooling", "--column", "T", "--input", "P",
                 "--effects", "radiation"]) == 0
    out = capsys.readouterr().out
    # it printed T_ambient = 0.3348 +- 0.01038 [95%: 0.3133, 0.3563] for an ambient of 20
    line = next(s for s in out.splitlines() if s.strip().startswith("T_ambient ="))
    assert "interval not determined" in line
    assert "T_ambient, kd_P are not identifiable" in out and "the input 'P' does not vary" in out
