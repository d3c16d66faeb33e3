"""The shipped disturbance classes: where the unmodelled part g(x) is allowed to live.

Subspace classes (``Even``, ``Periodic``, ``Band``, ``Subspace``) are linear: ``projector(x)``
is an orthogonal projector P onto the class, and theta is exactly the least-squares fit of
``(I - P) y`` on ``(I - P) F``. ``Orthogonal`` is the paper's Eq. 3 (g orthogonal to the basis).
``Convex`` and ``Monotone`` are cones: they only set-identify theta (defined in ``shapes.py``,
re-exported here; see ``cone.py``). The
interface they implement, and that a new class implements, is in :mod:`odnn_sep.core.base`.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable, ClassVar

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.core.base import Disturbance, Identification, Problem, SubspaceDisturbance
from odnn_sep.core.checks import outside_class_report
from odnn_sep.core.projection import BaseProjector, Projector
from odnn_sep.core.projectors import FFTProjector, LabelProjector, OrbitProjector
from odnn_sep.core.shapes import Convex, Monotone
from odnn_sep.errors import InputError

if TYPE_CHECKING:
    from odnn_sep.core.basis import Basis

__all__ = ["Orthogonal", "Even", "Periodic", "Band", "Subspace", "Convex", "Monotone", "DISTURBANCES"]


def _uniform_step(x: np.ndarray, who: str) -> float:
    if x.ndim != 1:
        raise InputError(f"{who} needs 1-D sample points x; got shape {x.shape}")
    if x.size < 3:
        raise InputError(f"{who} needs at least 3 samples; got {x.size}")
    d = np.diff(x)
    dt = float(np.median(d))
    # a record in decreasing order is as uniform: the band's frequency mask is symmetric, so its
    # projection commutes with reversing the samples and the same step serves (its magnitude)
    if dt == 0 or np.max(np.abs(d - dt)) > 1e-6 * abs(dt) + 1e-12 * np.max(np.abs(x)):
        ds = np.diff(np.sort(x))
        step = float(np.median(ds))
        if step > 0 and np.max(np.abs(ds - step)) <= 1e-6 * step + 1e-12 * np.max(np.abs(x)):
            # uniform once sorted: the rows are only out of order, and resampling is the wrong advice
            raise InputError(
                f"{who} needs x in order: the sample points are uniformly spaced ({step:.6g} apart) but not "
                "sorted; sort the rows by x first"
            )
        raise InputError(
            f"{who} needs uniformly spaced x (spacing varies from {d.min():.6g} to {d.max():.6g}); "
            "resample onto a uniform grid first"
        )
    return abs(dt)


@dataclass(frozen=True)
class Orthogonal(Disturbance):
    """g is orthogonal to every basis column (explicit orthogonality, the paper's Eq. 3).

    Theta is then the (weighted) least-squares fit of y on the basis, whatever g is.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Orthogonal, Separator
    >>> x = np.linspace(-1, 1, 201)
    >>> sep = Separator(Basis([lambda x: x], names=["a"]), disturbance=Orthogonal()).fit(x, 2 * x + x**2 - 1 / 3)
    >>> round(float(sep.theta_[0]), 9)
    2.0
    """

    supports_weights: ClassVar[bool] = True

    def describe(self) -> str:
        return "orthogonal to the physics basis (explicit)"

    def fit_exact(self, problem: Problem) -> dict:
        from odnn_sep.core.exact import fit_linear_class

        return fit_linear_class(problem, None)

    def identifies(self, F: ArrayLike, x: ArrayLike) -> Identification:
        F = np.asarray(F, dtype=float)
        frac, cond = outside_class_report(F, F)
        return Identification("none" if cond > 1e10 else "point", frac, cond)

    def reduced_residual(self, design: Callable, x: np.ndarray, y: np.ndarray, weights: np.ndarray | None,
                         prepared: Any) -> tuple[Callable, bool]:
        from odnn_sep.core.linalg import varpro_residual

        return varpro_residual(design, y, weights=weights), False

    def project_out(self, M: np.ndarray, x: ArrayLike) -> np.ndarray:
        # The class is the orthogonal complement of the physics columns: nothing of F lies in it.
        return M

    def network_layer(self, Fn: Any, sw: Any, prepared: Any) -> tuple[Callable, Any]:
        import torch

        # paper Eq. 3 in the (weighted) empirical inner product <a, b> = sum w a b, so that the
        # weighted loss splits into a theta part and a network part
        Q, _ = torch.linalg.qr(Fn * sw[:, None])
        safe = torch.where(sw > 0, sw, torch.ones_like(sw))
        return (lambda h: h - (Q @ (Q.T @ (sw * h))) / safe), None


@dataclass(frozen=True)
class Even(SubspaceDisturbance):
    """g is symmetric: unchanged by reflecting x about ``center`` along ``axes``.

    Parameters
    ----------
    center : float or sequence of float
        Reflection centre (per axis for 2-D x).
    axes : sequence of int, optional
        Axes to reflect for 2-D x (default: all). Symmetric about both axes means g is invariant
        under every combination of the reflections.

    Examples
    --------
    >>> import numpy as np
    >>> P = Even().projector(np.linspace(-1, 1, 5))
    >>> P.rank, P.project(np.array([1.0, 2.0, 3.0, 4.0, 5.0])).tolist()
    (3, [3.0, 3.0, 3.0, 3.0, 3.0])
    """

    center: float | tuple = 0.0
    axes: tuple | None = None

    def describe(self) -> str:
        return f"even (mirror-symmetric) about {self.center}"

    def projector(self, x: np.ndarray) -> BaseProjector:
        X = x[:, None] if x.ndim == 1 else x
        d = X.shape[1]
        center = np.broadcast_to(np.asarray(self.center, dtype=float), (d,))
        axes = tuple(range(d)) if self.axes is None else tuple(self.axes)
        for a in axes:
            if not 0 <= a < d:
                raise InputError(f"Even(axes={self.axes}) names axis {a}, but x has {d} dimension(s)")
        scale = np.ptp(X, axis=0)
        tol = np.where(scale > 0, scale, 1.0) * 1e-7
        keys = {tuple(k): i for i, k in enumerate(np.round(X / tol).astype(np.int64))}
        if len(keys) != X.shape[0]:
            seen: dict = {}
            for i, k in enumerate(np.round(X / tol).astype(np.int64)):
                j = seen.setdefault(tuple(k), i)
                if j != i:
                    break
            where = f"{X[i, 0]:.6g}" if d == 1 else str(tuple(float(v) for v in X[i]))
            raise InputError(
                f"Even needs distinct sample points; x repeats a point at rows {j} and {i} (x = {where}), and "
                f"{X.shape[0] - len(keys)} row(s) in all repeat one; average the readings at each point, or keep one"
            )
        perms = []
        for r in range(len(axes) + 1):
            for subset in itertools.combinations(axes, r):
                Xr = X.copy()
                for a in subset:
                    Xr[:, a] = 2 * center[a] - Xr[:, a]
                kr = np.round(Xr / tol).astype(np.int64)
                perm = np.fromiter((keys.get(tuple(k), -1) for k in kr), dtype=np.int64, count=X.shape[0])
                missing = np.flatnonzero(perm < 0)
                if missing.size:
                    i = int(missing[0])
                    raise InputError(
                        f"Even(center={self.center}) needs samples symmetric about the centre: {missing.size} of "
                        f"{X.shape[0]} samples have no mirror image (first at x={X[i].tolist() if d > 1 else X[i, 0]}); "
                        "sample on a grid symmetric about the centre or change center"
                    )
                perms.append(perm)
        return OrbitProjector(perms)


@dataclass(frozen=True)
class Periodic(SubspaceDisturbance):
    """g repeats with a known period.

    With uniform sampling and a period that is a whole number of sample steps, g may be any
    periodic sequence (exact phase averaging). Otherwise g is a Fourier series with
    ``harmonics`` terms (default: as many as the sampling resolves).

    Examples
    --------
    >>> import numpy as np
    >>> Periodic(4).projector(np.arange(12.0)).rank          # any sequence of period 4 samples
    4
    """

    period: float
    harmonics: int | None = None

    def describe(self) -> str:
        return f"periodic with period {self.period:g}"

    def projector(self, x: np.ndarray) -> BaseProjector:
        if not np.isfinite(self.period) or self.period <= 0:
            raise InputError(f"Periodic(period={self.period}) must be a positive finite number")
        if x.ndim != 1:
            raise InputError(f"Periodic needs 1-D sample points x; got shape {x.shape}")
        span = float(np.ptp(x))
        d = np.diff(np.sort(x))
        # the step of the sampling: repeated points (several readings at one x) are not a step of 0
        steps = d[d > 0]
        dt = float(np.median(steps)) if steps.size else 0.0
        # each sample stands for one step of the record: 48 hourly samples hold two whole days
        # (span 47 h), and the phase average sees every hour twice
        if 2 * self.period > (span + dt) * (1 + 1e-9):
            raise InputError(
                f"Periodic(period={self.period:g}) does not fit the sampling: the data span {span:g} holds fewer "
                "than two periods; use a longer record or a shorter period"
            )
        if self.period < 2 * dt:
            raise InputError(
                f"Periodic(period={self.period:g}) does not fit the sampling: it is shorter than two sample steps "
                f"(step {dt:g}); the sampling cannot resolve it"
            )
        ratio = self.period / dt
        uniform = np.max(np.abs(d - dt)) <= 1e-6 * dt
        if self.harmonics is None and uniform and abs(ratio - round(ratio)) < 1e-6 * ratio:
            m = int(round(ratio))
            labels = np.round((x - x.min()) / dt).astype(np.int64) % m
            return LabelProjector(labels)
        kmax = int(np.floor((ratio - 1) / 2)) if uniform else int(np.floor(ratio / 4))
        K = self.harmonics if self.harmonics is not None else kmax
        K = max(0, min(K, (x.size - 2) // 4))
        w = 2 * np.pi * (x - x.min()) / self.period
        cols = [np.ones_like(x)] + [f(k * w) for k in range(1, K + 1) for f in (np.cos, np.sin)]
        return Projector(np.stack(cols, axis=1))


@dataclass(frozen=True)
class Band(SubspaceDisturbance):
    """g's spectrum lies inside the frequency band [lo, hi] (cycles per unit of x; uniform sampling).

    Uses Parseval: functions in disjoint DFT bands are exactly orthogonal on the sample grid.

    Examples
    --------
    >>> import numpy as np
    >>> Band(0, 2).projector(np.arange(16) / 16).rank        # DFT bins 0, 1 and 2 (cos and sin)
    5
    """

    lo: float
    hi: float

    def describe(self) -> str:
        return f"band-limited to [{self.lo:g}, {self.hi:g}]"

    def projector(self, x: np.ndarray) -> BaseProjector:
        dt = _uniform_step(x, "Band")
        n = x.size
        nyq = 0.5 / dt
        if not (0 <= self.lo < self.hi):
            raise InputError(f"Band(lo={self.lo}, hi={self.hi}) needs 0 <= lo < hi")
        if self.lo > nyq:
            raise InputError(
                f"Band(lo={self.lo:g}, hi={self.hi:g}) does not fit the sampling: lo is above the Nyquist frequency "
                f"{nyq:g}; lower the band or sample faster"
            )
        freqs = np.fft.rfftfreq(n, dt)
        mask = (freqs >= self.lo - 1e-12) & (freqs <= self.hi + 1e-12)
        if not mask.any():
            raise InputError(
                f"Band(lo={self.lo:g}, hi={self.hi:g}) does not fit the sampling: it holds no DFT frequency "
                f"(resolution {1 / (n * dt):g}); widen the band or use a longer record"
            )
        return FFTProjector(n, mask)


class Subspace(SubspaceDisturbance):
    """g lies in the span of given nuisance columns (known shapes, unknown amounts).

    Parameters
    ----------
    G : (n, k) array, or a Basis evaluated at x

    Examples
    --------
    >>> import numpy as np
    >>> Subspace(np.c_[np.ones(4), np.arange(4.0)]).projector(np.arange(4.0)).rank
    2
    """


    def __init__(self, G: ArrayLike | Basis):
        self.G = G

    def describe(self) -> str:
        return "inside a given nuisance subspace"

    def projector(self, x: np.ndarray) -> BaseProjector:
        from odnn_sep.core.basis import Basis

        G = self.G.evaluate(x) if isinstance(self.G, Basis) else np.asarray(self.G, dtype=float)
        if G.ndim == 1:
            G = G[:, None]
        if G.shape[0] != x.shape[0]:
            raise InputError(f"Subspace matrix has {G.shape[0]} rows but x has {x.shape[0]} samples; they must match")
        return Projector(G)

    def __repr__(self) -> str:
        return "Subspace(G)"


#: The shipped classes (a user class subclasses :class:`~odnn_sep.core.base.Disturbance` instead).
DISTURBANCES = (Orthogonal, Even, Periodic, Band, Subspace, Convex, Monotone)
