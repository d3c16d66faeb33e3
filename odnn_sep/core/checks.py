"""Input validation for the separation engine: one clear error per problem."""
from __future__ import annotations

import warnings
from typing import Sequence

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import IdentifiabilityWarning, InputError, NotIdentifiableError, as_float_array


def check_xy(x: ArrayLike, y: ArrayLike, weights: ArrayLike | None = None
             ) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """Float copies of x (n,) or (n, d), y (n,) and weights (n,) >= 0, with one clear error per problem.

    Parameters
    ----------
    x : array_like
        Coordinates, (n,) or (n, d).
    y : array_like
        Data, (n,).
    weights : array_like, optional
        Non-negative sample weights, (n,).

    Returns
    -------
    x, y, weights : ndarray or None
        Float copies (``weights`` stays None when not given).

    Raises
    ------
    odnn_sep.errors.InputError
        For non-numeric or non-finite values, wrong shapes, mismatched lengths or negative weights.

    Examples
    --------
    >>> x, y, w = check_xy([0, 1, 2], [1.0, 2.0, 3.0])
    >>> x.dtype, w is None
    (dtype('float64'), True)
    """
    y = as_float_array("y", y, ndim=(1,))
    x = as_float_array("x", x, ndim=(1, 2))
    if x.shape[0] != y.shape[0]:
        raise InputError(f"x has {x.shape[0]} samples but y has {y.shape[0]}; they must have the same length")
    if weights is not None:
        weights = as_float_array("weights", weights, ndim=(1,))
        if weights.shape[0] != y.shape[0]:
            raise InputError(f"weights has {weights.shape[0]} entries but y has {y.shape[0]}; they must match")
        if (weights < 0).any():
            raise InputError(f"weights must be non-negative; {int((weights < 0).sum())} are negative")
    return x, y, weights


def check_basis_matrix(F: np.ndarray, names: Sequence[str], n_extra: int = 0) -> None:
    """Reject all-zero or duplicated columns and too few samples for the parameter count.

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns evaluated at the samples.
    names : sequence of str
        Column names, for the messages.
    n_extra : int, optional
        Further parameters fitted with theta (they also need samples).

    Raises
    ------
    odnn_sep.errors.InputError
        For no columns, a non-finite, all-zero or duplicated column, or too few samples.

    Examples
    --------
    >>> import numpy as np
    >>> check_basis_matrix(np.c_[np.arange(5.0), 2 * np.arange(5.0)], ["a", "b"])
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: basis columns 'a' and 'b' are duplicates (collinear at the given x); remove one
    """
    n, p = F.shape
    if p == 0:
        raise InputError("the basis has no columns; add at least one physics function")
    check = np.isfinite(F)
    if not check.all():
        j = int(np.flatnonzero(~check.all(axis=0))[0])
        raise InputError(
            f"basis column {names[j]!r} is not finite at {int((~check[:, j]).sum())} sample(s) "
            f"(first at index {int(np.flatnonzero(~check[:, j])[0])}); check the basis function's domain"
        )
    need = p + n_extra + 1
    if n < need:
        raise InputError(
            f"too few samples: n={n} for {p + n_extra} parameter(s); need at least {need} samples"
        )
    norms = np.linalg.norm(F, axis=0)
    for j in range(p):
        if norms[j] == 0:
            raise InputError(f"basis column {names[j]!r} is all zeros at the given x; remove it or check its function")
    U = F / norms
    G = U.T @ U
    iu = np.triu_indices(p, 1)
    dup = np.flatnonzero(np.abs(G[iu]) > 1 - 1e-10)
    if dup.size:
        a, b = iu[0][dup[0]], iu[1][dup[0]]
        raise InputError(
            f"basis columns {names[a]!r} and {names[b]!r} are duplicates (collinear at the given x); remove one"
        )


def outside_class_report(F: np.ndarray, Fp: np.ndarray) -> tuple[np.ndarray, float]:
    """Per-column share of the norm of ``F`` left in ``Fp`` (its part outside the class), and the
    condition number of the normalised ``Fp`` (inf when a column vanishes).

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns.
    Fp : (n, p) ndarray
        Their parts outside the disturbance class.

    Returns
    -------
    frac : (p,) ndarray
        ``|Fp_j| / |F_j|`` per column.
    cond : float
        Condition number of the column-normalised ``Fp``.

    Examples
    --------
    >>> import numpy as np
    >>> F = np.c_[np.ones(4), np.arange(4.0)]
    >>> frac, cond = outside_class_report(F, F - F.mean(axis=0))   # the class: constants
    >>> frac.round(3).tolist(), cond
    ([0.0, 0.598], inf)
    """
    frac = np.linalg.norm(Fp, axis=0) / np.linalg.norm(F, axis=0)
    if not (frac > 0).all():
        return frac, np.inf
    U = Fp / np.linalg.norm(Fp, axis=0)
    s = np.linalg.svd(U, compute_uv=False)
    return frac, float(s[0] / s[-1]) if s[-1] > 0 else np.inf


