"""The Disturbance interface, user-written classes, identification, and solvers as objects."""
import warnings

import numpy as np
import pytest

from odnn_sep.core import (
    Band,
    Basis,
    ConeDisturbance,
    Convex,
    Disturbance,
    Even,
    ExactSolver,
    Monotone,
    NetworkSolver,
    Orthogonal,
    Periodic,
    Separator,
    Solver,
    Subspace,
    SubspaceDisturbance,
    register_solver,
)
from odnn_sep.core import solvers as solvers_mod
from odnn_sep.core.bounds import efficiency_bound
from odnn_sep.core.linalg import Projector
from odnn_sep.errors import InputError

x = np.linspace(-2, 2, 201)
odd = Basis([lambda x: x ** 3, lambda x: np.sin(3 * x)], names=["c", "s"])


def test_shipped_classes_subclass_their_family():
    for d in (Even(), Periodic(1.0), Band(0, 1), Subspace(np.ones((5, 1)))):
        assert isinstance(d, SubspaceDisturbance) and d.identification == "point"
    for d in (Convex(), Monotone()):
        assert isinstance(d, ConeDisturbance) and d.identification == "set"
    assert isinstance(Orthogonal(), Disturbance) and Orthogonal.supports_weights
    with pytest.raises(TypeError):
        Disturbance()
    with pytest.raises(TypeError):
        SubspaceDisturbance()


def test_identifies_point_set_and_none():
    F = odd.evaluate(x)
    ok = Even().identifies(F, x)
    assert ok.identified == "point" and np.allclose(ok.outside_fraction, 1) and ok.condition < 10 and not ok.weak
    inside = Even().identifies(np.c_[x ** 2, x], x)
    assert inside.identified == "none" and inside.outside_fraction[0] < 1e-12
    assert Orthogonal().identifies(F, x).identified == "point"
    assert Convex().identifies(F, x).identified == "set"
    assert Convex().identifies(np.c_[x, x ** 3], x).identified == "none"      # a line is a free direction


class Quadratic(SubspaceDisturbance):
    """g is a quadratic polynomial in x (a user-written subspace class)."""

    def describe(self):
        return "quadratic"

    def projector(self, x):
        return Projector(np.c_[np.ones_like(x), x, x ** 2])


def test_user_subspace_class_gets_exact_fit_phi_bound_and_network():
    y = 1.5 * x ** 3 - 0.4 * np.sin(3 * x) + 2 - x + 0.7 * x ** 2
    r = Separator(odd, disturbance=Quadratic()).fit(x, y).result_
    np.testing.assert_allclose(r.theta, [1.5, -0.4], atol=1e-10)
    assert r.disturbance_class == "quadratic" and r.identified == "point"
    assert r.diagnostics["disturbance_rank"] == 3
    cov = efficiency_bound(odd, Quadratic(), x, r.theta, sigma=0.1)
    assert cov.shape == (2, 2) and np.all(np.diag(cov) > 0)
    rn = Separator(odd, disturbance=Quadratic(), solver=NetworkSolver(epochs=30), random_state=0).fit(x, y).result_
    assert rn.solver == "network"
    np.testing.assert_allclose(rn.theta, r.theta, atol=1e-4)


class Concave(ConeDisturbance):
    """g is concave: the convex class's generators, negated (a user-written cone class)."""

    def describe(self):
        return "concave"

    def generators(self, x_sorted):
        A, H = Convex().generators(x_sorted)
        return A, -H

    def full_generator_count(self, n):
        return n - 2


def test_user_cone_class_is_set_identified():
    xc = np.linspace(-1, 1, 60)
    y = -xc ** 2 + np.sin(5 * xc)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = Separator(Basis([lambda x: np.sin(5 * x)], names=["s"]), disturbance=Concave(),
                      random_state=0).fit(xc, y).result_
    assert r.identified == "set" and r.interval[0, 0] <= 1.0 <= r.interval[0, 1]
    with pytest.raises(InputError, match="only set-identifies"):
        efficiency_bound(Basis([np.sin], names=["s"]), Concave(), xc, [1.0], sigma=0.1)


def test_solver_objects_and_registry():
    y = 0.5 * x ** 3 + np.cos(x)
    a = Separator(odd, disturbance=Even()).fit(x, y).result_
    b = Separator(odd, disturbance=Even(), solver=ExactSolver()).fit(x, y).result_
    assert np.array_equal(a.theta, b.theta) and b.solver == "exact"

    class Halving(Solver):
        name = "halving"

        def __init__(self, epochs=None):
            self.epochs = epochs

        def solve(self, problem):
            out = ExactSolver().solve(problem)
            return {**out, "theta": out["theta"] / 2}

    register_solver("halving-test", Halving)
    try:
        c = Separator(odd, disturbance=Even(), solver="halving-test", epochs=7).fit(x, y).result_
        np.testing.assert_allclose(c.theta, a.theta / 2)
        assert c.solver == "halving"
        assert solvers_mod.get_solver("halving-test", epochs=7, lr=1.0).epochs == 7
        with pytest.raises(InputError, match="already registered"):
            register_solver("halving-test", Halving)
        register_solver("halving-test", Halving, replace=True)
    finally:
        solvers_mod.unregister_solver("halving-test")
    with pytest.raises(InputError, match="already registered"):
        register_solver("exact", Halving)
    with pytest.raises(InputError, match="factory must be callable"):
        register_solver("x-test", 3)
    assert "halving-test" not in solvers_mod.registered_solvers()
    with pytest.raises(InputError, match="cannot be removed"):
        solvers_mod.unregister_solver("exact")
    with pytest.raises(InputError, match="registered name or a Solver"):
        Separator(odd, solver=3).fit(x, y)

    class EvenOnly(ExactSolver):
        name = "even-only"

        def supports(self, disturbance):
            return isinstance(disturbance, Even)

    with pytest.raises(InputError, match="solver 'even-only' does not handle the convex disturbance class"):
        Separator(odd, disturbance=Convex(), solver=EvenOnly()).fit(x, y)


def test_network_solver_options_come_from_the_separator():
    s = solvers_mod.get_solver("network", epochs=12, lr=0.5)
    assert isinstance(s, NetworkSolver) and (s.epochs, s.lr) == (12, 0.5)
