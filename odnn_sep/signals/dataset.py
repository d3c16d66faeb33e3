"""The Dataset record every generator returns, and the noise model they share.

SNR convention (all generators): ``snr_db = 10 log10(mean(physics**2) / sigma**2)`` where
``physics`` is the true physics part ``F(phi) theta`` on the samples and the measurement noise is
white Gaussian with standard deviation ``sigma``. The disturbance does not enter the SNR: it is a
signal to be separated, not noise.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from odnn_sep.errors import InputError, check_type


@dataclass(frozen=True)
class Dataset:
    """A synthetic separation problem with known truth.

    ``y == physics + disturbance_true + noise`` holds exactly (to rounding).

    Examples
    --------
    >>> from odnn_sep.signals import figure2
    >>> ds = figure2(random_state=0)
    >>> bool(np.allclose(ds.y, ds.physics + ds.disturbance_true + ds.noise)), ds.targets
    (True, ('theta',))

    Attributes
    ----------
    name : str
        Registry name (see :data:`odnn_sep.signals.GENERATORS`).
    x : ndarray, shape (n,) or (n, d)
        Sample coordinates.
    y : ndarray, shape (n,)
        Observations.
    basis : Basis or ParametricBasis
        The known physics columns (nonlinear parameters start at a rough guess, not the truth).
    disturbance : core disturbance class instance
        A class the true disturbance provably belongs to; pass it to ``Separator``.
    theta_true : dict
        True linear coefficients by basis name, plus true nonlinear parameters phi by name.
    physics, disturbance_true, noise : ndarray, shape (n,)
        The three true parts of ``y``.
    snr_db : float
        Physics-to-noise power ratio (see module docstring); ``inf`` means no noise.
    description : str
        What the case is and why the disturbance class is sound for it.
    targets : tuple of str
        Parameters scored in Table 1 (a subset of ``theta_true``).
    identified : {"point", "set"}
        ``"set"`` for cone classes (Convex, Monotone): theta is only set-identified.
    extras : dict
        Case-specific truth that is not a fitted parameter (e.g. substrate level, growth rate r).
    """

    name: str
    x: np.ndarray
    y: np.ndarray
    basis: object
    disturbance: object
    theta_true: dict
    physics: np.ndarray
    disturbance_true: np.ndarray
    noise: np.ndarray
    snr_db: float
    description: str
    targets: tuple = ()
    identified: str = "point"
    extras: dict = field(default_factory=dict)

    @property
    def theta_vector(self) -> np.ndarray:
        """True linear coefficients in basis column order."""
        return np.array([self.theta_true[k] for k in self.basis.names], dtype=float)

    @property
    def phi_true(self) -> dict:
        """True nonlinear parameters (empty for linear bases)."""
        return {k: self.theta_true[k] for k in self.basis.phi_names}

    @property
    def noise_sigma(self) -> float:
        """Standard deviation of the measurement noise the generator drew (0 without noise)."""
        return noise_sigma(self.physics, self.snr_db)

    def design(self, phi: dict | None = None) -> np.ndarray:
        """Basis columns at the samples, at the true phi unless ``phi`` is given."""
        return self.basis.evaluate(self.x, self.phi_true if phi is None else phi)


def rng_from(random_state) -> np.random.Generator:
    """A numpy Generator from ``None``, a non-negative int or a Generator (returned as is).

    Parameters
    ----------
    random_state : None, int or numpy.random.Generator
        Seed (None: fresh entropy) or a ready generator.

    Returns
    -------
    numpy.random.Generator

    Raises
    ------
    odnn_sep.errors.InputError
        For a negative or non-integer seed.

    Examples
    --------
    >>> float(rng_from(0).uniform()) == float(np.random.default_rng(0).uniform())
    True
    """
    if isinstance(random_state, np.random.Generator):
        return random_state
    if random_state is not None and (not isinstance(random_state, (int, np.integer)) or random_state < 0):
        raise InputError(f"random_state must be None, a non-negative int or a numpy Generator; got {random_state!r}")
    return np.random.default_rng(random_state)


def check_n(n, minimum: int, name: str = "n") -> int:
    """``n`` as an int, or InputError unless it is an integer ``>= minimum``.

    Parameters
    ----------
    n : int
        The value to check.
    minimum : int
        Smallest value accepted.
    name : str, optional
        Option name, for the message.

    Returns
    -------
    int

    Raises
    ------
    odnn_sep.errors.InputError
        For a non-integer (booleans included) or a value below ``minimum``.

    Examples
    --------
    >>> check_n(50, 10)
    50
    >>> check_n(5, 10)
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: n must be an integer >= 10; got 5
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < minimum:
        raise InputError(f"{name} must be an integer >= {minimum}; got {n!r}")
    return int(n)


def check_snr(snr_db) -> float:
    """``snr_db`` as a float (``inf`` allowed: no noise), or InputError.

    Parameters
    ----------
    snr_db : float or str
        Signal-to-noise ratio in dB.

    Returns
    -------
    float

    Raises
    ------
    odnn_sep.errors.InputError
        For a non-number, NaN or ``-inf``.

    Examples
    --------
    >>> check_snr("30"), check_snr(float("inf"))
    (30.0, inf)
    """
    try:
        v = float(snr_db)
    except (TypeError, ValueError):
        raise InputError(f"snr_db must be a number in dB (or inf for no noise); got {snr_db!r}") from None
    if np.isnan(v) or v == -np.inf:
        raise InputError(f"snr_db must be a number in dB (or inf for no noise); got {snr_db!r}")
    return v


