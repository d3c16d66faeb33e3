"""Long records for ``bench_mismatch_long.py``: one system at its natural length or densely sampled.

Run as a script it analyses one record and prints one JSON line (time, ODE right-hand-side calls,
samples fitted, verdict, intervals of the base parameters and whether they cover the truth), so the
benchmark can run each case in its own process with a time limit, against any checkout
(``PYTHONPATH=<checkout>``):

    python recipes/_mismatch_long_cases.py oscillator 20000 100 [effect]
"""
from __future__ import annotations

import json
import sys
import time
import warnings

import numpy as np

# system: preset (or "user"), true parameters, span, natural length, noise, effect and its parameters
SYSTEMS = {
    "oscillator": ("oscillator", {"k": 4.0, "c": 0.05, "x0": 1.0, "v0": 0.0}, (0, 20), 400, 0.01,
                   ("cubic_stiffness", {"beta": 0.02})),
    "pendulum": ("pendulum", {"w2": 9.81, "c": 0.05, "theta0": 0.3, "omega0": 0.0}, (0, 15), 500, 0.002,
                 ("large_angle", {"s_angle": 1.0})),
    "cooling": ("cooling", {"h": 0.02, "T_ambient": 22.0, "T0": 95.0}, (0, 200), 200, 0.1,
                ("radiation", {"r_rad": 0.003})),
    # a cup logged at 1 Hz for four hours
    "cooling_hours": ("cooling", {"h": 0.0004, "T_ambient": 22.0, "T0": 95.0}, (0, 14400), 200, 0.1,
                      ("radiation", {"r_rad": 0.00006})),
    "freefall": ("freefall", {"g": 9.81, "h0": 2.0}, (0, 0.6), 120, 0.001,
                 ("quadratic_drag", {"q_drag": 0.02})),
    # a user ODE (Newton's law of cooling written by hand), its record made by the cooling preset
    "user": ("user", {"h": 0.02, "T_ambient": 22.0, "T0": 95.0}, (0, 200), 200, 0.1,
             ("radiation", {"r_rad": 0.003})),
}
BASE = {"oscillator": ("k", "c"), "pendulum": ("w2", "c"), "cooling": ("h", "T_ambient"),
        "cooling_hours": ("h", "T_ambient"), "freefall": ("g", "h0"), "user": ("h", "Ta")}


def record(system, n, seed, effect):
    """(t, y) of ``system`` with ``n`` samples over its span (noise and truth fixed by ``seed``)."""
    from odnn_sep.mismatch import make_model
    preset, params, (a, b), _, noise, (eff, eff_params) = SYSTEMS[system]
    t = np.linspace(a, b, n)
    m = make_model("cooling" if preset == "user" else preset, params)
    if effect:
        m = m.with_effect(eff, eff_params)
    return t, m.predict(t) + noise * np.random.default_rng(seed).normal(size=n)


def user_model():
    """Newton's law of cooling as a user ODE (its parameters h, Ta and the initial state T0)."""
    from odnn_sep.mismatch import ode_model
    return ode_model(lambda t, s, h, Ta: [-h * (s[0] - Ta)], {"h": 0.03, "Ta": 20.0, "T0": 90.0}, ["T0"],
                     name="newton")


def _count_rhs_calls():
    """Wrap the ODE integrator so every right-hand-side call is counted (a measure of work, not of time)."""
    import odnn_sep.mismatch.presets_base as pb
    calls = [0]
    original = pb.integrate_ode

    def counting(name, rhs, state0, t, p):
        def counted(tt, st):
            calls[0] += 1
            return rhs(tt, st)
        return original(name, counted, state0, t, p)
    for mod in list(sys.modules.values()):
        if getattr(mod, "__name__", "").startswith("odnn_sep.mismatch") and \
                getattr(mod, "integrate_ode", None) is original:
            mod.integrate_ode = counting
    return calls


def run_case(system, n, seed, effect):
    """Analyse one record; a dict of what was found and what it cost."""
    from odnn_sep.mismatch import explain
    calls = _count_rhs_calls()
    t, y = record(system, n, seed, effect)
    model = user_model() if system == "user" else SYSTEMS[system][0]
    w0, c0 = time.time(), time.process_time()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        res = explain(model, t, y)
    fin = res.final_fit or res.calibration.fit
    iv = fin.intervals()
    truth = dict(SYSTEMS[system][1])
    if system == "user":
        truth["Ta"] = truth.pop("T_ambient")
    cover = {}
    for k in BASE[system]:
        lo_hi = iv.get(k)
        cover[k] = None if lo_hi is None or lo_hi[0] is None else bool(lo_hi[0] <= truth[k] <= lo_hi[1])
    return dict(system=system, n=n, seed=seed, effect=effect, wall_s=round(time.time() - w0, 2),
                cpu_s=round(time.process_time() - c0, 2), rhs_calls=calls[0], fitted=len(res.y),
                named=res.effects, disturbances=[d["effect"] for d in res.disturbances],
                params={k: float(fin.params[k]) for k in BASE[system]},
                intervals={k: (None if iv.get(k) is None else [float(v) for v in iv[k]]) for k in BASE[system]},
                covers=cover)


if __name__ == "__main__":
    s, n_, seed_ = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
    print(json.dumps(run_case(s, n_, seed_, len(sys.argv) > 4 and sys.argv[4] == "effect")))
