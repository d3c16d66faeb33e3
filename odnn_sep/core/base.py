"""The disturbance-class interface: what a class must say for the separator and both solvers to use it.

Three families cover the shipped classes, and a new class subclasses the one it belongs to:

- :class:`Disturbance` (abstract): the interface.
- :class:`SubspaceDisturbance`: g lies in a linear subspace that depends on the sample points;
  a subclass writes :meth:`~SubspaceDisturbance.projector` and :meth:`~Disturbance.describe`, and
  inherits the exact projection solver, variable projection for phi, the network projection
  layer, the Cramér–Rao bound and the identification check.
- :class:`ConeDisturbance`: g lies in a convex cone given by generators (shape constraints); theta
  is only set-identified. A subclass writes :meth:`~ConeDisturbance.generators`,
  :meth:`~ConeDisturbance.full_generator_count`, :meth:`~Disturbance.network` and ``describe``.

``Orthogonal`` (explicit orthogonality to the physics) subclasses :class:`Disturbance` directly.
"""
from __future__ import annotations

import abc
from dataclasses import dataclass
from typing import Any, Callable, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.core.checks import outside_class_report
from odnn_sep.core.projection import BaseProjector
from odnn_sep.errors import InputError

__all__ = ["Disturbance", "SubspaceDisturbance", "ConeDisturbance", "Identification", "Problem"]


@dataclass(frozen=True)
class Problem:
    """One separation problem as the solvers see it (physics columns already evaluated at phi).

    ``prepared`` is what ``disturbance.prepare(x)`` returned (a projector for subspace classes).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Orthogonal
    >>> x = np.linspace(0, 1, 20)
    >>> out = Orthogonal().fit_exact(Problem(np.c_[x], x, 3 * x, None, ("a",), Orthogonal()))
    >>> round(float(out["theta"][0]), 9)
    3.0
    """

    F: np.ndarray
    x: np.ndarray
    y: np.ndarray
    weights: np.ndarray | None
    names: tuple
    disturbance: "Disturbance"
    prepared: Any = None
    random_state: int | None = None


@dataclass(frozen=True)
class Identification:
    """What the data can say about theta with this class: ``identified`` is ``"point"``, ``"set"`` or ``"none"``.

    ``outside_fraction[j]`` is the share of column j's norm outside the class (or outside the
    cone's free directions), ``condition`` the condition number of the projected, normalised
    columns. ``"none"``: a column (nearly) lies inside the class, or the projected columns are
    collinear (condition > 1e10).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Even
    >>> x = np.linspace(-1, 1, 11)
    >>> Even().identifies(np.c_[x], x).identified, Even().identifies(np.c_[x**2], x).identified
    ('point', 'none')
    """

    identified: str
    outside_fraction: np.ndarray
    condition: float

    @property
    def weak(self) -> bool:
        """Identified, but with < 1 % of some column outside the class or condition > 1e6."""
        return self.identified != "none" and (bool((self.outside_fraction < 1e-2).any()) or self.condition > 1e6)


