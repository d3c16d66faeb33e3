"""Former name of :mod:`odnn_sep.signals.dataset`; kept so that imports written before the rename work."""
from odnn_sep.signals.dataset import (
    Dataset,
    add_noise,
    check_n,
    check_snr,
    check_theta,
    make,
    noise_sigma,
    pick,
    rng_from,
)

__all__ = ["Dataset", "add_noise", "check_n", "check_snr", "check_theta", "make", "noise_sigma", "pick", "rng_from"]
