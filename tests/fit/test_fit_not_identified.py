"""Inputs where the disturbance class can imitate the physics: the answer is "not identified", not numbers.

A convex class holds ``x**2``, so with ``y = 2 x**2 + x`` every coefficient <= 2 fits: ``separate``
printed ``x**2 = -1.3e10 +- 6.7e9, identified set [-2.6e10, 2.00004]`` (the profile search read the
rounding of ever larger numbers as an edge). A line lies in the convex class's free part, and three
dependent columns leave theta free: both gave intervals of +-1e11 or +-1e12 with exit 0. With a linear
class the dependent columns were refused without naming them.
"""
import re

import numpy as np
import pytest

from odnn_sep.core import Basis, Convex, Monotone, Separator
from odnn_sep.errors import NotIdentifiableError

X = np.linspace(-1, 1, 201)
NOISE = 0.01 * np.random.default_rng(0).normal(size=X.size)


def _fit(cols, names, y, dist):
    return Separator(Basis([lambda x, f=f: f(x) for f in cols], names=names), disturbance=dist).fit(X, y)


@pytest.mark.parametrize("col, name, y, dist, bound", [
    (lambda x: x**2, "x**2", 2 * X**2 + X, Convex(), "<= 2.0"),
    (lambda x: x, "x", 2 * X + np.exp(X), Monotone(), "<= 2.3"),
    (lambda x: x, "x", 2 * X + np.exp(X), Monotone(increasing=False), ">= 4.6"),
])
def test_one_side_inside_the_class_is_refused_with_the_bound(col, name, y, dist, bound):
    with pytest.raises(NotIdentifiableError, match=f"'{re.escape(name)}' lies inside the .* on one side: every coefficient "
                                                   f"{re.escape(bound)}"):
        _fit([col], [name], y, dist)


def test_a_line_in_the_convex_class_is_refused():
    with pytest.raises(NotIdentifiableError, match="'x' lies inside the disturbance class \\(convex\\)"):
        _fit([lambda x: x], ["x"], 2 * X + np.exp(X), Convex())


@pytest.mark.parametrize("dist", [None, Convex()])
def test_dependent_columns_are_named(dist):
    cols = [lambda x: np.sin(5 * x), lambda x: x**3, lambda x: x**3 + np.sin(5 * x)]
    with pytest.raises(NotIdentifiableError, match="the columns 'sin', 'x3' and 'sum' are linearly dependent"):
        _fit(cols, ["sin", "x3", "sum"], 2 * np.sin(5 * X) + X**2 + NOISE, dist)


def test_bounded_cone_fit_is_unchanged():
    with pytest.warns(UserWarning, match="only set-identified"):
        r = _fit([lambda x: np.sin(5 * x)], ["s"], 2 * np.sin(5 * X) + X**2 + NOISE, Convex()).result_
    lo, hi = r.interval[0]
    assert np.isfinite([lo, hi]).all() and lo < 2 < hi and hi - lo < 0.2


def test_cli_exit_one_and_no_output(tmp_path, capsys):
    from odnn_sep.cli import main

    data, out = tmp_path / "s.csv", tmp_path / "parts.csv"
    np.savetxt(data, np.c_[X, 2 * X**2 + X + NOISE], delimiter=",", header="x,y", comments="")
    code = main(["separate", str(data), "--basis", "x**2", "--disturbance", "convex", "-o", str(out), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 1 and not out.exists()
    assert err.startswith("Error: basis column 'x**2' lies inside the convex") and "not identified" in err
