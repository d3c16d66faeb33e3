"""Synthetic datasets with known truth for every case in the paper (sections 3.2, 4.5, App. C).

Each generator is seedable (``random_state``), draws random true parameters unless given in
``theta``, adds white Gaussian measurement noise at ``snr_db`` relative to the *physics* power
(``10 log10(mean(physics**2) / sigma**2)``) and returns a :class:`Dataset` whose ``disturbance``
is a core class the true disturbance provably belongs to, ready for
``Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y)``.

Attributes are loaded lazily so that ``odnn_sep.signals.command`` (imported by ``odnn-sep --help``)
does not pull in numpy/scipy.

Examples
--------
>>> from odnn_sep.signals import make_dataset
>>> ds = make_dataset("figure2", theta={"theta": 0.5}, random_state=0)
>>> ds.theta_true
{'theta': 0.5}
"""
import importlib

_WHERE = {
    "Dataset": "dataset",
    "explicit_1d": "explicit", "explicit_2d": "explicit",
    "implicit_convex": "implicit", "implicit_periodic": "implicit", "implicit_symmetric": "implicit",
    "implicit_monotone": "implicit", "figure2": "implicit",
    "pendulum": "physical", "biology": "physical", "oscillator": "physical", "population": "physical",
    "heat2d": "physical", "aiba_edwards_mu": "physical",
    "power_grid": "power_grid", "humanoid": "humanoid",
}

#: Dataset names in Table 1 order (``GENERATORS`` maps them to their functions).
NAMES = ("explicit_1d", "explicit_2d", "implicit_convex", "implicit_periodic", "implicit_symmetric",
         "implicit_monotone", "figure2", "pendulum", "biology", "oscillator", "population", "heat2d")


#: Simulated engineering systems (optional extras: ``grid`` = pandapower, ``robotics`` = gymnasium[mujoco]).
#: They return richer records than :class:`Dataset` (a grid has one problem per bus equation).
SYSTEMS = ("power_grid", "humanoid")


def __getattr__(name):
    if name in _WHERE:
        return getattr(importlib.import_module(f"odnn_sep.signals.{_WHERE[name]}"), name)
    if name == "GENERATORS":
        return {n: __getattr__(n) for n in NAMES}
    raise AttributeError(f"module 'odnn_sep.signals' has no attribute {name!r}")


def __dir__():
    # the lazy names too: dir() and an editor's completion listed only NAMES, SYSTEMS and make_dataset
    return sorted(set(globals()) | set(__all__))


def make_dataset(name: str, **kwargs):
    """Build the dataset called ``name`` (one of :data:`NAMES` or :data:`SYSTEMS`) with the generator's options.

    Parameters
    ----------
    name : str
        The dataset, e.g. ``"figure2"``, ``"explicit_1d"`` or ``"power_grid"``.
    **kwargs
        Options of its generator (``random_state``, ``snr_db``, ``n``, ...).

    Returns
    -------
    Dataset or GridDataset or HumanoidDataset
        Data, basis, disturbance class and the truth.

    Raises
    ------
    odnn_sep.errors.InputError
        For an unknown ``name``.

    Examples
    --------
    >>> ds = make_dataset("explicit_1d", random_state=3)
    >>> ds.name, ds.identified, type(ds.disturbance).__name__
    ('explicit_1d', 'point', 'Band')
    """
    from odnn_sep.errors import check_option

    check_option("dataset", name, NAMES + SYSTEMS)
    return __getattr__(name)(**kwargs)


__all__ = ["Dataset", "GENERATORS", "NAMES", "SYSTEMS", "make_dataset", *NAMES, *SYSTEMS, "aiba_edwards_mu"]
