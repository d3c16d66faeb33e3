"""odnn-sep: separate known physics from disturbances.

Model: ``y = sum_j theta_j f_j(x) + g(x) + noise`` with ``g`` confined to a class that cannot
imitate the physics. Importing this package never imports torch; the network solver loads it
on first use.
"""
__version__ = "0.1.0"

from odnn_sep.errors import (  # noqa: F401
    FormatError,
    IdentifiabilityWarning,
    InputError,
    NotIdentifiableError,
    OdnnSepError,
)


def __getattr__(name):
    # Lazy re-exports keep `import odnn_sep` (and `odnn-sep --help`) light.
    core_names = {"Basis", "ParametricBasis", "Separator", "Result", "Orthogonal", "Even", "Periodic",
                  "Band", "Subspace", "Convex", "Monotone"}
    if name in core_names:
        from odnn_sep import core
        return getattr(core, name)
    raise AttributeError(f"module 'odnn_sep' has no attribute {name!r}")
