"""Datasets and fitted separators built by the package pickle, so they can go to worker processes."""
import pickle
from concurrent.futures import ProcessPoolExecutor

import numpy as np
import pytest

from odnn_sep.core import Even, Separator
from odnn_sep.fit.expr import basis_from_expressions
from odnn_sep.signals import NAMES, make_dataset


@pytest.mark.parametrize("name", NAMES)
def test_every_dataset_pickles_and_evaluates_the_same(name):
    ds = make_dataset(name, random_state=3)
    back = pickle.loads(pickle.dumps(ds))
    assert np.array_equal(back.basis.evaluate(back.x), ds.basis.evaluate(ds.x))
    assert np.array_equal(back.y, ds.y)


def _theta(sep_and_data):
    sep, x, y = sep_and_data
    return sep.fit(x, y).result_.theta


def test_expression_basis_fits_in_worker_processes():
    x = np.linspace(-1, 1, 101)
    y = 2 * np.sin(5 * x) + np.cos(x)
    sep = Separator(basis_from_expressions(["sin(5*x)"]), disturbance=Even())
    fitted = pickle.loads(pickle.dumps(sep.fit(x, y)))
    assert np.allclose(fitted.result_.theta, [2.0])
    with ProcessPoolExecutor(2) as pool:
        got = list(pool.map(_theta, [(sep, x, y), (sep, x, 3 * np.sin(5 * x) + x**2)]))
    assert np.allclose(got, [[2.0], [3.0]])
