"""Nonlinear least squares with the disturbance confined to a subspace, and block cross-validation.

The disturbance ``g`` lives in the span of known nuisance columns ``G`` (slow wander for
oscillatory records). Projecting ``G`` out of the residual gives the exact solution of the
separation ``y = model(t; p) + G beta + noise`` for every ``p`` (variable projection): the model
parameters are fitted to what ``G`` cannot express, so the disturbance can never absorb physics
that lies outside its span, and the physics can never hide disturbance inside ``G``. This is the
core engine's ``Subspace`` disturbance class applied to a nonlinear (ODE) model.
"""
from __future__ import annotations

import logging
import warnings
from dataclasses import dataclass, field

import numpy as np

from odnn_sep.core.bounded_interval import bounded_interval
from odnn_sep.core.linalg import Projector, orthonormal_basis, solve, varpro
from odnn_sep.core.numdiff import forward_jacobian
from odnn_sep.core.uncertainty import sandwich_standard_errors
from odnn_sep.errors import ConvergenceWarning, InputError
from odnn_sep.mismatch.effects import EFFECTS
from odnn_sep.mismatch.prediction_memo import PredictionMemo
from odnn_sep.mismatch.presets import ModelIntegrationError
from odnn_sep.mismatch.resolution import resolution

log = logging.getLogger(__name__)


@dataclass
class Fit:
    """A least-squares fit of a model: parameters, robust standard errors, residual and BIC.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60)
    >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2)
    >>> {k: round(v, 6) for k, v in f.params.items()}, f.free, f.n_eff, f.n_params
    ({'g': 9.8, 'h0': 5.0}, ['g', 'h0'], 60, 2.0)
    >>> sorted(f.intervals()), f.rms < 1e-9
    (['g', 'h0'], True)
    """

    model: object
    params: dict
    free: list
    stderr: dict
    rss: float
    n_eff: int
    prediction: np.ndarray = field(repr=False)
    disturbance: np.ndarray = field(repr=False)
    residual: np.ndarray = field(repr=False)
    converged: bool = True
    interval_dof: float = np.inf   # degrees of freedom of the spread estimate (blocks - 1 for the sandwich)
    # per-sample square of the record's resolution (resolution.py), included in ``rss``: residuals
    # under it are numerics, not noise
    floor2: float = 0.0
    # parameter groups the record cannot separate (identifiability.py): no interval for their members
    unidentified: list = field(default_factory=list)

    @property
    def n_params(self) -> float:
        """Parameter count of the BIC: free parameters plus the cost of discrete choices.

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.mismatch.model import make_model
        >>> t = np.linspace(0, 1, 60)
        >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60))
        >>> f.n_params
        2.0
        """
        k = float(len(self.free))
        # a discrete choice (which harmonic) costs log(choices) instead of log(n)
        for e in self.model.effects:
            for _, n_choices in EFFECTS[e].discrete.items():
                k += np.log(n_choices) / np.log(max(self.n_eff, 3))
        return k

    @property
    def bic(self) -> float:
        """Bayesian information criterion ``n log(RSS / n) + k log(n)`` on the effective sample count.

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.mismatch.model import make_model
        >>> t = np.linspace(0, 1, 60)
        >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60))
        >>> round(f.bic, 1)
        -559.0
        """
        n = max(self.n_eff, 1)
        return float(n * np.log(max(self.rss, 1e-300) / n) + self.n_params * np.log(n))

    @property
    def rms(self) -> float:
        """Root mean square of the residual (after the disturbance).

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.mismatch.model import make_model
        >>> t = np.linspace(0, 1, 60)
        >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60))
        >>> round(f.rms, 4)
        0.0089
        """
        return float(np.sqrt(np.mean(self.residual ** 2)))

    def determined(self, name) -> bool:
        """Whether the spread of parameter ``name`` was determined by the data.

        A standard error that is not finite, or whose 95 % half-width is zero or within float
        resolution of the value, on a record with a non-zero residual, comes from a flat or singular
        Jacobian (a difference step under the integration error, or one that changes nothing), not
        from the data: such a parameter gets no interval (never "± 0").

        Parameters
        ----------
        name : str
            A free parameter.

        Returns
        -------
        bool

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.mismatch.model import make_model
        >>> t = np.linspace(0, 1, 60)
        >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60))
        >>> bool(f.determined("g"))
        True
        >>> f.stderr["g"] = 0.0
        >>> bool(f.determined("g")), "g" in f.intervals(), f.reported_stderr("g")
        (False, False, None)
        """
        s = self.stderr.get(name)
        if s is None or not np.isfinite(s):
            return False
        v = float(self.params[name])
        scale = float(np.max(np.abs(self.prediction))) if np.size(self.prediction) else 0.0
        noise_free = self.rms <= 1e-12 * max(scale, 1e-300)
        return noise_free or t_over_normal(self.interval_dof) * s > 64 * np.spacing(abs(v))

    def reported_stderr(self, name):
        """The standard error of ``name`` for reports: None when not :meth:`determined` (see its example)."""
        return self.stderr.get(name) if self.determined(name) else None

    def intervals(self) -> dict:
        """95 % intervals: Wald intervals on the robust standard errors, kept inside the bounds.

        Where a Wald interval would cross a physical bound (a rate > 0), the interval of the log
        (logit for two bounds) of the parameter is used (:func:`odnn_sep.core.bounded_interval.bounded_interval`);
        an estimate within one standard error of its bound gets the Wald interval cut at the bound.
        A parameter whose spread is not :meth:`determined` has no interval.

        Returns
        -------
        dict
            ``{name: (lo, hi)}`` per free parameter with a determined spread.

        Examples
        --------
        >>> import numpy as np
        >>> from odnn_sep.mismatch.model import make_model
        >>> t = np.linspace(0, 1, 60)
        >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2 + 0.01 * np.random.default_rng(0).normal(size=60))
        >>> {k: (round(lo, 2), round(hi, 2)) for k, (lo, hi) in f.intervals().items()}
        {'g': (9.75, 9.83), 'h0': (4.99, 5.01)}
        """
        names = list(self.stderr)
        # a sandwich over nb blocks has about nb - 1 degrees of freedom: Student-t, not normal, quantiles
        widen = t_over_normal(self.interval_dof)
        out = {}
        for k in names:
            if not self.determined(k):
                continue
            # Wald inside the bounds; a log / logit interval where the Wald one would cross a bound
            lo, hi = self.model.bounds.get(k, (-np.inf, np.inf))
            a, b = bounded_interval(self.params[k], widen * self.stderr[k], lo, hi)
            out[k] = (float(a), float(b))
        return out


