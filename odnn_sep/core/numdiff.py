"""Forward-difference Jacobians whose steps do not shrink with the parameter.

SciPy's ``least_squares(diff_step=h)`` steps each parameter by ``h * |x|``. For a parameter near
zero (an initial velocity, a damping, a friction coefficient) that step falls to ``1e-10`` and
below, under the error of a numerically integrated model (relative 1e-9 to 1e-7): the Jacobian column is
then integration noise, its standard error comes out 100x too small and the optimiser cannot move
the parameter. Here the step is ``h * max(|x|, floor)``, the rule SciPy applies when no relative
step is given, so a parameter near zero is stepped on its own scale (``floor``, 1 by default:
parameters in the units of the presets, where 1e-5 is a small change). A parameter that is small
but not near zero in its own units (time in ms makes a stiffness of 4 into 4e-6) would be moved far
out of its linear range by that step: where the step moves the output by more than a given share
of its size, the parameter is stepped relative to itself instead (``max_response``).
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
                     floor: float = 1.0, scale: float | None = None,
                     max_response: float | None = None) -> tuple[Callable, Callable]:
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
    scale : float, optional
        Size of the function's output (the data's spread), for ``max_response``.
    max_response : float, optional
        A parameter below ``floor`` whose step changes the output by more than ``max_response *
        scale`` is stepped by ``rel_step * |x|`` instead: the absolute step is then far outside its
        linear range (a parameter that is tiny in its units, such as a stiffness of 4e-6 when time
        is in milliseconds). Other steps are left as they are.

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

    A decay rate of 1e-6 per unit of time over 2e6 units: the step of 1e-5 would move the curve by
    most of its range, a step of 1e-11 gives the derivative ``-t exp(-k t)``:

    >>> t = np.array([1e6, 2e6])
    >>> decay = lambda v: np.exp(-v[0] * t)
    >>> _, jac = forward_jacobian(decay, 1e-5, [0.0], [np.inf], scale=1.0, max_response=0.01)
    >>> (jac(np.array([1e-6]))[:, 0] / (-t * np.exp(-1e-6 * t))).round(4).tolist()
    [1.0, 1.0]
    >>> _, jac = forward_jacobian(decay, 1e-5, [0.0], [np.inf])     # the fixed step: far off
    >>> (jac(np.array([1e-6]))[:, 0] / (-t * np.exp(-1e-6 * t))).round(2).tolist()
    [0.1, 0.05]
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
            d = np.asarray(fun(xj), float) - f0
            resp = float(np.max(np.abs(d)) / scale) if scale else 0.0
            if max_response is not None and not resp <= max_response and 0 < abs(x[j]) < floor:
                # the absolute step is large for this parameter's own size (time in ms makes a
                # stiffness 1e-6): the model moved by more than max_response of the data's spread,
                # far outside its linear range; step relative to the parameter instead
                hj = step_sizes(x[j:j + 1], rel_step, lo[j:j + 1] if np.ndim(lo) else lo,
                                hi[j:j + 1] if np.ndim(hi) else hi, floor=0.0)[0]
                xj[j] = x[j] + hj
                d2 = np.asarray(fun(xj), float) - f0
                if np.all(np.isfinite(d2)):
                    h[j], d = hj, d2
            J[:, j] = d / h[j]
        return J

    return cached, jac
