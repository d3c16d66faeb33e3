"""Generic 1-D/2-D signal front-end: separate a recording with a basis written as expressions."""
from odnn_sep.fit.data import load_signal
from odnn_sep.fit.expr import basis_from_expressions, parse_disturbance

__all__ = ["basis_from_expressions", "load_signal", "parse_disturbance"]
