"""Network solver: the paper's constrained DNN trained jointly with theta (torch, float64).

The network output h(x) is passed through the class's projection layer so the disturbance can
only live in its class: Orthogonal uses Eq. 3 (h minus its projection on span F), subspace
classes apply their exact projector, Convex uses an ICNN and Monotone a monotone MLP (each class
gives its module and layer: ``Disturbance.network`` / ``Disturbance.network_layer``). Training:
Adam, then L-BFGS polishing. Deterministic for a given ``random_state``.
"""
from __future__ import annotations

import logging
import warnings
from typing import TYPE_CHECKING, Any

import numpy as np

from odnn_sep.errors import ConvergenceWarning

if TYPE_CHECKING:
    from odnn_sep.core.base import Disturbance

log = logging.getLogger(__name__)


def fit_network(F: np.ndarray, x: np.ndarray, y: np.ndarray, dist: Disturbance, projector: object,
                **kw: Any) -> dict:
    """Train the class's network jointly with theta (keywords: weights, random_state, epochs, lr, hidden,
    depth, lbfgs_iter, progress). Returns the solver dict without standard errors (see ``NetworkSolver``).

    Parameters
    ----------
    F : (n, p) ndarray
        Basis columns.
    x, y : ndarray
        Coordinates and data.
    dist : Disturbance
        The class whose network represents g.
    projector : object
        The class's projector, or None.
    **kw
        Training options (see above).

    Returns
    -------
    dict
        ``theta``, ``disturbance``, ``loss_history``, ``converged`` and further training diagnostics.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.core import Orthogonal
    >>> x = np.linspace(-1, 1, 50)
    >>> out = fit_network(np.c_[x], x, 2 * x + np.cos(3 * x), Orthogonal(), None, epochs=20)
    >>> round(float(out["theta"][0]), 3)
    2.0
    """
    import torch

    # The networks are tiny: one thread is as fast and does not fight other processes for cores.
    saved = torch.get_num_threads()
    torch.set_num_threads(1 if F.shape[0] <= 20000 else saved)
    try:
        return _fit_network(F, x, y, dist, projector, **kw)
    finally:
        torch.set_num_threads(saved)


def _lbfgs(params, loss_fn, *, max_iter, history_size):
    import torch

    opt = torch.optim.LBFGS(params, lr=1.0, max_iter=max_iter, tolerance_grad=1e-15, tolerance_change=1e-18,
                            history_size=history_size, line_search_fn="strong_wolfe")

    def closure():
        opt.zero_grad()
        loss = loss_fn()
        loss.backward()
        return loss

    opt.step(closure)
    return opt


def _fit_network(F, x, y, dist, projector, *, weights=None, random_state=None, epochs=1500, lr=1e-2,
                 hidden=32, depth=3, lbfgs_iter=300, progress=False):
    """Body of :func:`fit_network`.

    Why long (13 parameters): the problem's five arrays and objects plus one keyword per training
    knob of the paper's solver, each passed through unchanged from :class:`NetworkSolver`."""
    import torch

    torch.manual_seed(0 if random_state is None else int(random_state))
    dt = torch.float64
    X = x[:, None] if x.ndim == 1 else x
    # standardise inputs and outputs so one learning rate fits all problems
    xc, xs = X.mean(0), np.where(X.std(0) > 0, X.std(0), 1.0)
    ys = float(np.std(y)) or 1.0
    Xt = torch.as_tensor((X - xc) / xs, dtype=dt)
    Yt = torch.as_tensor(y / ys, dtype=dt)
    Ft = torch.as_tensor(F, dtype=dt)
    fs = torch.linalg.norm(Ft, dim=0) / np.sqrt(F.shape[0])
    Fn = Ft / fs
    W = None if weights is None else torch.as_tensor(weights / np.mean(weights), dtype=dt)
    net = dist.network(Xt.shape[1], hidden, depth).to(dt)
    theta = torch.zeros(F.shape[1], dtype=dt, requires_grad=True)
    sw = torch.ones_like(Yt) if W is None else torch.sqrt(W)
    layer, Fperp = dist.network_layer(Fn, sw, projector)
    split = Fperp is not None

    def loss_fn():
        if split:
            r = Yt - Fperp @ theta - layer(net(Xt))
            return torch.mean(r * r)
        r = Yt - Fn @ theta - layer(net(Xt))
        return torch.mean(r * r) if W is None else torch.mean(W * r * r)

    history = _train(net, theta, loss_fn, epochs=epochs, lr=lr, lbfgs_iter=lbfgs_iter, progress=progress)
    with torch.no_grad():
        final = float(loss_fn())
        g = layer(net(Xt))
        if split:
            g = g - (Fn - Fperp) @ theta
        g = g.numpy() * ys
        th = (theta / fs).numpy() * ys
    history.append(final)
    grad_norm = float(torch.linalg.norm(theta.grad)) if theta.grad is not None else 0.0
    converged = bool(np.isfinite(final) and grad_norm < 1e-6)
    if not converged:
        warnings.warn(f"network solver stopped with theta-gradient norm {grad_norm:.2e} (loss {final:.3e}); "
                      "increase epochs", ConvergenceWarning, stacklevel=5)
    return {"theta": th, "disturbance": g, "loss_history": history, "converged": converged,
            "diagnostics": {"network_final_loss": final * ys * ys, "network": type(net).__name__}}


def _train(net, theta, loss_fn, *, epochs: int, lr: float, lbfgs_iter: int, progress: bool = False) -> list:
    """Adam with a cosine schedule, a joint L-BFGS polish, then L-BFGS on theta alone; leaves the
    gradient of the final loss in ``theta.grad``. Returns the loss every 50 Adam steps. With
    ``progress``, a bar on stderr counts the Adam epochs (training takes minutes on long inputs)."""
    import sys

    import torch
    from tqdm import tqdm

    history = []
    opt = torch.optim.Adam([{"params": net.parameters(), "lr": lr * 0.3}, {"params": [theta], "lr": lr}])
    sched = torch.optim.lr_scheduler.CosineAnnealingLR(opt, max(1, epochs), eta_min=lr * 1e-3)
    for it in tqdm(range(epochs), desc="network solver", unit="epoch", file=sys.stderr, leave=False,
                   disable=not progress):
        opt.zero_grad()
        loss = loss_fn()
        loss.backward()
        opt.step()
        sched.step()
        if it % 50 == 0:
            history.append(float(loss.detach()))
    _lbfgs(list(net.parameters()) + [theta], loss_fn, max_iter=lbfgs_iter, history_size=50)
    # Adam leaves theta jittering around its optimum, and the joint L-BFGS can stop early on the
    # network's rough landscape; theta's own problem (network fixed) is a convex quadratic, so a
    # last L-BFGS pass on theta alone converges it.
    for q in net.parameters():
        q.requires_grad_(False)
    lb_theta = _lbfgs([theta], loss_fn, max_iter=200, history_size=20)
    lb_theta.zero_grad()
    loss_fn().backward()
    return history
