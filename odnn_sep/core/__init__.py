"""The separation engine: bases, disturbance classes, exact and network solvers.

Knows only matrices, functions and constraints; nothing here imports a front-end.
"""
from odnn_sep.core.basis import Basis, ParametricBasis
from odnn_sep.core.disturbance import Band, Convex, Even, Monotone, Orthogonal, Periodic, Subspace
from odnn_sep.core.result import Result
from odnn_sep.core.separator import Separator

__all__ = ["Basis", "ParametricBasis", "Separator", "Result", "Orthogonal", "Even", "Periodic", "Band",
           "Subspace", "Convex", "Monotone"]
