"""The result of a separation: parameters with uncertainty, the three parts of y, diagnostics."""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from odnn_sep.io_utils import to_jsonable as _jsonable


@dataclass(frozen=True)
class Result:
    """Outcome of ``Separator.fit``.

    ``physics + disturbance + residual == y`` holds to rounding. ``interval`` is a 95 % confidence
    interval for point-identified theta, and the identified set (profile-likelihood, 95 %) for cone
    classes, where ``identified == "set"`` and ``theta`` is the interval centre.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Basis, Even, Separator
    >>> x = np.linspace(-1, 1, 101)
    >>> r = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, 2 * x + np.cos(x)).result_
    >>> {k: round(v, 9) for k, v in r.theta_dict().items()}, r.identified
    ({'a': 2.0}, 'point')
    >>> bool(np.allclose(r.physics + r.disturbance + r.residual, 2 * x + np.cos(x)))
    True
    """

    theta: np.ndarray
    names: tuple
    stderr: np.ndarray
    interval: np.ndarray
    physics: np.ndarray
    disturbance: np.ndarray
    residual: np.ndarray
    solver: str
    disturbance_class: str
    identified: str = "point"
    phi: dict = field(default_factory=dict)
    phi_stderr: dict = field(default_factory=dict)
    loss_history: tuple = ()
    converged: bool = True
    diagnostics: dict = field(default_factory=dict)

    def theta_dict(self) -> dict:
        """``{name: theta}`` as Python floats."""
        return dict(zip(self.names, (float(t) for t in self.theta)))

    def as_dict(self) -> dict:
        """JSON-ready summary (no per-sample arrays); a value that is not finite (no noise estimate) is None.

        Examples
        --------
        >>> import json
        >>> import numpy as np
        >>> from odnn_sep.core import Basis, Even, Separator
        >>> x = np.array([-1.0, 0.0, 1.0])                  # the even class takes 2 of 3 points, theta the third
        >>> r = Separator(Basis([lambda x: x], names=["a"]), disturbance=Even()).fit(x, 2 * x + 1).result_
        >>> d = json.loads(json.dumps(r.as_dict(), allow_nan=False))["parameters"]["a"]
        >>> round(d["value"], 9), d["stderr"], d["interval"]
        (2.0, None, [None, None])
        """
        params = {
            n: {"value": _jsonable(float(t)), "stderr": _jsonable(float(s)), "interval": [_jsonable(float(a)),
                                                                                          _jsonable(float(b))]}
            for n, t, s, (a, b) in zip(self.names, self.theta, self.stderr, self.interval)
        }
        # NaN in json.dumps is not JSON (strict parsers, JavaScript's JSON.parse refuse it)
        return {
            "parameters": params,
            "phi": {k: {"value": _jsonable(float(v)), "stderr": _jsonable(float(self.phi_stderr.get(k, np.nan)))}
                    for k, v in self.phi.items()},
            "identified": self.identified,
            "solver": self.solver,
            "disturbance_class": self.disturbance_class,
            "converged": bool(self.converged),
            "diagnostics": {k: _jsonable(v) for k, v in self.diagnostics.items()},
        }

    def summary(self) -> str:
        """A few lines for people: every parameter with its standard error and interval."""
        lines = [f"ODNN separation ({self.solver} solver, disturbance {self.disturbance_class}, "
                 f"{self.identified}-identified)"]
        lab = "identified set" if self.identified == "set" else "95% CI"
        for n, t, s, (a, b) in zip(self.names, self.theta, self.stderr, self.interval):
            if np.isnan(s) and not np.isfinite([a, b]).any():
                # no residual degrees of freedom: the fit is exact and the noise cannot be estimated
                lines.append(f"  {n:>16s} = {t: .6g}  (no interval: no points are left to estimate the noise)")
                continue
            lines.append(f"  {n:>16s} = {t: .6g}  ± {s:.2g}   {lab} [{a:.6g}, {b:.6g}]")
        for k, v in self.phi.items():
            lines.append(f"  {k:>16s} = {v: .8g}  ± {self.phi_stderr.get(k, np.nan):.2g}  (nonlinear)")
        return "\n".join(lines)
