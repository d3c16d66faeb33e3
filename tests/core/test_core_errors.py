"""Every bad input gets one clear error, tested with its exact message."""
import numpy as np
import pytest

from odnn_sep.core import Band, Basis, Even, Periodic, Separator
from odnn_sep.errors import InputError, NotIdentifiableError

x = np.linspace(-1, 1, 101)
b = Basis([lambda x: x ** 3], names=["a"])


def fit(basis, y, x=x, dist=None):
    return Separator(basis, disturbance=dist).fit(x, y)


def test_empty():
    with pytest.raises(InputError, match=r"y is empty \(shape \(0,\)\); pass at least one sample"):
        fit(b, [], x=[])


def test_nan_reported_with_count_and_first_index():
    y = x.copy()
    y[[5, 9]] = np.nan
    with pytest.raises(InputError, match=r"y contains 2 NaN value\(s\) \(first at index 5\)"):
        fit(b, y)


def test_inf_reported_separately():
    y = x.copy()
    y[7] = np.inf
    with pytest.raises(InputError, match=r"y contains 1 inf value\(s\) \(first at index 7\)"):
        fit(b, y)


def test_mismatched_shapes():
    with pytest.raises(InputError, match="x has 101 samples but y has 100; they must have the same length"):
        fit(b, x[:100])


def test_zero_column():
    with pytest.raises(InputError, match="basis column 'z' is all zeros at the given x"):
        fit(Basis([lambda x: 0 * x], names=["z"]), x)


def test_duplicate_columns():
    bb = Basis([lambda x: x, lambda x: 2 * x], names=["p", "q"])
    with pytest.raises(InputError, match="basis columns 'p' and 'q' are duplicates"):
        fit(bb, x)


def test_too_few_samples():
    bb = Basis([lambda x: x, lambda x: x ** 2, lambda x: x ** 3], names=["a", "b", "c"])
    with pytest.raises(InputError, match=r"too few samples: n=3 for 3 parameter\(s\); need at least 4"):
        fit(bb, [1.0, 2.0, 3.0], x=[0.1, 0.2, 0.3])


def test_period_longer_than_half_span():
    with pytest.raises(InputError, match=r"Periodic\(period=1.5\) does not fit the sampling: the data span 2 holds"):
        fit(b, x, dist=Periodic(1.5))


def test_period_below_two_samples():
    with pytest.raises(InputError, match="shorter than two sample steps"):
        fit(b, x, dist=Periodic(0.01))


def test_band_above_nyquist():
    with pytest.raises(InputError, match=r"Band\(lo=100, hi=200\) does not fit the sampling: lo is above the Nyquist"):
        fit(b, x, dist=Band(100, 200))


def test_nonuniform_band():
    xx = np.sort(np.random.default_rng(0).random(50))
    with pytest.raises(InputError, match="Band needs uniformly spaced x"):
        fit(b, xx, x=xx, dist=Band(0, 3))


def test_basis_inside_disturbance_class():
    with pytest.raises(NotIdentifiableError, match="basis column 'e' lies inside the disturbance class"):
        fit(Basis([lambda x: x ** 2], names=["e"]), x, dist=Even())


def test_asymmetric_grid_for_even():
    xx = np.linspace(-1, 2, 50)
    with pytest.raises(InputError, match="samples have no mirror image"):
        fit(b, xx, x=xx, dist=Even())


def test_unknown_solver_and_class():
    with pytest.raises(InputError, match="solver must be one of 'exact', 'network'; got 'magic'"):
        Separator(b, solver="magic").fit(x, x)
    with pytest.raises(InputError, match="disturbance must be a Disturbance instance"):
        Separator(b, disturbance="even").fit(x, x)


def test_caller_arrays_not_mutated():
    y = np.cos(x) + x ** 3
    y0, x0 = y.copy(), x.copy()
    fit(b, y, dist=Even())
    np.testing.assert_array_equal(y, y0)
    np.testing.assert_array_equal(x, x0)


def test_check_option_and_check_type_messages():
    from odnn_sep.errors import check_option, check_type

    check_option("method", "qr", ("qr", "svd"))
    with pytest.raises(InputError, match=r"^method must be one of 'qr', 'svd'; got 'lu'$"):
        check_option("method", "lu", ("qr", "svd"))
    with pytest.raises(InputError, match="got \\[1\\]"):
        check_option("method", [1], ("qr",))           # unhashable values are reported, not crashed on
    check_type("n", 3, (int, float))
    with pytest.raises(InputError, match=r"^n must be int or float; got str \('3'\)$"):
        check_type("n", "3", (int, float))
    with pytest.raises(InputError, match="n must be a count; got NoneType"):
        check_type("n", None, int, "a count")


def test_every_exception_of_the_engine_lives_in_errors_py():
    import ast
    from pathlib import Path

    import odnn_sep.errors as errors

    core = Path(errors.__file__).parent / "core"
    for path in core.glob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, ast.ClassDef):
                assert not node.name.endswith(("Error", "Warning", "Exception")), f"{path.name}: {node.name}"
            if isinstance(node, ast.Raise) and isinstance(node.exc, ast.Call):
                name = getattr(node.exc.func, "id", "")
                assert name not in ("ValueError", "TypeError", "RuntimeError"), f"bare {name} in {path.name}"
    assert issubclass(errors.ModelIntegrationError, errors.InputError)
    assert issubclass(errors.NotFittedError, AttributeError)


@pytest.mark.parametrize("kw, msg", [({"n_starts": 0}, "n_starts must be >= 1; got 0"),
                                     ({"n_starts": 2.5}, "n_starts must be an integer; got float"),
                                     ({"epochs": -1}, "epochs must be >= 0"),
                                     ({"lr": 0.0}, "lr must be a finite number > 0"),
                                     ({"lr": "fast"}, "lr must be a number; got str")])
def test_separator_options_are_checked_in_fit(kw, msg):
    sep = Separator(b, **kw)                    # __init__ only stores
    with pytest.raises(InputError, match=msg):
        sep.fit(x, x)
