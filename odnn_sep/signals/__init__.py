"""Synthetic datasets with known truth for every case in the paper (sections 3.2, 4.5, App. C).

Each generator is seedable (``random_state``), draws random true parameters unless given in
``theta``, adds white Gaussian measurement noise at ``snr_db`` relative to the *physics* power
(``10 log10(mean(physics**2) / sigma**2)``) and returns a :class:`Dataset` whose ``disturbance``
is a core class the true disturbance provably belongs to, ready for
``Separator(ds.basis, disturbance=ds.disturbance).fit(ds.x, ds.y)``.

Examples
--------
>>> from odnn_sep.signals import make_dataset
>>> ds = make_dataset("figure2", theta={"theta": 0.5}, random_state=0)
>>> ds.theta_true
{'theta': 0.5}
"""
from odnn_sep.errors import InputError
from odnn_sep.signals._base import Dataset
from odnn_sep.signals.explicit import explicit_1d, explicit_2d
from odnn_sep.signals.implicit import (
    figure2,
    implicit_convex,
    implicit_monotone,
    implicit_periodic,
    implicit_symmetric,
)
from odnn_sep.signals.physical import aiba_edwards_mu, biology, heat2d, oscillator, pendulum, population

#: name -> generator, in Table 1 order.
GENERATORS = {
    "explicit_1d": explicit_1d,
    "explicit_2d": explicit_2d,
    "implicit_convex": implicit_convex,
    "implicit_periodic": implicit_periodic,
    "implicit_symmetric": implicit_symmetric,
    "implicit_monotone": implicit_monotone,
    "figure2": figure2,
    "pendulum": pendulum,
    "biology": biology,
    "oscillator": oscillator,
    "population": population,
    "heat2d": heat2d,
}


def make_dataset(name: str, **kwargs) -> Dataset:
    """Build the dataset called ``name`` (a key of :data:`GENERATORS`) with the generator's options."""
    if name not in GENERATORS:
        raise InputError(f"unknown dataset {name!r}; choose one of {', '.join(GENERATORS)}")
    return GENERATORS[name](**kwargs)


__all__ = ["Dataset", "GENERATORS", "make_dataset", "explicit_1d", "explicit_2d", "implicit_convex",
           "implicit_periodic", "implicit_symmetric", "implicit_monotone", "figure2", "pendulum", "biology",
           "oscillator", "population", "heat2d", "aiba_edwards_mu"]