# A difference step that moves the model by more than this share of the data's spread is far outside the
# linear range; for a parameter below 1 (stepped by 1e-5 absolute) it means the parameter is tiny in its
# units (time in ms or us) and it is stepped relative to its own size instead. On the golden cases every
# step of a parameter below 1 moves the model by less than 0.01 of that spread (99.9 % by less than 0.004),
# so none changes; with time in s the oscillator's steps move it by 1e-5 to 2e-4.
MAX_RESPONSE = 0.01

# Rank rule of the disturbance columns: a QR direction counts when |R_jj| > 1e-10 max(1, max |R_jj|).
_BASIS_RULE = {"method": "qr", "rtol": 1e-10, "min_scale": 1.0}


def orthonormal(G, rows=None):
    """Orthonormal basis (n, r) of the disturbance columns ``G`` (rows ``rows``), or None without columns.

    Parameters
    ----------
    G : ndarray or None
        Disturbance columns, shape (n, q).
    rows : array_like of int, optional
        Rows to keep.

    Returns
    -------
    ndarray or None

    Examples
    --------
    >>> import numpy as np
    >>> G = np.column_stack([np.ones(4), np.arange(4.0), 2 * np.arange(4.0)])   # rank 2
    >>> orthonormal(G).shape, orthonormal(None)
    ((4, 2), None)
    """
    if G is None or G.shape[1] == 0:
        return None
    return orthonormal_basis(G if rows is None else G[rows], **_BASIS_RULE)


def disturbance_projector(G, rows=None):
    """The core's :class:`~odnn_sep.core.linalg.Projector` onto span(G) (rows ``rows``), or None without columns.

    Parameters
    ----------
    G : ndarray or None
        Disturbance columns, shape (n, q).
    rows : array_like of int, optional
        Rows to keep.

    Returns
    -------
    Projector or None

    Examples
    --------
    >>> import numpy as np
    >>> P = disturbance_projector(np.column_stack([np.ones(4), np.arange(4.0)]))
    >>> P.project_out(np.array([1.0, 2.0, 3.0, 5.0])).round(3).tolist()   # minus the best line
    [0.2, -0.1, -0.4, 0.3]
    """
    if G is None or G.shape[1] == 0:
        return None
    return Projector(G if rows is None else G[rows], **_BASIS_RULE)


