"""Mismatch finder: where a simulation and a recording disagree, which physics is missing, and the refit.

Examples
--------
>>> import numpy as np
>>> from odnn_sep.mismatch import explain
>>> t = np.linspace(0, 100, 300)
>>> y = 20 + 70 * np.exp(-0.03 * t) + 0.05 * np.random.default_rng(1).normal(size=300)
>>> explain("cooling", t, y).effect is None
True
"""
from odnn_sep.mismatch.calibrate import calibrate, slow_disturbance  # noqa: F401
from odnn_sep.mismatch.effects import EFFECTS, VOCABULARY, Effect  # noqa: F401
from odnn_sep.mismatch.explain import MismatchResult, explain  # noqa: F401
from odnn_sep.mismatch.locate import locate  # noqa: F401
from odnn_sep.mismatch.model import Model, custom_model, make_model, ode_model  # noqa: F401
from odnn_sep.mismatch.presets import PRESETS, ModelIntegrationError  # noqa: F401

__all__ = ["explain", "calibrate", "locate", "make_model", "custom_model", "ode_model", "Model",
           "MismatchResult", "EFFECTS", "VOCABULARY", "PRESETS", "ModelIntegrationError", "slow_disturbance"]
