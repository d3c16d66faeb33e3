"""How many points a shape-constrained disturbance class (convex, monotone) is fitted on.

Such a class is a cone of n generators: its fit solves non-negative least squares over them many
times (the estimate, the bootstrap of its excess, the two ends of each identified interval), so its
cost grows faster than the data. Measured on a 2-core machine (one sine term, ``--disturbance
convex``): 3.8 s for 1 000 points, 19 s for 3 000, 64 s for 10 000 (monotone: 180 s), over 250 s for
30 000; 1 000 000 points ran past 5 minutes with 12.8 GB of memory and did not stop on SIGTERM for
3 more minutes. The general ``points`` limit (4 million) holds for the other classes, which cost
milliseconds per thousand points; these two get their own, far lower.
"""
from __future__ import annotations

from odnn_sep.errors import InputError
from odnn_sep.limits import DEFAULTS, limit

# The limit "shape_points" of odnn_sep.limits: 20 000 points by default, about 2-3 minutes on the
# machine above.
SHAPE_POINTS_VAR, MAX_SHAPE_POINTS = DEFAULTS["shape_points"]


def check_shape_points(dist, n: int, spec: str) -> None:
    """Refuse a convex or monotone class on more points than it can be fitted on in minutes.

    Parameters
    ----------
    dist : odnn_sep.core.base.Disturbance
        The parsed ``--disturbance``.
    n : int
        Number of points.
    spec : str
        The option as given (for the message).

    Raises
    ------
    odnn_sep.errors.InputError
        For a cone class (convex, monotone) on more than ``ODNN_SEP_MAX_SHAPE_POINTS`` points
        (default :data:`MAX_SHAPE_POINTS`), or a malformed value of that variable.

    Examples
    --------
    >>> from odnn_sep.core import Convex, Orthogonal
    >>> check_shape_points(Orthogonal(), 10**6, "orthogonal")
    >>> check_shape_points(Convex(), 10**6, "convex")     # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: --disturbance convex on 1,000,000 points: ...
    """
    from odnn_sep.core.base import ConeDisturbance

    if not isinstance(dist, ConeDisturbance):
        return
    lim = limit("shape_points")
    if n > lim:
        raise InputError(f"--disturbance {spec} on {n:,} points: a shape-constrained fit's time and memory grow "
                         f"faster than the data (about a minute for 10,000 points; 1,000,000 ran past 5 "
                         f"minutes with 12 GB); average or decimate to at most {lim:,.0f} points, or set {SHAPE_POINTS_VAR} "
                         f"(e.g. {SHAPE_POINTS_VAR}={n})")
