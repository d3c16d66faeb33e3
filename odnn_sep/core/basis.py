"""Physics bases: named columns evaluated at sample points, composable with ``+``.

A ``Basis`` has only linear coefficients theta. A ``ParametricBasis`` also has nonlinear parameters
phi (frequency, decay, position); its function receives ``xp`` (numpy or torch) so the same code
is differentiable by torch.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from types import ModuleType
from typing import Callable, Iterable, Sequence

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import InputError


@dataclass(frozen=True)
class Term:
    """One block of columns of a basis: a function (or pre-evaluated matrix) with its column names and,
    for parametric terms, the nonlinear parameters' start values, bounds and search grid.

    Examples
    --------
    >>> import numpy as np
    >>> Basis([np.sin], names=["s"]).terms[0].names
    ('s',)
    """

    fn: Callable | None          # x -> (n,) / (n,p), or fn(x, xp=..., **phi) for parametric terms
    names: tuple[str, ...]
    matrix: np.ndarray | None = None   # pre-evaluated columns
    phi0: dict = field(default_factory=dict)
    bounds: dict = field(default_factory=dict)
    grid: dict | None = None


def unique_terms(terms: Iterable[Term]) -> tuple[Term, ...]:
    """``terms`` as a tuple, or InputError if a column name or a nonlinear parameter name repeats.

    Parameters
    ----------
    terms : iterable of Term

    Returns
    -------
    tuple of Term

    Raises
    ------
    odnn_sep.errors.InputError
        For a repeated column or parameter name.

    Examples
    --------
    >>> unique_terms([Term(fn=None, names=("a",)), Term(fn=None, names=("a",))])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: basis column name 'a' appears twice; names must be unique
    """
    terms = tuple(terms)
    for what, names in (("basis column name", [n for t in terms for n in t.names]),
                        ("nonlinear parameter name", [k for t in terms for k in t.phi0])):
        seen = set()
        for n in names:
            if n in seen:
                raise InputError(f"{what} {n!r} appears twice; names must be unique")
            seen.add(n)
    return terms


class Basis:
    """Linear physics basis.

    Parameters
    ----------
    funcs : sequence of callables
        Each maps sample points ``x`` ((n,) or (n, d)) to an (n,) array.
    names : sequence of str, optional
        Column names (default ``f0, f1, ...``).

    Examples
    --------
    >>> import numpy as np
    >>> b = Basis([np.sin, np.cos], names=["sin", "cos"]) + Basis([lambda x: x], names=["x"])
    >>> b.names
    ('sin', 'cos', 'x')
    >>> b.evaluate(np.linspace(0, 1, 4)).shape
    (4, 3)
    """

    def __init__(self, funcs: Sequence[Callable] = (), names: Sequence[str] | None = None):
        funcs = list(funcs)
        if names is None:
            names = [getattr(f, "__name__", f"f{i}") for i, f in enumerate(funcs)]
            names = [n if n != "<lambda>" else f"f{i}" for i, n in enumerate(names)]
        names = list(names)
        if len(names) != len(funcs):
            raise InputError(f"names has {len(names)} entries but funcs has {len(funcs)}; give one name per function")
        self.terms: tuple[Term, ...] = unique_terms(Term(fn=f, names=(n,)) for f, n in zip(funcs, names))

    # -- construction -------------------------------------------------------------------------
    @classmethod
    def from_matrix(cls, F: ArrayLike, names: Sequence[str] | None = None) -> "Basis":
        """Columns already evaluated at the samples (``x`` is then only used for its length)."""
        F = np.array(F, dtype=float)
        if F.ndim == 1:
            F = F[:, None]
        if F.ndim != 2:
            raise InputError(f"basis matrix must be 2-D (n, p); got shape {F.shape}")
        names = list(names) if names is not None else [f"f{i}" for i in range(F.shape[1])]
        if len(names) != F.shape[1]:
            raise InputError(f"names has {len(names)} entries but the matrix has {F.shape[1]} columns")
        b = cls()
        b.terms = unique_terms([Term(fn=None, names=tuple(names), matrix=F)])
        return b

    def __add__(self, other: "Basis") -> "Basis":
        if not isinstance(other, Basis):
            return NotImplemented
        out = ParametricBasis.__new__(ParametricBasis) if (self.is_parametric or other.is_parametric) else Basis()
        out.terms = unique_terms(self.terms + other.terms)
        return out

    # -- properties ---------------------------------------------------------------------------
    @property
    def names(self) -> tuple[str, ...]:
        """Column names, in column order."""
        return tuple(n for t in self.terms for n in t.names)

    @property
    def n_columns(self) -> int:
        """Number of columns p (linear coefficients)."""
        return len(self.names)

    @property
    def phi_names(self) -> tuple[str, ...]:
        """Names of the nonlinear parameters (empty for a linear basis)."""
        return tuple(k for t in self.terms for k in t.phi0)

    @property
    def is_parametric(self) -> bool:
        """Whether the basis has nonlinear parameters phi."""
        return bool(self.phi_names)

    @property
    def phi0(self) -> dict:
        """Starting values of phi."""
        return {k: v for t in self.terms for k, v in t.phi0.items()}

    @property
    def bounds(self) -> dict:
        """``name -> (lo, hi)`` for every phi (infinite where none were given)."""
        return {k: t.bounds.get(k, (-np.inf, np.inf)) for t in self.terms for k in t.phi0}

    @property
    def grid(self) -> dict:
        """``name -> candidate values`` for the multi-start search (phi with a grid only)."""
        return {k: v for t in self.terms if t.grid for k, v in t.grid.items()}

    # -- evaluation ---------------------------------------------------------------------------
    def evaluate(self, x: ArrayLike, phi: dict | None = None, xp: ModuleType = np) -> np.ndarray:
        """Return the (n, p) design matrix at ``x`` (with nonlinear parameters ``phi``)."""
        phi = {**self.phi0, **(phi or {})}
        n = x.shape[0]
        cols = []
        for t in self.terms:
            if t.matrix is not None:
                if t.matrix.shape[0] != n:
                    raise InputError(
                        f"basis matrix has {t.matrix.shape[0]} rows but x has {n} samples; they must match"
                    )
                cols.append(xp.asarray(t.matrix) if xp is np else _to_xp(t.matrix, xp, x))
                continue
            if t.phi0:
                v = t.fn(x, xp=xp, **{k: phi[k] for k in t.phi0})
            else:
                v = t.fn(x)
            v = v if xp is not np else np.asarray(v, dtype=float)
            if v.ndim == 0 or (xp is np and v.size == 1 and n != 1):
                v = v * xp.ones(n) if xp is not np else np.full(n, float(v))
            if v.ndim == 1:
                v = v[:, None]
            if v.shape[0] != n or v.shape[1] != len(t.names):
                raise InputError(
                    f"basis term {t.names} returned shape {tuple(v.shape)}; expected ({n}, {len(t.names)})"
                )
            cols.append(v)
        if xp is np:
            return np.concatenate(cols, axis=1) if cols else np.zeros((n, 0))
        return xp.cat(cols, dim=1)

    def __repr__(self) -> str:
        phi = f", phi={self.phi0}" if self.is_parametric else ""
        return f"{type(self).__name__}(names={list(self.names)}{phi})"


def _to_xp(a, xp, like):
    return xp.as_tensor(a, dtype=like.dtype)


class ParametricBasis(Basis):
    """Basis with nonlinear parameters phi.

    Parameters
    ----------
    fn : callable ``fn(x, xp=np, **phi) -> (n, p)``
        Use ``xp.sin`` etc. so that torch can differentiate it.
    phi0 : dict
        Starting values of the nonlinear parameters.
    bounds : dict, optional
        ``name -> (lo, hi)``.
    names : sequence of str
        Column names.
    grid : dict, optional
        ``name -> candidate values`` for a multi-start search (frequencies: the loss is multimodal).

    Examples
    --------
    >>> import numpy as np
    >>> pb = ParametricBasis(lambda x, xp=np, f=1.0: xp.stack([xp.sin(2*np.pi*f*x), xp.cos(2*np.pi*f*x)], 1),
    ...                      phi0={"f": 1.0}, bounds={"f": (0.5, 2.0)}, names=["s", "c"])
    >>> pb.evaluate(np.linspace(0, 1, 8), {"f": 1.5}).shape
    (8, 2)
    """

    def __init__(self, fn: Callable, phi0: dict, *, names: Sequence[str], bounds: dict | None = None,
                 grid: dict | None = None):
        if not phi0:
            raise InputError("phi0 is empty; a ParametricBasis needs at least one nonlinear parameter (use Basis)")
        bounds = dict(bounds or {})
        for k, (lo, hi) in bounds.items():
            if k not in phi0:
                raise InputError(f"bounds given for {k!r}, which is not in phi0 {sorted(phi0)}")
            if not lo < hi:
                raise InputError(f"bounds for {k!r} must satisfy lo < hi; got ({lo}, {hi})")
            if not lo <= phi0[k] <= hi:
                raise InputError(f"phi0[{k!r}] = {phi0[k]} lies outside its bounds ({lo}, {hi})")
        self.terms = unique_terms([Term(fn=fn, names=tuple(names), phi0={k: float(v) for k, v in phi0.items()},
                                        bounds=bounds, grid=grid)])
