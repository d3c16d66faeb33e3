"""The separation engine: bases, disturbance classes, exact and network solvers, and the numerics.

Knows only matrices, functions and constraints; nothing here imports a front-end, and nothing
imports torch until the network solver runs.

- :mod:`~odnn_sep.core.linalg`: projections, weighted and complex solves, standard errors,
  intervals, variable projection (what every front-end calls for its algebra);
- :mod:`~odnn_sep.core.base`: the :class:`Disturbance` interface and its subspace and cone families;
  :mod:`~odnn_sep.core.disturbance`: the shipped classes;
- :mod:`~odnn_sep.core.solvers`: :class:`ExactSolver`, :class:`NetworkSolver` and the solver registry;
- :mod:`~odnn_sep.core.separator`: :class:`Separator`, which ties them together into a :class:`Result`.
"""
from odnn_sep.core import linalg
from odnn_sep.core.base import ConeDisturbance, Disturbance, Identification, Problem, SubspaceDisturbance
from odnn_sep.core.basis import Basis, ParametricBasis
from odnn_sep.core.disturbance import Band, Convex, Even, Monotone, Orthogonal, Periodic, Subspace
from odnn_sep.core.result import Result
from odnn_sep.core.separator import Separator
from odnn_sep.core.solvers import (
    ExactSolver,
    NetworkSolver,
    Solver,
    get_solver,
    register_solver,
    unregister_solver,
)

__all__ = ["Basis", "ParametricBasis", "Separator", "Result", "Orthogonal", "Even", "Periodic", "Band",
           "Subspace", "Convex", "Monotone", "Disturbance", "SubspaceDisturbance", "ConeDisturbance",
           "Identification", "Problem", "Solver", "ExactSolver", "NetworkSolver", "register_solver", "unregister_solver", "get_solver",
           "linalg"]
