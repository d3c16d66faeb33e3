"""Small torch networks for the disturbance term (the paper's constrained DNNs).

- ``MLP``: unconstrained; used inside projection layers (Orthogonal/Even/Periodic/Band) and by the
  regular-DNN baseline.
- ``ICNN``: input-convex network (Amos et al. 2017): non-negative weights on the hidden path and
  convex, non-decreasing activations make the output convex in the input.
- ``MonotoneMLP``: non-negative weights throughout with monotone activations give an output that is
  non-decreasing in every input; ``increasing=False`` flips the sign.

Only this module and ``network.py`` import torch, and only when the network solver is used: the
classes are built on first access (``from odnn_sep.core.nets import MLP``), so importing the module
does not need torch.

Examples
--------
>>> import torch
>>> from odnn_sep.core.nets import ICNN
>>> _ = torch.manual_seed(0)
>>> net = ICNN(in_dim=1, hidden=8, depth=2)
>>> g = net(torch.linspace(-2, 2, 41)[:, None]).detach().squeeze()
>>> bool((g[:-2] - 2 * g[1:-1] + g[2:] >= -1e-6).all())      # convex whatever the weights
True
"""
from __future__ import annotations

import functools
from types import ModuleType
from typing import Any

#: The torch modules, built on first access by the module ``__getattr__``.
NETWORKS = ("MLP", "ICNN", "MonotoneMLP")
__all__ = ["require_torch", *NETWORKS]  # noqa: F822 - the networks come from __getattr__


def __getattr__(name: str):
    if name in NETWORKS:
        return _classes()[name]
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def require_torch() -> ModuleType:
    """Import and return torch, or raise a one-line InputError naming the ``network`` extra.

    Examples
    --------
    >>> require_torch().__name__
    'torch'
    """
    try:
        import torch
    except ImportError:  # pragma: no cover - depends on the environment
        from odnn_sep.errors import InputError

        raise InputError("the network solver needs torch: install the `network` extra "
                         "(pip install 'odnn-sep[network]') or use solver='exact'") from None
    return torch


@functools.lru_cache(maxsize=None)
def _classes() -> dict:
    """Define the torch modules once, on first use: defining them inside functions is what keeps
    ``import odnn_sep.core.nets`` free of torch."""
    torch = require_torch()
    return {"MLP": _mlp_class(torch), "ICNN": _icnn_class(torch), "MonotoneMLP": _monotone_class(torch)}


def _softplus_pos(w):
    # Reparametrise to keep weights non-negative without projected steps.
    from torch.nn import functional as F

    return F.softplus(w)


def _mlp_class(torch):
    from torch import nn

    class MLP(nn.Module):
        def __init__(self, in_dim: int = 1, hidden: int = 32, depth: int = 3, out_dim: int = 1):
            super().__init__()
            layers: list[nn.Module] = []
            d = in_dim
            for _ in range(depth):
                layers += [nn.Linear(d, hidden), nn.Tanh()]
                d = hidden
            layers.append(nn.Linear(d, out_dim))
            self.net = nn.Sequential(*layers)

        def forward(self, x: Any) -> Any:
            return self.net(x).squeeze(-1)

    return MLP


def _icnn_class(torch):
    from torch import nn
    from torch.nn import functional as F

    class ICNN(nn.Module):
        """z_{k+1} = softplus(W_k^+ z_k + A_k x + b_k); output = w^+ . z_K + a . x + b (convex in x)."""

        def __init__(self, in_dim: int = 1, hidden: int = 32, depth: int = 3):
            super().__init__()
            self.inp = nn.ModuleList([nn.Linear(in_dim, hidden) for _ in range(depth)])
            self.hid = nn.ParameterList(
                [nn.Parameter(torch.randn(hidden, hidden) * 0.1 - 1.0) for _ in range(depth - 1)]
            )
            self.out_w = nn.Parameter(torch.randn(hidden) * 0.1 - 1.0)
            self.out_lin = nn.Linear(in_dim, 1)

        def forward(self, x: Any) -> Any:
            z = F.softplus(self.inp[0](x))
            for A, W in zip(self.inp[1:], self.hid):
                z = F.softplus(z @ _softplus_pos(W).T + A(x))
            return z @ _softplus_pos(self.out_w) + self.out_lin(x).squeeze(-1)

    return ICNN


def _monotone_class(torch):
    from torch import nn

    class MonotoneMLP(nn.Module):
        """Output non-decreasing in each input (non-increasing with ``increasing=False``)."""

        def __init__(self, in_dim: int = 1, hidden: int = 32, depth: int = 3, increasing: bool = True):
            super().__init__()
            self.sign = 1.0 if increasing else -1.0
            dims = [in_dim] + [hidden] * depth + [1]
            self.w = nn.ParameterList([nn.Parameter(torch.randn(o, i) * 0.3 - 1.0) for i, o in zip(dims, dims[1:])])
            self.b = nn.ParameterList([nn.Parameter(torch.zeros(o)) for o in dims[1:]])

        def forward(self, x: Any) -> Any:
            h = self.sign * x
            for k, (w, b) in enumerate(zip(self.w, self.b)):
                h = h @ _softplus_pos(w).T + b
                if k < len(self.w) - 1:
                    h = torch.tanh(h)
            return h.squeeze(-1)

    return MonotoneMLP
