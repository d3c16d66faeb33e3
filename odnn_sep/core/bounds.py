"""The best precision any unbiased estimator can reach for a separation problem (Cramér–Rao bound).

With white Gaussian noise of standard deviation sigma and a disturbance that may be *anything* in a
linear class G (Orthogonal, Even, Periodic, Band, Subspace), the disturbance is a nuisance with as many
free parameters as G has dimensions. Its efficient score removes the part of every physics direction
that lies in G, so the information matrix for (theta, phi) is

    I = J^T (I - P_G) J / sigma^2,     J = [F(phi), d(F(phi) theta)/d phi],

and no unbiased estimator of theta can have a covariance below I^-1. The exact solver's projection
estimator attains it (to first order in phi), which is why a miss of an accuracy target at a given
noise level can be a property of the problem rather than of the solver. The cone classes (Convex,
Monotone) only set-identify theta, so no such bound exists for them.
"""
from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.core.base import Disturbance
from odnn_sep.core.basis import Basis
from odnn_sep.errors import InputError, check_type


def _jacobian(basis, x, theta: np.ndarray, phi: dict) -> np.ndarray:
    """Columns d(model)/d(theta, phi); phi derivatives by central differences (relative step 1e-6)."""
    F = basis.evaluate(x, phi)
    cols = [F]
    for name in basis.phi_names:
        h = 1e-6 * max(abs(phi[name]), 1e-3)
        up = basis.evaluate(x, {**phi, name: phi[name] + h}) @ theta
        down = basis.evaluate(x, {**phi, name: phi[name] - h}) @ theta
        cols.append(((up - down) / (2 * h))[:, None])
    return np.hstack(cols)


def efficiency_bound(basis: Basis, disturbance: Disturbance, x: ArrayLike, theta: ArrayLike, phi: dict | None = None, *,
                     sigma: float) -> np.ndarray:
    """Cramér–Rao covariance of (theta, phi) for ``y = F(phi) theta + g + N(0, sigma^2)``, g in the class.

    Parameters
    ----------
    basis : Basis or ParametricBasis
    disturbance : Disturbance
        A point-identifying class: Orthogonal, Even, Periodic, Band, Subspace or a SubspaceDisturbance.
    x : array_like
        Sample points, as passed to ``Separator.fit``.
    theta : array_like, shape (p,)
        Linear coefficients at which to evaluate the bound (the truth, in a simulation study).
    phi : dict, optional
        Nonlinear parameters (required for a parametric basis).
    sigma : float
        Standard deviation of the white measurement noise.

    Returns
    -------
    ndarray, shape (p + q, p + q)
        Lower bound on the covariance of any unbiased estimator, theta first, then phi in
        ``basis.phi_names`` order.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Periodic
    >>> t = np.arange(200.0)
    >>> b = Basis([lambda t: t / 200], names=["trend"])
    >>> cov = efficiency_bound(b, Periodic(20), t, [1.0], sigma=0.1)
    >>> bool(np.sqrt(cov[0, 0]) > 0.1 / np.sqrt(200))   # worse than with no disturbance at all
    True
    """
    check_type("disturbance", disturbance, Disturbance, "a Disturbance instance")
    if disturbance.identification == "set":
        raise InputError(f"efficiency_bound needs a linear disturbance class; {type(disturbance).__name__} only "
                         "set-identifies theta (use the identified interval of Separator.fit instead)")
    if not (np.isfinite(sigma) and sigma > 0):
        raise InputError(f"sigma must be a positive finite noise standard deviation; got {sigma!r}")
    x = np.asarray(x, dtype=float)
    theta = np.asarray(theta, dtype=float).ravel()
    J = _jacobian(basis, x, theta, dict(phi or {}))
    A = disturbance.project_out(J, x)     # the part of every direction the class cannot imitate
    info = A.T @ A / sigma ** 2
    return np.linalg.pinv(info, hermitian=True)


def expected_mape(cov: np.ndarray, values: ArrayLike) -> float:
    """Mean absolute percentage error (%) of a Gaussian estimator with covariance ``cov`` around ``values``.

    E|N(0, s^2)| = s sqrt(2/pi); averaged over the parameters as MAPE is.

    Parameters
    ----------
    cov : (p, p) ndarray
        Covariance of the estimator (at least as many rows as ``values``).
    values : array_like
        True parameter values (non-zero).

    Returns
    -------
    float
        Expected MAPE in percent.

    Examples
    --------
    >>> import numpy as np
    >>> round(expected_mape(np.diag([0.01]), [1.0]), 3)      # sd 0.1 around 1: 8 % on average
    7.979
    """
    values = np.asarray(values, dtype=float).ravel()
    sd = np.sqrt(np.clip(np.diag(cov)[: values.size], 0, None))
    return float(np.mean(sd * np.sqrt(2 / np.pi) / np.abs(values)) * 100)