class Disturbance(abc.ABC):
    """Where the unmodelled part g(x) is allowed to live: the interface every class implements.

    Class attributes
    ----------------
    identification : {"point", "set"}
        Whether theta is a point (linear classes) or only an interval (cones).
    supports_weights : bool
        Whether ``Separator.fit(..., weights=...)`` is meaningful for the class.

    Subclass :class:`SubspaceDisturbance` or :class:`ConeDisturbance` rather than this class
    directly; the README ("Your own disturbance class") has a complete example.

    Examples
    --------
    >>> from odnn_sep.core import Convex, Disturbance, Even
    >>> isinstance(Even(), Disturbance), Even().identification, Convex().identification
    (True, 'point', 'set')
    """

    identification: ClassVar[str] = "point"
    supports_weights: ClassVar[bool] = False

    @abc.abstractmethod
    def describe(self) -> str:
        """A short phrase for reports: ``"even (mirror-symmetric) about 0"``."""

    def check_inputs(self, x: np.ndarray, weights: np.ndarray | None) -> None:
        """Reject sample points or weights this class cannot use (one-line InputError)."""
        if weights is not None and not self.supports_weights:
            raise InputError(f"weights are supported only with Orthogonal(); got disturbance {self!r}")

    def prepare(self, x: np.ndarray) -> object:
        """What the solvers reuse for these sample points (a projector for subspace classes); None here."""
        return None

    @abc.abstractmethod
    def fit_exact(self, problem: Problem) -> dict:
        """The exact solver's answer for ``problem`` (see :mod:`odnn_sep.core.exact`)."""

    @abc.abstractmethod
    def identifies(self, F: ArrayLike, x: ArrayLike) -> Identification:
        """Whether theta in ``y = F theta + g`` is point-, set- or not identified for g in this class.

        Parameters
        ----------
        F : array_like, shape (n, p)
            Physics columns at the sample points.
        x : array_like
            Sample points.
        """

    @abc.abstractmethod
    def reduced_residual(self, design: Callable, x: np.ndarray, y: np.ndarray, weights: np.ndarray | None,
                         prepared: Any) -> tuple[Callable, bool]:
        """``(residual(phi), scalar)`` for variable projection over the nonlinear parameters.

        ``scalar`` is True when the residual is not smooth in phi (then a derivative-free search is used).
        """

    def nuisance_rank(self, prepared: Any) -> int:
        """Dimension the class takes from the residual degrees of freedom (0 when not a subspace)."""
        return 0

    def project_out(self, M: np.ndarray, x: ArrayLike) -> np.ndarray:
        """The part of the columns ``M`` the class cannot imitate (for the efficiency bound)."""
        raise InputError(f"{type(self).__name__} is not a linear class; it only set-identifies theta")

    def network(self, in_dim: int = 1, hidden: int = 32, depth: int = 3) -> object:
        """The torch module the network solver trains for g (an unconstrained MLP by default)."""
        from odnn_sep.core.nets import MLP

        return MLP(in_dim, hidden, depth)

    def network_layer(self, Fn: Any, sw: Any, prepared: Any) -> tuple[Callable, Any]:
        """``(layer, F_perp)`` for the network solver: ``layer(h)`` confines the network output to the
        class; ``F_perp`` (or None) is the part of the scaled columns ``Fn`` outside the class, when
        the loss splits into a theta part and a network part. The identity by default (the
        architecture itself enforces the class)."""
        return (lambda h: h), None


class SubspaceDisturbance(Disturbance):
    """A linear class: g lies in a subspace of R^n given by an orthogonal projector.

    Subclasses implement :meth:`projector` and :meth:`~Disturbance.describe`. ``prepare`` is the
    projector (the name the classes have always used).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Separator, SubspaceDisturbance
    >>> from odnn_sep.core.linalg import Projector
    >>> class Constant(SubspaceDisturbance):
    ...     def describe(self):
    ...         return "constant"
    ...     def projector(self, x):
    ...         return Projector(np.ones((x.size, 1)))
    >>> x = np.arange(10.0)
    >>> sep = Separator(Basis([lambda x: x], names=["slope"]), disturbance=Constant()).fit(x, 2 * x + 7)
    >>> round(float(sep.theta_[0]), 9)
    2.0
    """

    @abc.abstractmethod
    def projector(self, x: np.ndarray) -> BaseProjector:
        """The orthogonal projector onto the class at sample points ``x``."""

    def prepare(self, x: np.ndarray) -> BaseProjector:
        return self.projector(x)

    def fit_exact(self, problem: Problem) -> dict:
        from odnn_sep.core.exact import fit_linear_class

        return fit_linear_class(problem, problem.prepared)

    def identifies(self, F: ArrayLike, x: ArrayLike) -> Identification:
        F = np.asarray(F, dtype=float)
        return _identification(F, self.projector(np.asarray(x, dtype=float)).project_out(F), "point")

    def reduced_residual(self, design: Callable, x: np.ndarray, y: np.ndarray, weights: np.ndarray | None,
                         prepared: Any) -> tuple[Callable, bool]:
        from odnn_sep.core.linalg import varpro_residual

        return varpro_residual(design, y, project_out=prepared.project_out, weights=weights), False

    def nuisance_rank(self, prepared: Any) -> int:
        return int(prepared.rank)

    def project_out(self, M: np.ndarray, x: ArrayLike) -> np.ndarray:
        return self.projector(np.asarray(x, dtype=float)).project_out(M)

    def network_layer(self, Fn: Any, sw: Any, prepared: Any) -> tuple[Callable, Any]:
        import torch

        # Reparametrise g' = g + P F theta (same class): the loss then splits into a theta part on
        # (I - P) and a network part on P, exactly as Eq. 3 does for the orthogonal case.
        Fperp = Fn - torch.stack([prepared.apply_torch(Fn[:, j].contiguous()) for j in range(Fn.shape[1])], 1)
        return prepared.apply_torch, Fperp


