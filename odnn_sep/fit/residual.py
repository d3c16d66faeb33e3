"""Whether a separation's residual still looks like white noise (``separate`` warns when it does not).

Every interval ``separate`` prints assumes that the disturbance lies in the chosen class and that the
noise is white. When either fails, what the class cannot hold is left in the residual as a smooth
curve, and the intervals are confidently wrong (a monotone class on a U-shaped disturbance put
theta = 2 outside [2.10, 2.20]). Neighbouring residuals then agree: their lag-1 correlation is near 1,
against about 0 for a fit whose class is right (at most 0.02 over the paper's datasets).
"""
from __future__ import annotations

import numpy as np

__all__ = ["residual_correlation", "residual_warning"]

#: Lag-1 correlation above which the residual is not called noise.
MAX_CORRELATION = 0.5
#: ... when it is also this many standard errors (1/sqrt(n)) above 0.
MIN_SIGNIFICANCE = 4.0


def residual_correlation(x: np.ndarray, residual: np.ndarray, grid: tuple | None = None) -> float:
    """Lag-1 correlation of ``residual`` between neighbouring samples (along x; along both axes of a field).

    Parameters
    ----------
    x : ndarray
        (n,) coordinates (any order), or the (n, 2) points of a field.
    residual : (n,) ndarray
    grid : tuple of int, optional
        ``(ny, nx)`` of a field whose points are in row order.

    Returns
    -------
    float
        The larger of the axes' correlations for a field; NaN when the residual is constant.

    Examples
    --------
    >>> x = np.linspace(0, 1, 200)
    >>> round(residual_correlation(x, np.sin(3 * x)), 2)                  # a smooth curve left over
    0.98
    >>> abs(residual_correlation(x, np.random.default_rng(0).normal(size=200))) < 0.2
    True
    """
    r = np.asarray(residual, dtype=float)
    if grid is not None:
        R = r.reshape(grid) - r.mean()
        den = float((R * R).sum())
        if den == 0:
            return float("nan")
        return max(float((R[:, 1:] * R[:, :-1]).sum()), float((R[1:] * R[:-1]).sum())) / den
    r = r[np.argsort(np.asarray(x), kind="stable")] - r.mean()
    den = float(r @ r)
    return float(r[1:] @ r[:-1]) / den if den > 0 else float("nan")


def residual_warning(x: np.ndarray, y: np.ndarray, residual: np.ndarray, class_desc: str,
                     grid: tuple | None = None) -> str | None:
    """A warning when the residual is far from white noise, else None.

    Parameters
    ----------
    x, y, residual : ndarray
        Coordinates, data and the fit's residual.
    class_desc : str
        The disturbance class, as its ``describe()`` says it.
    grid : tuple of int, optional
        ``(ny, nx)`` of a field.

    Returns
    -------
    str or None

    Examples
    --------
    >>> x = np.linspace(-1, 1, 400)
    >>> print(residual_warning(x, x**2, 0.1 * x**2 - 0.03, "monotone non-decreasing"))  # doctest: +ELLIPSIS
    the residual is not like noise (lag-1 correlation 0.99 between neighbouring samples): the disturbance may ...
    >>> residual_warning(x, x**2, 0.01 * np.random.default_rng(0).normal(size=400), "even") is None
    True
    """
    r = np.asarray(residual, dtype=float)
    scale = float(np.sqrt(np.mean(np.asarray(y, dtype=float) ** 2)))
    if not float(np.sqrt(np.mean(r * r))) > 1e-9 * scale:
        return None          # noise-free data: what is left is rounding, structured or not
    rho = residual_correlation(x, r, grid)
    if not (rho > MAX_CORRELATION and rho * np.sqrt(r.size) > MIN_SIGNIFICANCE):
        return None
    return (f"the residual is not like noise (lag-1 correlation {rho:.2f} between neighbouring samples): the "
            f"disturbance may not lie in the {class_desc} class, or the noise is correlated; the intervals "
            "assume both, so read them as too narrow, or try another class")
