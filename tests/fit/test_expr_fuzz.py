"""Property fuzz of the --basis evaluator: any string gives a finite column or one InputError,
quickly and in little memory (no hang, no RecursionError, no big-integer blow-up)."""
from __future__ import annotations

import time
import tracemalloc

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis", reason="the fuzz test needs hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402

from odnn_sep.errors import InputError  # noqa: E402
from odnn_sep.fit.expr import FUNCS, compile_expression  # noqa: E402

X = np.linspace(-3.0, 3.0, 257)
TIME_S = 1.0
PEAK_BYTES = 64 << 20

atoms = st.one_of(
    st.sampled_from(["x", "pi", "e", "y", "xx", "...", "None", "'s'", "1j", "True", "__import__"]),
    st.integers(-10**6, 10**6).map(str),
    st.sampled_from(["9", "99", "999999999999", "10**100000", "1e300", "1e400", "2**2**40", "9**9**9"]),
    st.floats(allow_nan=False, allow_infinity=False, width=32).map(repr),
)


def _combine(children):
    ops = st.sampled_from(["+", "-", "*", "/", "**", "%", "//", "<", ">=", "==", "and", "|", "@"])
    unary = st.sampled_from(["-", "+", "~", "not "])
    funcs = st.sampled_from(sorted(FUNCS) + ["eval", "open", "getattr"])
    return st.one_of(
        st.tuples(children, ops, children).map(lambda t: f"({t[0]}{t[1]}{t[2]})"),
        st.tuples(unary, children).map(lambda t: f"{t[0]}{t[1]}"),
        st.tuples(funcs, st.lists(children, min_size=0, max_size=3)).map(lambda t: f"{t[0]}({', '.join(t[1])})"),
        st.tuples(children, children, children).map(lambda t: f"{t[0]}<{t[1]}<{t[2]}"),
        st.tuples(children, st.sampled_from([".real", "[0]", "()", " if x else 1"])).map(lambda t: t[0] + t[1]),
    )


expressions = st.one_of(st.recursive(atoms, _combine, max_leaves=40), st.text(max_size=200),
                        st.integers(1, 3000).map(lambda n: "(" * n + "x" + ")" * n),
                        st.integers(1, 3000).map(lambda n: "-" * n + "x"))


def _bounded(expr):
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        col = compile_expression(expr, ("x",))(X)
    except InputError as exc:
        col = None
        assert str(exc) and "\n" not in str(exc)
    elapsed = time.perf_counter() - t0
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return col, elapsed, peak


@settings(max_examples=400, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(expressions)
def test_any_expression_is_a_finite_column_or_one_clear_error(expr):
    col, elapsed, peak = _bounded(expr)
    assert elapsed < TIME_S, f"{expr!r} took {elapsed:.2f} s"
    assert peak < PEAK_BYTES, f"{expr!r} used {peak / 2**20:.0f} MiB"
    if col is not None:
        assert col.shape == X.shape and np.isfinite(col).all()


@pytest.mark.parametrize("expr, msg", [
    ("9**9**9", "exponents are limited"),
    ("x*2**2**40", "exponents are limited"),
    ("x*10**100000", "exponents are limited"),
    ("(" * 500 + "x" + ")" * 500, "nested"),
    ("-" * 100 + "x", "nested more than"),
    ("foo(x)", "unknown function 'foo'"),
    ("xx", "unknown name 'xx'"),
    ("...", "not a number"),
    ("0 < x < 1", "chains comparisons"),
    ("x" + "+x" * 1200, "characters long"),
    ("sin(x)\nx", "control character"),
])
def test_documented_refusals(expr, msg):
    with pytest.raises(InputError, match=msg):
        compile_expression(expr, ("x",))(X)