def _optimise(model, t, y, idx, P, p0, max_nfev, memo=None):
    """Bounded least squares of the free parameters from ``p0``: (parameters, Jacobian, converged).

    ``memo`` (a :class:`PredictionMemo` of this model and ``t``) serves predictions already made.
    """
    predict = model.predict if memo is None else memo.predict
    free = model.free
    yy = y[idx]
    lo = np.array([model.bounds.get(k, (-np.inf, np.inf))[0] for k in free], float)
    hi = np.array([model.bounds.get(k, (-np.inf, np.inf))[1] for k in free], float)
    x0 = np.clip(np.array([float(p0[k]) for k in free]), lo, hi)

    def unpack(x):
        p = dict(p0)
        p.update(zip(free, (float(v) for v in x), strict=True))
        return p

    pred0 = predict(t, unpack(x0))  # raises a clear error if the start itself fails
    big = 1e3 * (np.abs(yy).max() + np.abs(pred0[idx]).max() + 1.0)

    def resid(x):
        try:
            r = yy - predict(t, unpack(x))[idx]
        except ModelIntegrationError:
            return np.full(len(yy), big)
        if P is not None:
            r = P.project_out(r)
        return r

    if not free:
        return unpack(x0), np.zeros((len(yy), 0)), True
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        # ODE solutions carry ~1e-9 relative error: a step of 1e-5 of the parameter, and 1e-5
        # absolute for a parameter below 1 (not 1e-5 of ~0, SciPy's rule for a given diff_step),
        # keeps the finite-difference Jacobian well above that floor
        fun, jac = forward_jacobian(resid, 1e-5, lo, hi, scale=float(np.std(yy)) or 1.0,
                                    max_response=MAX_RESPONSE)
        res = varpro(fun, [x0], (lo, hi), x_scale="jac", max_nfev=max_nfev,
                     method="trf", xtol=1e-10, ftol=1e-10, gtol=1e-10, jac=jac).result
    return unpack(res.x), res.jac, bool(res.status > 0)


def fit(model, t, y, *, start=None, G=None, rows=None, max_nfev=300, warn=True) -> Fit:
    """Fit the free parameters of ``model`` to ``y`` (rows ``rows`` only) with ``G`` projected out.

    A model whose parameters have two labellings of the same curve (two exponentials) is refitted
    from its canonical one (:meth:`Model.canonical`), so intervals always describe the same parameter.

    Parameters
    ----------
    model : Model
        The model; its free parameters are fitted.
    t, y : ndarray
        Sample times and samples.
    start : dict, optional
        Starting values (default: ``model.start``).
    G : ndarray, optional
        Disturbance columns, projected out of the residual.
    rows : array_like of int, optional
        Samples to fit (default: all).
    max_nfev : int, optional
        Most model evaluations.
    warn : bool, optional
        Warn (:class:`ConvergenceWarning`) when the fit did not converge.

    Returns
    -------
    Fit

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60)
    >>> f = fit(make_model("freefall"), t, 5.0 - 4.9 * t ** 2, rows=np.arange(30))
    >>> round(f.params["g"], 6), f.n_eff, f.converged
    (9.8, 30, True)
    """
    pt = _point_fit(model, t, y, start, G, rows, max_nfev)
    f = finish_fit(model, t, y, pt, G=G, rows=rows, max_nfev=max_nfev)
    if not pt.converged and warn:
        warnings.warn(f"calibration of {model.name!r} with effects {list(model.effects)} stopped after "
                      f"{max_nfev} evaluations before converging; treat its numbers with care",
                      ConvergenceWarning, stacklevel=2)
    return f


def point_fit(model, t, y, *, start=None, G=None, rows=None, max_nfev=300):
    """The least-squares point estimate of :func:`fit`, without its spread; ``.rss`` as :attr:`Fit.rss`.

    Choosing among several starts needs only each start's sum of squares: the standard errors and
    the identifiability profiles (refits of their own) are computed for the chosen one alone with
    :func:`finish_fit`, which gives exactly the :class:`Fit` that :func:`fit` gives from that start.

    Parameters
    ----------
    model : Model
        The model; its free parameters are fitted.
    t, y : ndarray
        Sample times and samples.
    start : dict, optional
        Starting values (default: ``model.start``).
    G : ndarray, optional
        Disturbance columns, projected out of the residual.
    rows : array_like of int, optional
        Samples to fit (default: all).
    max_nfev : int, optional
        Most model evaluations.

    Returns
    -------
    _PointFit
        Parameters, Jacobian, prediction, disturbance, residual and ``rss``.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 + 0.01 * np.cos(40 * t)
    >>> m = make_model("freefall")
    >>> pt = point_fit(m, t, y)
    >>> f = finish_fit(m, t, y, pt)
    >>> f.rss == pt.rss == fit(m, t, y).rss, f.stderr == fit(m, t, y).stderr
    (True, True)
    """
    return _point_fit(model, t, y, start, G, rows, max_nfev)