def noise_sigma(physics: np.ndarray, snr_db: float) -> float:
    """Standard deviation of the white noise at ``snr_db`` relative to the mean power of ``physics``.

    Parameters
    ----------
    physics : ndarray
        The clean signal.
    snr_db : float
        Signal-to-noise ratio in dB.

    Returns
    -------
    float
        ``sqrt(mean(physics**2) / 10**(snr_db / 10))``.

    Examples
    --------
    >>> noise_sigma(np.ones(10), 20.0)          # 20 dB below unit power
    0.1
    """
    return float(np.sqrt(np.mean(physics**2) / 10 ** (check_snr(snr_db) / 10)))


def add_noise(physics: np.ndarray, snr_db: float, rng: np.random.Generator) -> np.ndarray:
    """White Gaussian noise at ``snr_db`` relative to the mean power of ``physics``.

    Parameters
    ----------
    physics : ndarray
        The clean signal.
    snr_db : float
        Signal-to-noise ratio in dB (``inf``: zeros).
    rng : numpy.random.Generator

    Returns
    -------
    ndarray
        Noise of the shape of ``physics``.

    Examples
    --------
    >>> add_noise(np.ones(3), np.inf, rng_from(0)).tolist()     # inf dB: no noise
    [0.0, 0.0, 0.0]
    """
    if np.isinf(check_snr(snr_db)):
        return np.zeros_like(physics)
    return noise_sigma(physics, snr_db) * rng.standard_normal(physics.shape)


def pick(rng: np.random.Generator, theta, name: str, lo: float, hi: float, signed: bool = False) -> float:
    """Value given by the caller in ``theta`` or drawn uniformly from [lo, hi] (random sign if asked).

    Parameters
    ----------
    rng : numpy.random.Generator
    theta : dict or None
        Values given by the caller.
    name : str
        The parameter.
    lo, hi : float
        Range of the uniform draw.
    signed : bool, optional
        Give the drawn value a random sign.

    Returns
    -------
    float

    Raises
    ------
    odnn_sep.errors.InputError
        For a given value that is not finite.

    Examples
    --------
    >>> pick(rng_from(0), {"a": 2.0}, "a", 0.5, 1.5), 0.5 <= pick(rng_from(0), None, "a", 0.5, 1.5) <= 1.5
    (2.0, True)
    """
    if theta is not None and name in theta:
        v = float(theta[name])
        if not np.isfinite(v):
            raise InputError(f"theta[{name!r}] must be finite; got {theta[name]!r}")
        return v
    v = float(rng.uniform(lo, hi))
    return v * (1 if not signed or rng.random() < 0.5 else -1)


def check_theta(theta, allowed) -> None:
    """InputError unless ``theta`` is None or a dict whose keys are among ``allowed``.

    Parameters
    ----------
    theta : dict or None
        Parameter name -> value.
    allowed : iterable of str
        The generator's parameter names.

    Raises
    ------
    odnn_sep.errors.InputError
        For a non-dict or unknown names.

    Examples
    --------
    >>> check_theta({"a": 1.0}, ("a", "b"))
    >>> check_theta({"c": 1.0}, ("a", "b"))
    Traceback (most recent call last):
    ...
    odnn_sep.errors.InputError: theta has unknown parameter(s) ['c']; allowed: ['a', 'b']
    """
    if theta is None:
        return
    check_type("theta", theta, dict, "a dict of parameter name -> value")
    bad = sorted(set(theta) - set(allowed))
    if bad:
        raise InputError(f"theta has unknown parameter(s) {bad}; allowed: {sorted(allowed)}")


def make(name, x, basis, disturbance, theta_true, physics, g, snr_db, rng, description, *, targets=None,
         identified="point", extras=None, noise=None) -> Dataset:
    """The :class:`Dataset` with ``y = physics + g + noise`` (noise drawn at ``snr_db`` unless given).

    Why long: one argument per field of the record it fills (Dataset has 14 fields); grouping them
    would only rename the fields.

    Parameters
    ----------
    name : str
        Dataset name.
    x : ndarray
        Coordinates, (n,) or (n, d).
    basis : Basis
    disturbance : Disturbance
        The class the true disturbance belongs to.
    theta_true : dict
        True parameters.
    physics, g : (n,) ndarray
        The physics part and the disturbance.
    snr_db : float
        Noise level relative to ``physics``.
    rng : numpy.random.Generator
    description : str
    targets : tuple of str, optional
        Parameters scored (default: the basis names).
    identified : {"point", "set"}, optional
    extras : dict, optional
    noise : ndarray, optional
        Noise to use instead of drawing it.

    Returns
    -------
    Dataset

    Examples
    --------
    >>> from odnn_sep.core import Basis, Even
    >>> x = np.linspace(-1, 1, 5)
    >>> ds = make("demo", x, Basis([lambda x: x], names=["a"]), Even(), {"a": 2.0}, 2 * x, x**2, np.inf,
    ...           rng_from(0), "a line under an even disturbance")
    >>> bool(np.all(ds.y == 2 * x + x**2)), ds.targets
    (True, ('a',))
    """
    if noise is None:
        noise = add_noise(physics, snr_db, rng)
    return Dataset(
        name=name, x=x, y=physics + g + noise, basis=basis, disturbance=disturbance,
        theta_true=dict(theta_true), physics=physics, disturbance_true=g, noise=noise,
        snr_db=float(snr_db), description=description,
        targets=tuple(targets if targets is not None else basis.names), identified=identified,
        extras=dict(extras or {}),
    )
