"""The ODNN separator: y = F(phi) theta + g + noise with g confined to a disturbance class."""
from __future__ import annotations

import itertools
import logging
import warnings

import numpy as np

from odnn_sep.core import cone
from odnn_sep.core.basis import Basis
from odnn_sep.core.checks import check_basis_matrix, check_outside_class, check_xy
from odnn_sep.core.disturbance import DISTURBANCES, Orthogonal
from odnn_sep.core.linalg import (
    Z95,
    intervals,
    noise_variance,
    orthonormal_basis,
    solve,
    standard_errors,
    stderr_from_cov,
    varpro,
    varpro_residual,
)
from odnn_sep.core.result import Result
from odnn_sep.errors import IdentifiabilityWarning, InputError

log = logging.getLogger(__name__)


class Separator:
    """Separate known physics from a disturbance confined to a class that cannot imitate it.

    Parameters
    ----------
    basis : Basis or ParametricBasis
    disturbance : disturbance class instance, default ``Orthogonal()``
    solver : {"exact", "network"}
        ``"exact"``: closed-form projection (subspace classes) or shape-constrained least squares
        (cones). ``"network"``: the paper's constrained network trained by gradient descent (torch);
        it must agree with the exact solver where both apply.
    random_state : int, optional
        Seed for the network solver and multi-start search.
    n_starts : int
        Random starts for nonlinear parameters without a grid.
    epochs : int
        Network-solver Adam iterations (followed by L-BFGS polishing).

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-2, 2, 401)
    >>> y = 0.5 * x**2 * np.sin(5 * x) + np.cos(x)      # physics odd, disturbance even
    >>> r = Separator(Basis([lambda x: x**2 * np.sin(5 * x)], names=["a"]), disturbance=Even()).fit(x, y).result_
    >>> round(float(r.theta[0]), 6)
    0.5
    """

    def __init__(self, basis: Basis, disturbance=None, solver: str = "exact", *, random_state=None,
                 n_starts: int = 8, epochs: int = 1500, lr: float = 1e-2):
        self.basis = basis
        self.disturbance = disturbance
        self.solver = solver
        self.random_state = random_state
        self.n_starts = n_starts
        self.epochs = epochs
        self.lr = lr

    # ------------------------------------------------------------------------------------------
    def _validate(self):
        if not isinstance(self.basis, Basis):
            raise InputError(f"basis must be an odnn_sep.core.Basis; got {type(self.basis).__name__}")
        dist = Orthogonal() if self.disturbance is None else self.disturbance
        if not isinstance(dist, DISTURBANCES):
            allowed = ", ".join(c.__name__ for c in DISTURBANCES)
            raise InputError(f"disturbance must be one of {allowed}; got {dist!r}")
        if self.solver not in ("exact", "network"):
            raise InputError(f"solver must be 'exact' or 'network'; got {self.solver!r}")
        return dist

    def fit(self, x, y, weights=None) -> "Separator":
        dist = self._validate()
        x, y, weights = check_xy(x, y, weights)
        if weights is not None and dist.kind != "orthogonal":
            raise InputError(f"weights are supported only with Orthogonal(); got disturbance {dist!r}")
        if dist.kind == "cone" and x.ndim != 1:
            raise InputError(f"{type(dist).__name__} needs 1-D x; got shape {x.shape}")
        names = self.basis.names
        projector = dist.prepare(x) if dist.kind == "subspace" else None
        check_basis_matrix(self.basis.evaluate(x), names, n_extra=len(self.basis.phi_names))

        phi, phi_info = {}, {}
        if self.basis.is_parametric:
            phi, phi_info = self._fit_phi(x, y, weights, dist, projector)
        F = self.basis.evaluate(x, phi)
        check_basis_matrix(F, names)

        if self.solver == "exact":
            out = self._exact(F, x, y, weights, dist, projector)
        else:
            from odnn_sep.core.network import fit_network

            out = fit_network(F, x, y, dist, projector, weights=weights, random_state=self.random_state,
                              epochs=self.epochs, lr=self.lr)
            # uncertainty and identified sets come from the exact analysis of the same problem
            exact = self._exact(F, x, y, weights, dist, projector)
            out["stderr"], out["interval_exact"] = exact["stderr"], exact["interval"]
            out["diagnostics"] = {**exact["diagnostics"], **out.get("diagnostics", {}),
                                  "exact_theta": exact["theta"].tolist()}
            if dist.kind == "cone":
                out["interval"] = exact["interval"]
            else:
                out["interval"] = intervals(out["theta"], exact["stderr"])
        diag = dict(out.get("diagnostics", {}))
        diag.update(phi_info.get("diagnostics", {}))
        g = out["disturbance"]
        g_norm = float(np.linalg.norm(g))
        if g_norm > 0:
            # how much of the estimated disturbance lies in span(F): that part would have gone into theta
            Q = orthonormal_basis(F, method="qr", rtol=None)
            diag["disturbance_in_basis_span"] = float(np.linalg.norm(Q.T @ g)) / g_norm
        self.result_ = Result(
            theta=out["theta"], names=names, stderr=out["stderr"], interval=out["interval"],
            physics=F @ out["theta"], disturbance=g, residual=y - F @ out["theta"] - g,
            solver=self.solver, disturbance_class=dist.describe(),
            identified="set" if dist.kind == "cone" else "point",
            phi=phi, phi_stderr=phi_info.get("stderr", {}),
            loss_history=tuple(out.get("loss_history", ())), converged=bool(out.get("converged", True)),
            diagnostics=diag,
        )
        self.theta_ = self.result_.theta
        self.phi_ = phi
        return self

    # ------------------------------------------------------------------------------------------
    def _exact(self, F, x, y, weights, dist, projector) -> dict:
        names = self.basis.names
        n, p = F.shape
        if dist.kind == "cone":
            c = cone.fit_cone(F, x, y, dist, random_state=self.random_state)
            width = c["interval"][:, 1] - c["interval"][:, 0]
            rel = width / np.maximum(np.abs(c["theta_mid"]), 1e-300)
            if np.any(rel > 0.05):
                warnings.warn(
                    f"theta is only set-identified with the {dist.describe()} disturbance class: identified "
                    f"intervals {dict(zip(names, np.round(c['interval'], 6).tolist()))} (relative widths "
                    f"{np.round(rel, 3).tolist()}); the point estimate is the interval centre",
                    IdentifiabilityWarning, stacklevel=3,
                )
            return {"theta": c["theta_mid"], "stderr": width / (2 * Z95), "interval": c["interval"],
                    "disturbance": c["g"],
                    "diagnostics": {"theta_least_squares": c["theta_ls"].tolist(), "rss_min": c["rss_min"],
                                    "sigma": float(np.sqrt(c["sigma2"])), "active_cone_generators": c["active"],
                                    "cone_generators": c["generators"], "exact_cone": c["exact_cone"],
                                    "interval_relative_width": rel.tolist()}}
        if dist.kind == "orthogonal":
            Fp, yp, rank_g = F, y, 0
            diag = check_outside_class(F, F, names, dist.describe())
        else:
            Fp = F - projector.apply(F)
            yp = y - projector.apply(y)
            rank_g = projector.rank
            diag = check_outside_class(F, Fp, names, dist.describe())
        theta, cov_u, rank = solve(Fp, yp, weights=weights, method="qr", return_cov=True)
        r = yp - Fp @ theta
        if dist.kind == "orthogonal":
            # g absorbs everything outside span(F); the noise level comes from the fit residual,
            # which treats g as noise (conservative when g is not exactly orthogonal).
            dof = n - rank
            sigma2 = noise_variance(r, dof, np.ones(n) if weights is None else weights)
            disturbance = y - F @ theta
        else:
            dof = n - rank_g - rank
            sigma2 = noise_variance(r, dof)
            disturbance = projector.apply(y - F @ theta)
        stderr = stderr_from_cov(cov_u, sigma2)
        diag.update({"sigma": float(np.sqrt(sigma2)) if np.isfinite(sigma2) else None, "dof": int(dof),
                     "disturbance_rank": int(rank_g)})
        return {"theta": theta, "stderr": stderr, "interval": intervals(theta, stderr),
                "disturbance": disturbance, "diagnostics": diag, "cov": cov_u * sigma2}

    # ------------------------------------------------------------------------------------------
    def _residual_fn(self, x, y, weights, dist, projector):
        """Variable projection: residual vector as a function of phi with theta solved exactly inside."""
        basis = self.basis
        keys = basis.phi_names
        design = lambda v: basis.evaluate(x, dict(zip(keys, v)))  # noqa: E731
        if dist.kind == "cone":
            def resid(v):
                c = cone._solve(np.hstack([design(v), cone.cone_generators(np.sort(x), dist)[0]]),
                                cone.cone_generators(np.sort(x), dist)[1], y[np.argsort(x)])
                return np.array([np.sqrt(c[2])])
            return resid
        return varpro_residual(design, y, project_out=None if projector is None else projector.project_out,
                               weights=weights)

    def _fit_phi(self, x, y, weights, dist, projector):
        basis = self.basis
        keys = basis.phi_names
        bounds = basis.bounds
        lo = np.array([bounds[k][0] for k in keys], dtype=float)
        hi = np.array([bounds[k][1] for k in keys], dtype=float)
        resid = self._residual_fn(x, y, weights, dist, projector)
        cost = lambda v: float(np.sum(resid(v) ** 2))  # noqa: E731
        starts = [np.array([basis.phi0[k] for k in keys])]
        grid = basis.grid
        if grid:
            axes = [np.asarray(grid.get(k, [basis.phi0[k]]), dtype=float) for k in keys]
            cand = list(itertools.product(*axes))
            if len(cand) > 5000:
                raise InputError(f"the phi grid has {len(cand)} points; keep it under 5000 (coarsen the grid)")
            costs = [cost(np.array(c)) for c in cand]
            starts += [np.array(cand[i]) for i in np.argsort(costs)[:3]]
        elif np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and self.n_starts > 1:
            rng = np.random.default_rng(self.random_state)
            starts += [lo + (hi - lo) * rng.random(len(keys)) for _ in range(self.n_starts - 1)]
        best = varpro(resid, starts, (lo, hi), scalar=dist.kind == "cone")
        val, v = best.cost, best.phi
        phi = dict(zip(keys, (float(t) for t in v)))
        at_bound = [k for k, t, a, b in zip(keys, v, lo, hi) if np.isclose(t, a) or np.isclose(t, b)]
        if at_bound:
            warnings.warn(f"nonlinear parameter(s) {at_bound} ended on their bounds; widen the bounds",
                          IdentifiabilityWarning, stacklevel=3)
        stderr = {}
        if dist.kind != "cone":
            # Jacobian of the reduced residual w.r.t. phi; the projected-out theta is accounted for by VarPro.
            J = best.jac
            r = resid(v)
            dof = r.size - len(keys) - self.basis.n_columns - (projector.rank if projector is not None else 0)
            if J is not None and dof > 0:
                try:
                    stderr = dict(zip(keys, standard_errors(J, r, dof).tolist()))
                except np.linalg.LinAlgError:
                    stderr = {}
        return phi, {"stderr": stderr, "diagnostics": {"phi_starts": len(starts), "phi_cost": float(val)}}
