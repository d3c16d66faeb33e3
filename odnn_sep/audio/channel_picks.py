"""Channel picks as MNE reads them: names, indices, channel types, or None (the data channels).

Written here rather than through MNE's private ``_picks_to_idx`` so that arrays (no MNE) and Raw
objects share one rule; the test suite checks it against MNE's on a Raw.
"""
from __future__ import annotations

import numpy as np

from odnn_sep.errors import InputError

# MNE's data channel types (its _DATA_CH_TYPES_SPLIT): what picks=None and "data" mean
DATA_TYPES = ("mag", "grad", "eeg", "csd", "seeg", "ecog", "dbs", "hbo", "hbr", "fnirs_cw_amplitude",
              "fnirs_fd_ac_amplitude", "fnirs_fd_phase", "fnirs_od", "fnirs_td_gated_amplitude",
              "fnirs_td_moments_intensity", "fnirs_td_moments_mean", "fnirs_td_moments_variance")
GROUPS = {"data": DATA_TYPES, "meg": ("mag", "grad"), "fnirs": tuple(t for t in DATA_TYPES if "fnirs" in t or
                                                                       t in ("hbo", "hbr"))}


def resolve_picks(picks, n_channels: int, ch_names=None, ch_types=None) -> np.ndarray:
    """Sorted, unique channel indices selected by ``picks``.

    Parameters
    ----------
    picks : None, str, int, slice, sequence of str/int, or boolean mask
        As in MNE: channel names, indices, channel types (``'eeg'``, ``'mag'``, ``'grad'``,
        ``'meg'``, ``'data'``, ``'all'``). ``None`` is every data channel of a Raw and every channel
        of an array.
    n_channels : int
    ch_names, ch_types : list of str, optional
        Names and types of the channels (a Raw's); arrays have neither.

    Returns
    -------
    ndarray of int

    Examples
    --------
    >>> resolve_picks([2, 0], 4).tolist()
    [0, 2]
    >>> resolve_picks("eeg", 3, ["Fz", "Cz", "STI"], ["eeg", "eeg", "stim"]).tolist()
    [0, 1]
    """
    if picks is None:
        if ch_types is None:
            return np.arange(n_channels)
        return _nonempty(np.flatnonzero([t in DATA_TYPES for t in ch_types]), "None (the data channels)",
                         ch_types)
    if isinstance(picks, slice):
        return _nonempty(np.arange(n_channels)[picks], picks, ch_types)
    arr = np.asarray(picks)
    if arr.dtype == bool:
        if arr.shape != (n_channels,):
            raise InputError(f"picks as a boolean mask must have one entry per channel ({n_channels}); "
                             f"got shape {arr.shape}")
        return _nonempty(np.flatnonzero(arr), "a mask", ch_types)
    items = [picks] if isinstance(picks, (str, int, np.integer)) else list(np.ravel(np.asarray(picks, object)))
    out = []
    for item in items:
        out.extend(_one_pick(item, n_channels, ch_names, ch_types))
    return _nonempty(np.unique(np.asarray(out, dtype=int)), picks, ch_types)


def _one_pick(item, n_channels, ch_names, ch_types) -> list[int]:
    if isinstance(item, (int, np.integer)) and not isinstance(item, bool):
        i = int(item)
        if not -n_channels <= i < n_channels:
            raise InputError(f"picks index {i} is out of range for {n_channels} channel(s); "
                             f"use 0..{n_channels - 1}")
        return [i % n_channels]
    if not isinstance(item, str):
        raise InputError(f"picks must hold channel names, indices or types; got {type(item).__name__} ({item!r})")
    if ch_names is not None and item in ch_names:
        return [list(ch_names).index(item)]
    if item == "all":
        return list(range(n_channels))
    if ch_types is None:
        raise InputError(f"picks {item!r}: an array has no channel names or types; pick channels by index "
                         f"(0..{n_channels - 1}), or pass an MNE Raw")
    wanted = GROUPS.get(item, (item,))
    hits = [i for i, t in enumerate(ch_types) if t in wanted]
    if not hits:
        names = ", ".join(list(ch_names or [])[:5])
        kinds = ", ".join(sorted(set(ch_types)))
        raise InputError(f"picks {item!r} is neither a channel name (e.g. {names}) nor a channel type present "
                         f"({kinds}); check the spelling or use raw.ch_names")
    return hits


def _nonempty(idx, picks, ch_types) -> np.ndarray:
    if idx.size == 0:
        kinds = f" (channel types present: {', '.join(sorted(set(ch_types)))})" if ch_types else ""
        raise InputError(f"picks={picks!r} selects no channel{kinds}; pick at least one channel")
    return idx
