"""Separator follows the scikit-learn estimator contract (clone, get/set_params, predict)."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import Basis, Convex, Even, NetworkSolver, Orthogonal, ParametricBasis, Separator
from odnn_sep.errors import InputError, NotFittedError, NotIdentifiableError

x = np.linspace(-2, 2, 201)
basis = Basis([lambda x: x ** 3, lambda x: np.sin(3 * x)], names=["c", "s"])
y = 0.5 * x ** 3 - 0.2 * np.sin(3 * x) + np.cos(x)


def test_init_only_stores_and_get_set_params_round_trip():
    sep = Separator(basis, disturbance=Even(), solver="exact", random_state=3, n_starts=2, epochs=5, lr=0.1)
    p = sep.get_params()
    assert list(p) == ["basis", "disturbance", "solver", "random_state", "n_starts", "epochs", "lr"]
    assert p["disturbance"] == Even() and p["basis"] is basis
    Separator(basis, disturbance="not a class", solver="nope", n_starts=-1)      # no validation before fit
    assert sep.set_params(n_starts=4, lr=0.2) is sep and (sep.n_starts, sep.lr) == (4, 0.2)
    with pytest.raises(InputError, match="parameter must be one of 'basis'"):
        sep.set_params(depth=3)
    with pytest.raises(InputError, match="has no parameters to set"):
        sep.set_params(basis__names=["a"])
    assert repr(sep).startswith("Separator(basis=Basis(names=['c', 's']), disturbance=Even(")


def test_sklearn_clone_gives_an_unfitted_equal_estimator():
    base = pytest.importorskip("sklearn.base", reason="scikit-learn is needed to test clone")
    sep = Separator(basis, disturbance=Even(), random_state=1).fit(x, y)
    twin = base.clone(sep)
    assert not hasattr(twin, "result_") and twin.get_params(deep=False).keys() == sep.get_params(deep=False).keys()
    np.testing.assert_array_equal(twin.fit(x, y).theta_, sep.theta_)
    net = base.clone(Separator(basis, solver=NetworkSolver(epochs=3)))
    assert isinstance(net.solver, NetworkSolver) and net.solver.epochs == 3


def test_predict_linear_and_parametric_and_errors():
    sep = Separator(basis, disturbance=Even())
    with pytest.raises(NotFittedError, match="not fitted yet"):
        sep.predict(x)
    sep.fit(x, y)
    assert np.array_equal(sep.predict(x), sep.result_.physics)
    xn = np.array([2.5, 3.0])
    np.testing.assert_allclose(sep.predict(xn), 0.5 * xn ** 3 - 0.2 * np.sin(3 * xn), atol=1e-9)
    with pytest.raises(InputError, match="2 coordinate"):
        sep.predict(np.ones((3, 2)))

    pb = ParametricBasis(lambda t, xp=np, f=1.0: xp.sin(2 * np.pi * f * t), {"f": 1.0}, names=["a"],
                         bounds={"f": (0.5, 2.0)}, grid={"f": np.linspace(0.5, 2, 31)})
    t = np.linspace(0, 5, 400)
    sp = Separator(pb, disturbance=Orthogonal()).fit(t, 0.7 * np.sin(2 * np.pi * 1.3 * t))
    np.testing.assert_allclose(sp.predict(np.array([7.1])), 0.7 * np.sin(2 * np.pi * 1.3 * 7.1), atol=1e-6)

    xc = np.linspace(-1, 1, 50)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        sc = Separator(Basis([lambda x: np.sin(5 * x)], names=["s"]), disturbance=Convex(),
                       random_state=0).fit(xc, xc ** 2 + np.sin(5 * xc))
    with pytest.raises(NotIdentifiableError, match="only set-identified"):
        sc.predict(xc)
