"""Forward-difference Jacobians whose steps do not shrink with the parameter.

SciPy's ``least_squares(diff_step=h)`` steps each parameter by ``h * |x|``. For a parameter near
zero (an initial velocity, a damping, a friction coefficient) that step falls to ``1e-10`` and
below, under the error of a numerically integrated model (relative 1e-9 to 1e-7): the Jacobian column is
then integration noise, its standard error comes out 100x too small and the optimiser cannot move
the parameter. Here the step is ``h * max(|x|, floor)``, the rule SciPy applies when no relative
step is given, so a parameter near zero is stepped on its own scale (``floor``, 1 by default:
parameters in the units of the presets, where 1e-5 is a small change).
"""
from __future__ import annotations

from typing import Callable

import numpy as np


def step_sizes(x, rel_step, lo, hi, floor=1.0) -> np.ndarray:
    """Signed forward-difference steps ``rel_step * max(|x|, floor)``, backwards where the step would leave the bounds.

    Parameters
    ----------
    x : array_like
        Point.
    rel_step : float
        Relative step.
    lo, hi : array_like
        Bounds (``-inf`` / ``inf`` for none).
    floor : float, optional
        Smallest scale a step is taken relative to.

    Returns
    -------
    ndarray

    Examples
    --------
    >>> step_sizes([0.0, 1e-6, 200.0, 1.0], 1e-5, [-1, -1, -1, -1], [1, 1, 1e3, 1.0]).tolist()
    [1e-05, 1e-05, 0.002, -1e-05]
    """
    x = np.asarray(x, float)
    h = rel_step * np.maximum(np.abs(x), floor)
    return np.where(x + h > np.asarray(hi, float), -h, h)


def forward_jacobian(fun: Callable[[np.ndarray], np.ndarray], rel_step: float, lo, hi, *,
                     floor: float = 1.0) -> tuple[Callable, Callable]:
    """``(fun_cached, jac)`` for :func:`scipy.optimize.least_squares` with :func:`step_sizes` steps.

    ``least_squares`` evaluates ``fun(x)`` and then asks for ``jac(x)`` at the same point; the
    cached function keeps that value, so a Jacobian costs one evaluation per parameter.

    Parameters
    ----------
    fun : callable
        ``x -> residual vector``.
    rel_step : float
        Relative step.
    lo, hi : array_like
        Bounds.
    floor : float, optional
        See :func:`step_sizes`.

    Returns
    -------
    (callable, callable)

    Examples
    --------
    >>> import numpy as np
    >>> f, jac = forward_jacobian(lambda v: np.array([v[0] ** 2, np.sin(v[1])]), 1e-6, [-5, -5], [5, 5])
    >>> _ = f(np.array([2.0, 1e-9]))
    >>> np.round(jac(np.array([2.0, 1e-9])), 4).tolist()
    [[4.0, 0.0], [0.0, 1.0]]
    """
    last: dict = {}

    def cached(x):
        out = np.asarray(fun(x), float)
        last["x"], last["f"] = np.array(x, float), out
        return out

    def jac(x):
        x = np.asarray(x, float)
        f0 = last["f"] if "x" in last and np.array_equal(last["x"], x) else np.asarray(fun(x), float)
        h = step_sizes(x, rel_step, lo, hi, floor)
        J = np.empty((len(f0), len(x)))
        for j in range(len(x)):
            xj = x.copy()
            xj[j] += h[j]
            J[:, j] = (np.asarray(fun(xj), float) - f0) / h[j]
        return J

    return cached, jac