def finish_fit(model, t, y, pt, *, G=None, rows=None, max_nfev=300) -> Fit:
    """The :class:`Fit` of a :func:`point_fit` result: robust standard errors and identifiability.

    ``G``, ``rows`` and ``max_nfev`` must be those of the point fit (the identifiability profiles
    refit with them). See :func:`point_fit` for an example.

    Parameters
    ----------
    model : Model
        The fitted model.
    t, y : ndarray
        Sample times and samples.
    pt : _PointFit
        From :func:`point_fit`.
    G : ndarray, optional
        Disturbance columns.
    rows : array_like of int, optional
        Samples fitted.
    max_nfev : int, optional
        Most model evaluations of a profile refit.

    Returns
    -------
    Fit

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2 + 0.01 * np.cos(40 * t)
    >>> m = make_model("freefall")
    >>> f = finish_fit(m, t, y, point_fit(m, t, y))
    >>> sorted(f.stderr) == sorted(m.free), f.unidentified
    (True, [])
    """
    free = model.free
    idx, r = pt.idx, pt.residual
    floor2, rss = pt.floor2, pt.rss
    n_eff = len(idx) - pt.rank
    stderr, interval_dof = {}, np.inf
    if free:
        errs = sandwich_standard_errors(pt.jac, r[idx], max(n_eff - len(free), 1))
        stderr = dict(zip(free, (float(s) for s in errs.stderr), strict=True))
        interval_dof = float(max(errs.n_blocks - 1, 1))
    unidentified = _unidentified(model, t, y, pt, rss, n_eff, G, rows, max_nfev, floor2)
    for group in unidentified:
        # the pseudo-inverse dropped this direction and left its members tight errors: they have none
        stderr.update({k: float("inf") for k in group["parameters"]})
    return Fit(model, pt.params, free, stderr, rss, n_eff, pt.prediction, pt.disturbance, r, pt.converged,
               interval_dof, floor2, unidentified)


def _unidentified(model, t, y, pt, rss, n_eff, G, rows, max_nfev, floor2):
    """Confirmed groups of parameters the record cannot separate (:mod:`odnn_sep.mismatch.identifiability`)."""
    from odnn_sep.mismatch.identifiability import confirmed_groups, suspect_groups
    groups = suspect_groups(pt.jac, list(model.free)) if model.free else []
    if not groups:
        return []

    def refit(pinned, start):
        q = _point_fit(pinned, t, y, start, G, rows, max_nfev)
        return float(np.sum(q.residual[q.idx] ** 2)) + len(q.idx) * floor2

    return confirmed_groups(model, groups, pt.params, rss, n_eff, refit)


@dataclass
class _PointFit:
    """Least-squares point estimate: what :func:`fit` needs before the spread (a held-out refit needs no more)."""

    params: dict
    jac: np.ndarray
    converged: bool
    prediction: np.ndarray
    disturbance: np.ndarray
    residual: np.ndarray
    idx: np.ndarray
    rank: int
    floor2: float = 0.0   # as Fit.floor2
    rss: float = np.nan   # as Fit.rss: the fitted rows' sum of squares plus their resolution floor


def _point_fit(model, t, y, start, G, rows, max_nfev, memo=None):
    """Optimise (again from the canonical labelling when there is one); disturbance and residual at the optimum.

    The start, its first Jacobian and the optimum are usually predictions made before (the same
    start for every fold of a cross-validation; the optimum as a trial point): ``memo`` serves them
    (a new one when not given).
    """
    memo = PredictionMemo(model, t) if memo is None else memo
    idx = np.arange(len(y)) if rows is None else np.asarray(rows)
    P = disturbance_projector(G, idx)
    p, J, converged = _optimise(model, t, y, idx, P, dict(model.start if start is None else start), max_nfev, memo)
    relabelled = model.canonical(p)
    if relabelled is not None:
        p, J, converged = _optimise(model, t, y, idx, P, relabelled, max_nfev, memo)
    pred = memo.predict(t, p)
    r_all = y - pred
    dist = G @ solve(G[idx], r_all[idx], method="lstsq") if P is not None else np.zeros_like(y)
    r = r_all - dist
    floor2 = resolution(np.asarray(y)[idx]) ** 2
    rss = float(np.sum(r[idx] ** 2)) + len(idx) * floor2
    return _PointFit(p, J, converged, pred, dist, r, idx, 0 if P is None else P.rank, floor2, rss)


