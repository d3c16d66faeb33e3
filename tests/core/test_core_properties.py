"""Property tests: projectors are idempotent, classes are respected, the parts add up."""
import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

from odnn_sep.core import Band, Basis, Even, Periodic, Separator

finite = st.floats(-10, 10, allow_nan=False)


@settings(max_examples=40, deadline=None)
@given(st.lists(finite, min_size=40, max_size=40), st.sampled_from(["even", "periodic", "band"]))
def test_projector_idempotent_and_symmetric(v, which):
    x = np.linspace(-1, 1, 40)
    dist = {"even": Even(), "periodic": Periodic(0.4 * 39 / 40 * 2 / 2 * (40 / 39)), "band": Band(0, 5)}[which]
    if which == "periodic":
        dist = Periodic(8 * (x[1] - x[0]))
    P = dist.prepare(x)
    v = np.asarray(v)
    Pv = P.apply(v)
    np.testing.assert_allclose(P.apply(Pv), Pv, atol=1e-9)
    w = np.cos(np.arange(40.0))
    assert abs(P.apply(v) @ w - v @ P.apply(w)) < 1e-8 * (1 + np.abs(v).sum() * np.abs(w).sum())


@settings(max_examples=30, deadline=None)
@given(st.lists(finite, min_size=51, max_size=51), finite)
def test_parts_add_up_and_even_part_is_even(noise, theta):
    x = np.linspace(-1, 1, 51)
    y = theta * x ** 3 + np.asarray(noise)
    r = Separator(Basis([lambda x: x ** 3], names=["a"]), disturbance=Even()).fit(x, y).result_
    np.testing.assert_allclose(r.physics + r.disturbance + r.residual, y, atol=1e-9)
    np.testing.assert_allclose(r.disturbance, r.disturbance[::-1], atol=1e-9)