class ConeDisturbance(Disturbance):
    """A shape class on 1-D x: ``g = A u + H d`` with u free and d >= 0 (a polyhedral cone).

    Theta is only set-identified; the exact solver reports the identified interval (see
    :mod:`odnn_sep.core.cone`). Subclasses implement :meth:`generators`,
    :meth:`full_generator_count`, :meth:`~Disturbance.network` and ``describe``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import ConeDisturbance, Convex
    >>> class Concave(ConeDisturbance):
    ...     def describe(self):
    ...         return "concave"
    ...     def generators(self, x_sorted):
    ...         A, H = Convex().generators(x_sorted)
    ...         return A, -H
    ...     def full_generator_count(self, n):
    ...         return n - 2
    >>> x = np.linspace(-1, 1, 21)
    >>> Concave().identification, Concave().identifies(np.c_[np.sin(5 * x)], x).identified
    ('set', 'set')
    """

    identification: ClassVar[str] = "set"

    @abc.abstractmethod
    def generators(self, x_sorted: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(A, H)`` at increasing sample points: free directions A (n, a), cone generators H (n, m)."""

    @abc.abstractmethod
    def full_generator_count(self, n: int) -> int:
        """How many generators describe the cone exactly on n samples (fewer: an inner approximation)."""

    def check_inputs(self, x: np.ndarray, weights: np.ndarray | None) -> None:
        super().check_inputs(x, weights)
        if x.ndim != 1:
            raise InputError(f"{type(self).__name__} needs 1-D x; got shape {x.shape}")

    def fit_exact(self, problem: Problem) -> dict:
        from odnn_sep.core.exact import fit_cone_class

        return fit_cone_class(problem)

    def identifies(self, F: ArrayLike, x: ArrayLike) -> Identification:
        from odnn_sep.core.projection import Projector

        F = np.asarray(F, dtype=float)
        x = np.asarray(x, dtype=float)
        A, _ = self.generators(np.sort(x))
        ident = _identification(F, Projector(A).project_out(F[np.argsort(x, kind="stable")]), "set")
        return ident

    def reduced_residual(self, design: Callable, x: np.ndarray, y: np.ndarray, weights: np.ndarray | None,
                         prepared: Any) -> tuple[Callable, bool]:
        from odnn_sep.core import cone

        order = np.argsort(x)
        A0, H = self.generators(x[order])
        ys = y[order]

        def resid(v):
            return np.array([np.sqrt(cone.cone_lstsq(np.hstack([design(v)[order], A0]), H, ys)[2])])

        return resid, True


def _identification(F: np.ndarray, Fp: np.ndarray, identified: str) -> Identification:
    frac, cond = outside_class_report(F, Fp)
    if (frac < 1e-8).any() or cond > 1e10:
        identified = "none"
    return Identification(identified=identified, outside_fraction=frac, condition=cond)