def t_over_normal(dof, level=0.95):
    """Ratio of the Student-t to the normal two-sided quantile (1 for infinite ``dof``).

    Parameters
    ----------
    dof : float
        Degrees of freedom.
    level : float, optional
        Two-sided coverage.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> t_over_normal(np.inf), round(t_over_normal(9), 3)
    (1.0, 1.154)
    """
    if not np.isfinite(dof):
        return 1.0
    from scipy import stats  # on use: the package is imported by every subcommand
    q = 0.5 + level / 2
    return float(stats.t.ppf(q, dof) / stats.norm.ppf(q))


def cv_folds(n, *, folds=4, blocks_per_fold=5, min_block=3):
    """Interleaved contiguous blocks: block b belongs to fold b % folds. Returns the block id per sample.

    Short records get fewer blocks per fold (at least 2, so the held-out test has at least
    2 x folds paired blocks).

    Parameters
    ----------
    n : int
        Number of samples.
    folds : int, optional
        Number of folds.
    blocks_per_fold : int, optional
        Blocks per fold (fewer for short records).
    min_block : int, optional
        Fewest samples per block.

    Returns
    -------
    ndarray of int, shape (n,)
        Block id of every sample.

    Examples
    --------
    >>> cv_folds(24, folds=2).tolist()
    [0, 0, 0, 1, 1, 1, 2, 2, 2, 3, 3, 3, 4, 4, 4, 5, 5, 5, 6, 6, 6, 7, 7, 7]
    """
    bpf = min(blocks_per_fold, n // (folds * min_block))
    if bpf < 2:
        fewest = 2 * 2 * min_block
        hint = (f"fewer folds (--folds 2, at least {fewest} samples) analyse shorter series, with less power"
                if folds > 2 and n >= fewest else "a longer record (or a finer sampling of it) is needed to test effects")
        raise InputError(f"too little data for the held-out split: {n} samples; need at least "
                         f"{folds * 2 * min_block} ({folds} folds x 2 blocks x {min_block} samples); {hint}")
    n_blocks = folds * bpf
    return np.minimum((np.arange(n) * n_blocks) // n, n_blocks - 1)


def cross_validate(model, t, y, start, *, G=None, block_id, folds=4, max_nfev=30):
    """Held-out mean squared error per block (refit on the other folds, predict the held-out blocks).

    The first and last blocks are always in the training set (their entry is NaN): holding them
    out would test extrapolation beyond the record, where an initial transient (the first minutes
    of a cooling curve) cannot be pinned down by any model, right or wrong.

    Parameters
    ----------
    model : Model
        The model.
    t, y : ndarray
        Sample times and samples.
    start : dict
        Starting values of every refit.
    G : ndarray, optional
        Disturbance columns.
    block_id : ndarray of int
        Block of every sample (:func:`cv_folds`).
    folds : int, optional
        Number of folds.
    max_nfev : int, optional
        Most evaluations per refit.

    Returns
    -------
    ndarray
        Held-out MSE per block (NaN for the first and last).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.linspace(0, 1, 60); y = 5.0 - 4.9 * t ** 2
    >>> m = make_model("freefall")
    >>> mse = cross_validate(m, t, y, m.start, block_id=cv_folds(60, folds=2), folds=2)
    >>> len(mse), bool(np.isnan(mse[0]) and np.isnan(mse[-1])), bool(np.nanmax(mse) < 1e-12)
    (10, True, True)
    """
    n_blocks = int(block_id.max()) + 1
    mse = np.full(n_blocks, np.nan)
    memo = PredictionMemo(model, t)   # every fold starts at ``start``: its prediction and first Jacobian are shared
    for f in range(folds):
        test_blocks = [b for b in range(f, n_blocks, folds) if 0 < b < n_blocks - 1]
        if not test_blocks:
            continue
        test = np.isin(block_id, test_blocks)
        train = np.flatnonzero(~test)
        fr = _point_fit(model, t, y, start, G, train, max_nfev, memo)
        err = y - fr.prediction - fr.disturbance
        for b in test_blocks:
            mse[b] = float(np.mean(err[block_id == b] ** 2))
    return mse
