"""A lone hum line under a louder tone near it: its phase bridged across the tone.

With one line there is nothing else to carry the fundamental's phase. Where a tone 0.3-1.5 Hz away
(a bass note) is louder than the line at the line's frequency, the line's demodulated phase turns with
the tone for as long as it sounds, and the 0.5 s track (finetrack.py) follows it: 0.05-0.25 cycles
off for seconds at a time, which leaves 5-15 dB of hum gain over the whole input (40-50 dB between
the notes). ``finetrack.lone_line_correction`` removes a beat's fast wobble, not a turn that lasts
as long as the note.

What the data say instead: where the tone sounds, the line's scatter about its whole-input mean is
tens of times its scatter elsewhere, so the phase weights of ``finetrack.refine_phase`` drop there.

1. **Held samples**: weights below ``TRUST_RATIO`` times their upper quartile (the quartile is the
   line's level between notes as long as a quarter of the input is free of them).
2. The refinement is run again with the held samples' weights set to zero: the trusted samples'
   phases are then free of the tone (the 0.5 s kernel no longer carries it into them).
3. **Bridges**: every held stretch gets a quadratic in time fitted to the trusted phase on both
   sides, as far out as the stretch is long (at least ``SIDE_S``); at the input's ends, one side,
   twice as far (a ramp's curvature matters there as much as inside).
4. **Checked on the data**: each trusted stretch is held out in turn and bridged from the rest
   (with the stretches beside it, so the check is harder than the real bridges); the RMS error over
   them is the bridges' error ``e``. Where no trusted stretch can be checked so (one trusted stretch
   only: a sweep passing the line in the input's first seconds holds those, and the stretch with
   the held one beside it is the whole input), the trusted stretches are cut into pieces no longer
   than the longest held stretch and the pieces at their ends are held out instead
   (:func:`trusted_pieces`), the worst of them standing for ``e``.
5. The bridged track (the re-run's trusted phase, the bridges across the held stretches) replaces
   the first one only when on at least one held stretch the first track departs from its bridge by
   more than ``DEPART`` times ``e`` and by at least ``MIN_DEPART_CYCLES``: it is then further from the
   bridge than the bridge can be from the hum (where ``e`` comes from pieces, by at least
   ``MIN_DEPART_PIECES``). When no stretch departs (a steady note beside the
   line that does not bend its phase; weights that drop for drums or formants), or where the first
   track keeps a step of the phase outside the held stretches (a splice), the first track stands.

A hum that wanders faster than the bridges reach (the phase not a quadratic over two notes) fails
step 4, and the first track stands: there the data cannot tell the hum's phase under the note.
Chosen on development cases (``recipes/_audio_hosts.py``, the pure-hum bass_near host, seeds 7, 11
and 100-115, and every pure-hum case of seeds 7 and 11; the check on pieces on the swept-sine host's
pure-hum case, seeds 300-331).
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage

TRUST_RATIO = 0.1       # weights below this share of their upper quartile: held (the tone sounds)
MIN_HELD, MAX_HELD = 0.02, 0.85   # held share of the input for which bridges are tried
SIDE_S = 2.0            # trusted phase taken on each side of a held stretch, at least (s)
FAR_S = 30.0            # ... at most (s): farther, a bridge is not tried
MAX_ERROR_CYCLES = 0.02  # bridges checked worse than this (RMS, cycles) are not used
DEPART = 3.0            # a held stretch is bridged when the first track departs this many errors
MIN_DEPART_CYCLES = 0.004   # ... and at least this much (RMS, cycles: the hum left at -32 dB)
MIN_DEPART_PIECES = 0.02    # ... where the check was made on pieces (trusted_pieces): the first track
                            # is left unless it leaves the hum at -18 dB or more there (a bridge that
                            # is better by less moved the amplitude paths' choice of span on sweeps:
                            # 3 of 32 development cases lost 2-8 dB with the bar at 0.004)
MAX_CHECKS = 24         # trusted stretches held out in the check, at most (evenly spread)


def held_samples(w: np.ndarray) -> np.ndarray:
    """Samples whose phase weight is below ``TRUST_RATIO`` of the weights' upper quartile.

    Parameters
    ----------
    w : np.ndarray
        (nd, ...) weights of the phase estimates (summed over the other axes).

    Returns
    -------
    (nd,) bool array

    Examples
    --------
    >>> import numpy as np
    >>> w = np.ones(40); w[10:20] = 0.01
    >>> np.nonzero(held_samples(w))[0].tolist() == list(range(10, 20))
    True
    """
    wt = np.asarray(w, dtype=float).reshape(len(w), -1).sum(axis=1)
    return wt < TRUST_RATIO * float(np.quantile(wt, 0.75))


def bridge(psi_d: np.ndarray, held: np.ndarray, td: np.ndarray, n_min: int, fs_d: float,
           only=None) -> np.ndarray | None:
    """``psi_d`` with every held stretch (or the one ``only`` (start, stop)) replaced by a quadratic
    fitted to the trusted samples around it; None where a stretch has too few trusted samples within
    ``FAR_S``.

    Parameters
    ----------
    psi_d : np.ndarray
        (nd,) phase (cycles) at the decimated times ``td``.
    held : np.ndarray
        (nd,) bool, the held samples.
    td : np.ndarray
        (nd,) times (s).
    n_min : int
        Shortest phase kernel (samples): the trusted samples needed on a side (half of it) or on the
        one side at an end (twice it).
    fs_d : float
        Sample rate of ``psi_d`` (Hz).
    only : tuple of int, optional
        Bridge this stretch only.

    Returns
    -------
    np.ndarray or None

    Examples
    --------
    >>> import numpy as np
    >>> td = np.arange(200) / 10.0; psi = 0.01 * td + 0.002 * td ** 2
    >>> held = np.zeros(200, bool); held[60:90] = True; held[:15] = True
    >>> bad = psi.copy(); bad[held] += 0.3
    >>> bool(np.abs(bridge(bad, held, td, 12, 10.0) - psi).max() < 1e-9)
    True
    """
    nd = len(psi_d)
    out = psi_d.copy()
    side = int(round(SIDE_S * fs_d))
    far = int(round(FAR_S * fs_d))
    if only is not None:
        spans = [only]
    else:
        lab, n = ndimage.label(held)
        spans = [(int(s.start), int(s.stop)) for (s,) in ndimage.find_objects(lab)]
    for a, b in spans:
        end = a == 0 or b == nd
        reach = max(side, b - a) if not end else max(2 * side, 2 * (b - a))
        while True:
            sel = np.r_[max(0, a - reach):a, b:min(nd, b + reach)]
            sel = sel[~held[sel]]
            left, right = int((sel < a).sum()), int((sel >= b).sum())
            enough = left + right >= 2 * n_min if end else min(left, right) >= n_min // 2
            if enough or reach > far:
                break
            reach *= 2
        if not enough:
            return None
        coef = np.polyfit(td[sel] - td[a], psi_d[sel], 2)
        out[a:b] = np.polyval(coef, td[a:b] - td[a])
    return out


def bridge_error(psi_d: np.ndarray, held: np.ndarray, td: np.ndarray, n_min: int, fs_d: float) -> float:
    """RMS error (cycles) of the bridges on the data: each trusted stretch held out in turn, with the
    held stretches beside it, and bridged from the rest; where none can be, the worst of the pieces
    at the ends of the trusted stretches (:func:`trusted_pieces`) instead (inf when none of those
    can be bridged either).

    Parameters
    ----------
    psi_d, held, td, n_min, fs_d
        As in :func:`bridge`.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> td = np.arange(300) / 10.0; held = (td % 6) < 3
    >>> bridge_error(0.01 * td, held, td, 12, 10.0) < 1e-9
    True
    >>> bridge_error(0.02 * np.sin(2 * np.pi * td / 5), held, td, 12, 10.0) > 0.005
    True
    >>> start = td < 5                                    # held at the start only: checked on pieces
    >>> bridge_error(0.01 * td + 0.001 * td ** 2, start, td, 12, 10.0) < 1e-9
    True
    """
    return _checked_error(psi_d, held, td, n_min, fs_d)[0]


def _checked_error(psi_d, held, td, n_min: int, fs_d: float) -> tuple[float, bool]:
    """:func:`bridge_error` and whether it was measured on pieces (:func:`trusted_pieces`)."""
    lab, n = ndimage.label(~held)
    runs = [(int(s.start), int(s.stop)) for (s,) in ndimage.find_objects(lab)]
    sq = _checked(psi_d, held, td, n_min, fs_d, [r for r in runs if r[1] - r[0] >= 3])
    if sq:
        return float(np.sqrt(np.mean(sq))), False
    # no whole trusted stretch could be held out: the same check on the pieces at the ends of
    # them, and the worst of those (two or so checks are too few for a mean to stand for them)
    sq = _checked(psi_d, held, td, n_min, fs_d, trusted_pieces(held, n_min))
    return (float(np.sqrt(np.max(sq))) if sq else float("inf")), True


def trusted_pieces(held: np.ndarray, n_min: int) -> list:
    """The first and the last piece of each trusted stretch cut into pieces of equal length, each at
    most as long as the longest held stretch (or ``n_min`` samples, where that is longer): the check
    of :func:`bridge_error` where no whole trusted stretch can be held out. Those pieces border a
    held stretch or an end of the input, so each is bridged across a held stretch or from one side
    only, as the real bridges are (a piece inside a stretch, bridged from both sides, would make
    the check easier than they are). A stretch already that short is not cut and gives no piece.

    Parameters
    ----------
    held : np.ndarray
        (nd,) bool, the held samples.
    n_min : int
        Shortest phase kernel (samples).

    Returns
    -------
    list of (start, stop)

    Examples
    --------
    >>> held = np.zeros(130, bool); held[:33] = True         # held at the start only
    >>> trusted_pieces(held, 12)
    [(33, 65), (98, 130)]
    >>> held[60:130] = True                                 # the trusted stretch is short
    >>> trusted_pieces(held, 12)
    []
    """
    lab, n = ndimage.label(held)
    longest = max((s.stop - s.start for (s,) in ndimage.find_objects(lab)), default=0)
    size = max(longest, n_min)
    lab, n = ndimage.label(~held)
    pieces = []
    for (s,) in ndimage.find_objects(lab):
        m = int(np.ceil((s.stop - s.start) / size))
        if m >= 2:
            edges = np.linspace(s.start, s.stop, m + 1).round().astype(int)
            pieces += [(int(edges[0]), int(edges[1])), (int(edges[-2]), int(edges[-1]))]
    return pieces


def _checked(psi_d: np.ndarray, held: np.ndarray, td: np.ndarray, n_min: int, fs_d: float, runs) -> list:
    """Mean squared errors (cycles^2) of the trusted stretches ``runs`` (start, stop), each held out
    with the held stretches beside it and bridged from the rest (those that can be bridged)."""
    nd = len(psi_d)
    if len(runs) > MAX_CHECKS:
        runs = [runs[i] for i in np.linspace(0, len(runs) - 1, MAX_CHECKS).round().astype(int)]
    sq = []
    for a, b in runs:
        # the run and the held stretches on either side of it, bridged as one
        lo, hi = a, b
        while lo > 0 and held[lo - 1]:
            lo -= 1
        while hi < nd and held[hi]:
            hi += 1
        hold = held.copy()
        hold[lo:hi] = True
        out = bridge(psi_d, hold, td, n_min, fs_d, only=(lo, hi))
        if out is not None:
            sq.append(float(np.mean((out[a:b] - psi_d[a:b]) ** 2)))
    return sq


def _decimated(x: np.ndarray, nd: int) -> np.ndarray:
    """Chunk-rate values ``x`` (J,) averaged to the ``nd`` decimated samples (``J // nd`` chunks each)."""
    dec = len(x) // nd
    return x[: nd * dec].reshape(nd, dec).mean(axis=1)


def bridged_phase(psi: np.ndarray, w: np.ndarray, rerun, tc: np.ndarray, n_min: int, fs_d: float,
                  steps=()) -> np.ndarray:
    """The lone line's phase ``psi`` (cycles, at the chunk centres ``tc``) bridged across the
    stretches a louder tone holds, where the data show that the first track followed the tone;
    ``psi`` itself otherwise (see the module text).

    Parameters
    ----------
    psi : np.ndarray
        (J,) the first track's phase (``finetrack.refine_phase``).
    w : np.ndarray
        (nd, C, 1) its last round's weights.
    rerun : callable
        ``rerun(gate)`` -> the rounds again, without steps, with each round's weights ``wr`` times
        ``gate(wr)`` (nd,): a tuple whose first item is the phase.
    tc : np.ndarray
        (J,) chunk centres (s).
    n_min : int
        Shortest phase kernel (decimated samples).
    fs_d : float
        Decimated sample rate (Hz).
    steps : sequence of int
        Decimated indices of the phase steps the first track keeps (``phasejumps``,
        ``phasesteps``): bridged over only when a tone holds the line there (a note's onset taken
        for a splice); at any other step the first track stands.

    Returns
    -------
    (J,) array

    Examples
    --------
    >>> import numpy as np
    >>> tc = np.arange(3000) / 100.0; psi = 0.01 * tc
    >>> w = np.ones((300, 1, 1))
    >>> bridged_phase(psi, w, None, tc, 12, 10.0) is psi        # nothing held: the track stands
    True
    """
    nd = len(w)
    held = held_samples(w)
    if not MIN_HELD <= held.mean() <= MAX_HELD:
        return psi
    td = _decimated(tc, nd)
    last = {}

    def gate(wr):
        # each round's own held samples (the first round's weights are along the block track's
        # phase, the later ones along the gated track's)
        last["held"] = held_samples(wr)
        return (~last["held"]).astype(float)

    gated = rerun(gate)[0]
    held = last["held"]
    if not MIN_HELD <= held.mean() <= MAX_HELD or not all(held[q] for q in steps):
        return psi   # a step of the phase where no tone holds the line: a splice, which the first track keeps
    g_d = _decimated(gated, nd)
    new = bridge(g_d, held, td, n_min, fs_d)
    if new is None:
        return psi
    err, on_pieces = _checked_error(g_d, held, td, n_min, fs_d)
    if not err <= MAX_ERROR_CYCLES:
        return psi
    first = _decimated(psi, nd)
    lab, n = ndimage.label(held)
    depart = [float(np.sqrt(np.mean((first[s] - new[s]) ** 2))) for s in ndimage.find_objects(lab)]
    least = MIN_DEPART_PIECES if on_pieces else MIN_DEPART_CYCLES
    if not any(d > max(DEPART * err, least) for d in depart):
        return psi
    return gated + np.interp(tc, td, new - g_d)
