"""The shipped shape (cone) classes: convex and monotone disturbances on 1-D x.

They only set-identify theta (see :mod:`odnn_sep.core.cone`); re-exported by
:mod:`odnn_sep.core.disturbance` and :mod:`odnn_sep.core`.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from odnn_sep.core.base import ConeDisturbance
from odnn_sep.core.cone import thin_knots

__all__ = ["Convex", "Monotone"]


@dataclass(frozen=True)
class Convex(ConeDisturbance):
    """g is a convex function of 1-D x. Only set-identifies theta (cone, not subspace).

    Examples
    --------
    >>> import numpy as np
    >>> A, H = Convex().generators(np.linspace(0, 1, 5))   # constant and line free, a hinge per interior sample
    >>> A.shape, H.shape
    ((5, 2), (5, 3))
    """

    def describe(self) -> str:
        return "convex"

    def generators(self, x_sorted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # free: constant and line; cone: a hinge at every interior sample
        knots = thin_knots(x_sorted[1:-1])
        H = np.maximum(x_sorted[:, None] - knots[None, :], 0.0)
        return np.hstack([np.ones((x_sorted.size, 1)), x_sorted[:, None]]), H

    def full_generator_count(self, n: int) -> int:
        return n - 2

    def network(self, in_dim: int = 1, hidden: int = 32, depth: int = 3) -> object:
        from odnn_sep.core.nets import ICNN

        return ICNN(in_dim, hidden, depth)


@dataclass(frozen=True)
class Monotone(ConeDisturbance):
    """g is monotone in 1-D x (non-decreasing, or non-increasing with ``increasing=False``).

    Examples
    --------
    >>> import numpy as np
    >>> A, H = Monotone(increasing=False).generators(np.arange(4.0))   # a step down at every sample
    >>> H[:, 0].tolist()
    [-0.0, -1.0, -1.0, -1.0]
    """

    increasing: bool = True

    def describe(self) -> str:
        return "monotone " + ("non-decreasing" if self.increasing else "non-increasing")

    def generators(self, x_sorted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        # free: constant; cone: a step up (or down) at every sample
        steps = (x_sorted[:, None] >= thin_knots(x_sorted[1:])[None, :]).astype(float)
        return np.ones((x_sorted.size, 1)), steps if self.increasing else -steps

    def full_generator_count(self, n: int) -> int:
        return n - 1

    def network(self, in_dim: int = 1, hidden: int = 32, depth: int = 3) -> object:
        from odnn_sep.core.nets import MonotoneMLP

        # monotone in the original x: the solver's standardisation keeps the direction (scale > 0)
        return MonotoneMLP(in_dim, hidden, depth, increasing=self.increasing)
