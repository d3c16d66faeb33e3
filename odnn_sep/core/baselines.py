"""Baselines that ODNN is compared against in Table 1 (paper section 4.5).

All take the physics columns already evaluated, ``F`` of shape (n, p), and return ``theta`` (p,).

- :func:`ols`: ordinary least squares on the raw data. Unbiased exactly when the disturbance is
  orthogonal to span(F) in the empirical inner product (explicit orthogonality, Eq. 3).
- :func:`regular_dnn`: Eq. 2, an unconstrained MLP ``h`` trained jointly with ``F @ theta``.
  Proposition 1: the MLP can represent the physics too, so every theta is (nearly) a minimiser
  and the one gradient descent stops at depends on initialisation and training length.
- :func:`pinn_penalty`: the same model plus ``lam * mean((P_F h)**2)``, the network's projection on
  span(F). With an exact global optimum the penalty drives ``P_F h`` to zero and theta to the OLS
  value, for any ``lam > 0``; trained for a finite number of steps with a finite ``lam`` the network
  keeps part of the physics, which is where its bias comes from.
- :func:`sindy`: pysindy's sequentially thresholded least squares (STLSQ) on the columns of F.

The torch baselines are deterministic for a given ``random_state`` and small on purpose (CPU,
about a second per fit at n = 1000).
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike

from odnn_sep.errors import InputError, as_float_array

__all__ = ["ols", "regular_dnn", "pinn_penalty", "sindy", "Training"]


@dataclass(frozen=True)
class Training:
    """Training options of the torch baselines (the knobs of the paper's baseline set-up).

    Examples
    --------
    >>> Training(hidden=8, depth=2, epochs=10, lr=1e-2, random_state=0, theta_init=None).checked(p=1).epochs
    10
    >>> Training(hidden=8, depth=2, epochs=0, lr=1e-2, random_state=0, theta_init=None).checked(p=1)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: epochs must be a positive integer; got 0
    """

    hidden: int
    depth: int
    epochs: int
    lr: float
    random_state: int
    theta_init: object

    def checked(self, p: int) -> "Training":
        """Itself, or InputError naming the first bad option (``p``: number of physics columns)."""
        if self.theta_init is not None:
            t0 = np.asarray(self.theta_init, dtype=float)
            if t0.ndim > 1 or (t0.ndim == 1 and t0.shape[0] != p) or not np.all(np.isfinite(t0)):
                raise InputError(f"theta_init must be a finite scalar or have {p} entries; got {self.theta_init!r}")
        for name, v in (("hidden", self.hidden), ("depth", self.depth), ("epochs", self.epochs)):
            if int(v) != v or v < 1:
                raise InputError(f"{name} must be a positive integer; got {v!r}")
        if not self.lr > 0:
            raise InputError(f"lr must be > 0; got {self.lr!r}")
        return self


def _check(F, y, x=None):
    F = as_float_array("F", F, ndim=(1, 2))
    if F.ndim == 1:
        F = F[:, None]
    y = as_float_array("y", y, ndim=(1,))
    if F.shape[0] != y.shape[0]:
        raise InputError(f"F has {F.shape[0]} rows but y has {y.shape[0]} samples; they must match")
    if F.shape[0] <= F.shape[1]:
        raise InputError(
            f"F has {F.shape[1]} columns but only {F.shape[0]} rows; need more samples than parameters"
        )
    if x is None:
        return F, y
    x = as_float_array("x", x, ndim=(1, 2))
    if x.shape[0] != y.shape[0]:
        raise InputError(f"x has {x.shape[0]} samples but y has {y.shape[0]}; they must match")
    return F, y, x


def ols(F: ArrayLike, y: ArrayLike) -> np.ndarray:
    """Ordinary least squares ``argmin ||y - F theta||``.

    Parameters
    ----------
    F : array_like, shape (n, p)
        Physics columns.
    y : array_like, shape (n,)
        Observations.

    Returns
    -------
    theta : ndarray, shape (p,)

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-1, 1, 50)
    >>> ols(np.c_[x], 2 * x).round(6)
    array([2.])
    """
    F, y = _check(F, y)
    theta, *_ = np.linalg.lstsq(F, y, rcond=None)
    return theta


def _torch_fit(x, y, F, lam: float, opts: Training, return_loss: bool = False):
    import torch

    # Nets this small gain nothing from intra-op threads, and on a busy machine thread contention
    # makes them many times slower; run single-threaded and restore the caller's setting.
    prev = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        return _torch_fit1(x, y, F, lam, opts, return_loss)
    finally:
        torch.set_num_threads(prev)


def _torch_fit1(x, y, F, lam: float, opts: Training, return_loss: bool):
    """One training run of the Eq. 2 model (plus the PINN penalty when ``lam > 0``): the single
    implementation behind :func:`regular_dnn` and :func:`pinn_penalty`."""
    import torch

    from odnn_sep.core.nets import MLP

    torch.manual_seed(int(opts.random_state))
    xs = x if x.ndim == 2 else x[:, None]
    # Standardise inputs/outputs so one learning rate suits every dataset; theta is mapped back.
    x_mu, x_sd = xs.mean(0), xs.std(0) + 1e-12
    y_sd = y.std() + 1e-12
    f_sd = F.std(0) + 1e-12
    Xt = torch.as_tensor((xs - x_mu) / x_sd, dtype=torch.float32)
    Yt = torch.as_tensor(y / y_sd, dtype=torch.float32)
    Ft = torch.as_tensor(F / f_sd, dtype=torch.float32)
    net = MLP(in_dim=Xt.shape[1], hidden=opts.hidden, depth=opts.depth)
    t0 = np.zeros(F.shape[1]) if opts.theta_init is None else np.broadcast_to(opts.theta_init, (F.shape[1],))
    theta = torch.tensor(t0 * f_sd / y_sd, dtype=torch.float32, requires_grad=True)
    opt = torch.optim.Adam([*net.parameters(), theta], lr=opts.lr)
    if lam:
        Q, _ = torch.linalg.qr(Ft)  # orthonormal basis of span(F): P_F h = Q Q^T h
    for _ in range(int(opts.epochs)):
        opt.zero_grad()
        h = net(Xt)
        loss = torch.mean((Yt - Ft @ theta - h) ** 2)
        if lam:
            loss = loss + lam * torch.mean((Q @ (Q.T @ h)) ** 2)
        loss.backward()
        opt.step()
    theta_hat = theta.detach().double().numpy() * y_sd / f_sd
    if return_loss:
        with torch.no_grad():
            mse = float(torch.mean((Yt - Ft @ theta - net(Xt)) ** 2)) * y_sd**2
        return theta_hat, mse
    return theta_hat


def regular_dnn(x: ArrayLike, y: ArrayLike, F: ArrayLike, *, hidden: int = 64, depth: int = 3, epochs: int = 1000, lr: float = 3e-3,
                random_state: int = 0, theta_init: ArrayLike | None = None, return_loss: bool = False) -> np.ndarray:
    """Eq. 2: unconstrained MLP ``h(x)`` plus ``F @ theta`` trained jointly by full-batch Adam.

    theta starts at ``theta_init`` (zero by default). Inputs, outputs and columns are standardised
    internally. Because the MLP can absorb the physics (Proposition 1), the theta returned depends
    on ``theta_init``, the seed and the training length, while the training loss stays small.
    Why long (10 parameters): the training options are separate keywords on purpose, the knobs of the
    paper's baseline set-up that the Table 1 recipe states and varies (a table of options; they are
    bundled into a :class:`Training` inside).

    Parameters
    ----------
    x : array_like, shape (n,) or (n, d)
        Sample coordinates fed to the network.
    y : array_like, shape (n,)
        Observations.
    F : array_like, shape (n, p)
        Physics columns.
    hidden, depth, epochs, lr : network width, number of hidden layers, Adam steps and step size.
    random_state : int
        Seed for the network initialisation.
    theta_init : float or array_like, shape (p,), optional
        Starting value of theta (zeros when omitted).
    return_loss : bool
        Also return the final training mean squared error (in units of y squared).

    Returns
    -------
    theta : ndarray, shape (p,)
    mse : float
        Only with ``return_loss=True``.

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-3, 3, 200)
    >>> theta = regular_dnn(x, 0.5 * x**2 * np.sin(5 * x) + np.cos(x), x**2 * np.sin(5 * x), epochs=50)
    >>> theta.shape
    (1,)
    """
    F, y, x = _check(F, y, x)
    opts = Training(hidden, depth, epochs, lr, random_state, theta_init).checked(F.shape[1])
    return _torch_fit(x, y, F, 0.0, opts, return_loss)


def pinn_penalty(x: ArrayLike, y: ArrayLike, F: ArrayLike, *, lam: float = 1.0, hidden: int = 64, depth: int = 3, epochs: int = 1000,
                 lr: float = 3e-3, random_state: int = 0, theta_init: ArrayLike | None = None) -> np.ndarray:
    """PINN-style soft constraint: Eq. 2 plus ``lam * mean((P_F h)**2)``.

    ``P_F`` projects on span(F) (computed on the standardised columns). This is the additive
    regularisation the paper argues against: its result depends on ``lam`` and on training length.
    Why long (10 parameters): keyword-only training options as in :func:`regular_dnn`.

    Parameters
    ----------
    x, y, F : as in :func:`regular_dnn`.
    lam : float
        Penalty weight, > 0.
    hidden, depth, epochs, lr, random_state, theta_init : as in :func:`regular_dnn`.

    Returns
    -------
    theta : ndarray, shape (p,)

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(-3, 3, 200)
    >>> pinn_penalty(x, np.sin(x), np.sin(x), lam=1.0, epochs=50).shape
    (1,)
    """
    F, y, x = _check(F, y, x)
    opts = Training(hidden, depth, epochs, lr, random_state, theta_init).checked(F.shape[1])
    if not (np.isfinite(lam) and lam > 0):
        raise InputError(f"lam must be a finite number > 0; got {lam!r} (use regular_dnn for lam = 0)")
    return _torch_fit(x, y, F, float(lam), opts)


def sindy(F: ArrayLike, y: ArrayLike, *, threshold: float = 0.05, alpha: float = 0.0) -> np.ndarray:
    """pysindy's STLSQ (sequentially thresholded ridge regression) on the columns of F.

    Columns are normalised inside STLSQ so ``threshold`` is relative to unit-norm columns; the
    surviving coefficients are refitted without the ridge term (pysindy's ``unbias``).

    Parameters
    ----------
    F : array_like, shape (n, p)
        Library columns (the physics basis).
    y : array_like, shape (n,)
        Observations (the target SINDy regresses on the library).
    threshold, alpha : float
        STLSQ threshold and ridge weight.

    Returns
    -------
    theta : ndarray, shape (p,)

    Examples
    --------
    >>> import numpy as np
    >>> x = np.linspace(0, 1, 100)
    >>> sindy(np.c_[x, x**2], 3 * x).round(6)
    array([3., 0.])
    """
    F, y = _check(F, y)
    try:
        import pysindy as ps
    except ImportError:  # pragma: no cover - depends on the environment
        raise InputError("sindy() needs pysindy; install it with `pip install pysindy`") from None
    opt = ps.STLSQ(threshold=threshold, alpha=alpha, normalize_columns=True)
    opt.fit(F, y[:, None])
    return np.asarray(opt.coef_, dtype=float).reshape(-1)
