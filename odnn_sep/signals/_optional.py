"""Former name of :mod:`odnn_sep.signals.optional`; kept so that imports written before the rename work."""
from odnn_sep.errors import MissingDependencyError
from odnn_sep.signals.optional import require

__all__ = ["require", "MissingDependencyError"]
