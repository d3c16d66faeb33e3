"""Long audio for the hum preset: keep the band the hum model and its effects live in, at a lower rate.

A 60 s, 16 kHz recording has about a million samples, while the hum model, its missing harmonics
(up to ``harmonics + 6``) and the frequency drift live below ``(harmonics + 7) f0``. A zero-phase
low-pass and decimation to about 2.5 times that band keep every line the effects are tested for,
so every fit runs on 10-30 times fewer samples.
"""
from __future__ import annotations

import numpy as np

MAX_SAMPLES = 40_000


def reduce_rate(model, t, y, aux):
    """Return (t, y, aux, note): decimated when the hum record is long, else unchanged (note None).

    Parameters
    ----------
    model : Model
        The model; only the ``hum`` family is decimated.
    t, y : ndarray
        Sample times (s) and samples.
    aux : dict or None
        Other channels, decimated alike.

    Returns
    -------
    t, y : ndarray
        The (possibly decimated) record.
    aux : dict
        The (possibly decimated) other channels.
    note : str or None
        What was done, in words; None when the record is unchanged.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.mismatch.model import make_model
    >>> t = np.arange(48000) / 16000.0
    >>> t2, y2, aux2, note = reduce_rate(make_model("hum"), t, np.cos(2 * np.pi * 50 * t), {})
    >>> len(y2), note.split(";")[0]
    (3200, 'long record: analysed at 1067 Hz (low-pass and decimation by 15)')
    >>> reduce_rate(make_model("cooling"), t[:10], t[:10], None)[3] is None
    True
    """
    if model.family != "hum" or np.ndim(t) != 1 or len(y) <= MAX_SAMPLES or getattr(model.preset, "baseband", False):
        return t, y, aux, None
    fs = 1.0 / float(np.median(np.diff(t)))
    f_top = (int(model.start.get("harmonics", 1)) + 7) * float(model.start.get("f0", 60.0)) * 1.02
    q = int(fs // (2.5 * f_top))
    if q < 2:
        return t, y, aux, None
    from scipy.signal import decimate  # on use: the package is imported by every subcommand

    def down(a):
        return decimate(np.asarray(a, float), q, ftype="fir", zero_phase=True)

    y2 = down(y)
    t2 = t[::q][: len(y2)]
    aux2 = {k: down(v)[: len(y2)] for k, v in (aux or {}).items()}
    note = (f"long record: analysed at {fs / q:.0f} Hz (low-pass and decimation by {q}); every line below "
            f"{f_top:.0f} Hz, where the hum model and its effects live, is kept")
    return t2, y2, aux2, note