def dependent_columns(Fp: np.ndarray, names: Sequence[str]) -> list[str]:
    """Names of the columns that take part in the (near) linear dependence of ``Fp``.

    They are the columns with a visible weight in the right singular vector of the smallest
    singular value of the column-normalised ``Fp``: the combination that (nearly) vanishes.

    Parameters
    ----------
    Fp : (n, p) ndarray
        Columns, none all zero.
    names : sequence of str
        Their names.

    Returns
    -------
    list of str
        In column order.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0, 1, 9)
    >>> dependent_columns(np.c_[np.sin(x), x, np.cos(x), x + np.sin(x)], ["s", "x", "c", "x+s"])
    ['s', 'x', 'x+s']
    """
    U = Fp / np.linalg.norm(Fp, axis=0)
    v = np.linalg.svd(U)[2][-1]
    return [names[j] for j in np.flatnonzero(np.abs(v) > 1e-3 * np.abs(v).max())]


def require_outside_class(F: np.ndarray, Fp: np.ndarray, names: Sequence[str], cls_desc: str
                          ) -> tuple[np.ndarray, float]:
    """:func:`outside_class_report`, raising NotIdentifiableError where :func:`check_outside_class` does
    (same parameters; without its warning of weak identification, which cone classes do not need).

    Returns
    -------
    frac : (p,) ndarray
    cond : float

    Raises
    ------
    odnn_sep.errors.NotIdentifiableError
        When a column is (nearly) inside the class or the projected columns are collinear; the
        message names the columns of the dependence.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.arange(6.0)
    >>> F = np.c_[x, x**2, x + x**2]
    >>> require_outside_class(F, F - F.mean(axis=0), ["a", "b", "c"], "constant")  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    odnn_sep.errors.NotIdentifiableError: the basis columns become collinear ... the columns 'a', 'b' and 'c' ...
    """
    frac, cond = outside_class_report(F, Fp)
    for j, f in enumerate(frac):
        if f < 1e-8:
            raise NotIdentifiableError(
                f"basis column {names[j]!r} lies inside the disturbance class ({cls_desc}): only {f:.1e} of its "
                "norm is outside it, so its coefficient is not identifiable; remove the column or choose a "
                "disturbance class that excludes it"
            )
    if cond > 1e10:
        cols = [repr(n) for n in dependent_columns(Fp, names)]
        which = ", ".join(cols[:-1]) + f" and {cols[-1]}" if len(cols) > 1 else "".join(cols)
        raise NotIdentifiableError(
            f"the basis columns become collinear once the disturbance class ({cls_desc}) is projected out "
            f"(condition number {cond:.1e}): the columns {which} are linearly dependent; theta is not "
            "identifiable — drop one of them or change the class"
        )
    return frac, cond


def check_outside_class(F: np.ndarray, Fp: np.ndarray, names: Sequence[str], cls_desc: str) -> dict:
    """How much of each basis column lies outside the disturbance class; fail if (nearly) none.

    Returns diagnostics: per-column outside fraction and the condition number of the projected basis.
    Raises NotIdentifiableError when a column lies (nearly) inside the class or the projected
    columns are collinear; warns (IdentifiabilityWarning) when identification is weak.

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns.
    Fp : (n, p) ndarray
        Their parts outside the disturbance class.
    names : sequence of str
        Column names.
    cls_desc : str
        The class's description, for the messages.

    Returns
    -------
    dict
        ``outside_fraction`` (name -> share) and ``projected_condition``.

    Raises
    ------
    odnn_sep.errors.NotIdentifiableError
        When a column is (nearly) inside the class or the projected columns are collinear.

    Examples
    --------
    >>> import numpy as np
    >>> F = np.c_[np.arange(4.0)]
    >>> check_outside_class(F, F - F.mean(), ["slope"], "constant")["outside_fraction"]["slope"] > 0.5
    True
    """
    frac, cond = require_outside_class(F, Fp, names, cls_desc)
    weak = [names[j] for j, f in enumerate(frac) if f < 1e-2]
    if weak or cond > 1e6:
        warnings.warn(
            f"theta is weakly identified: columns {weak} have < 1 % of their norm outside the disturbance "
            f"class, projected-basis condition number {cond:.1e}; expect large standard errors",
            IdentifiabilityWarning, stacklevel=3,
        )
    return {"outside_fraction": dict(zip(names, frac.tolist())), "projected_condition": cond}
