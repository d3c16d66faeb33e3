"""The lines ``denoise`` removes, under one name each: the **tracked comb** (harmonics of the
drifting fundamental) and the **fixed lines** (the named tones and any further steady combs, fitted
at fixed frequencies). :class:`LineSet` holds both and gives every derived list (names, fixed-line
frequencies) in the one column order the fit and the report use: harmonics, tones, further combs.
"""
from __future__ import annotations

from dataclasses import dataclass, field


def as_combs(fixed_lines):
    """``fixed_lines``: frequencies (Hz) or (fundamental, [harmonic numbers]) pairs, in column
    order; yields ``(fundamental, harmonics)`` for each (a lone tone is its own first harmonic).

    Parameters
    ----------
    fixed_lines : iterable
        Floats (tones, Hz) or ``(fundamental, harmonics)`` tuples.

    Yields
    ------
    (float, list of int)

    Examples
    --------
    >>> list(as_combs([1000.0, (60.1, [4, 5])]))
    [(1000.0, [1]), (60.1, [4, 5])]
    """
    for t in fixed_lines:
        if isinstance(t, tuple):
            yield t[0], list(t[1])
        else:
            yield float(t), [1]


@dataclass
class LineSet:
    """Tracked harmonics, named tones (refined, Hz) and further combs (``combs.Comb``).

    Examples
    --------
    >>> from odnn_sep.audio.combs import Comb
    >>> ls = LineSet([1, 2], [1000.0], [Comb(60.1, [4, 5])])
    >>> ls.names
    ['h1', 'h2', 'tone_1000Hz', 'c2_h4', 'c2_h5']
    >>> ls.n_fixed, [round(f, 1) for f in ls.fixed_freqs]
    (3, [1000.0, 240.4, 300.5])
    """

    harmonics: list
    tones: list = field(default_factory=list)
    combs: list = field(default_factory=list)

    @property
    def fixed_lines(self) -> list:
        """Tones, then one ``(fundamental, harmonics)`` pair per further comb (see :func:`as_combs`)."""
        return list(self.tones) + [(c.fundamental_hz, c.harmonics) for c in self.combs]

    @property
    def fixed_freqs(self) -> list[float]:
        """Frequency of every fixed line, in column order."""
        return list(self.tones) + [k * c.fundamental_hz for c in self.combs for k in c.harmonics]

    @property
    def n_fixed(self) -> int:
        return len(self.tones) + sum(len(c.harmonics) for c in self.combs)

    @property
    def names(self) -> list[str]:
        return ([f"h{k}" for k in self.harmonics] + [f"tone_{t:g}Hz" for t in self.tones]
                + [f"c{i + 2}_h{k}" for i, c in enumerate(self.combs) for k in c.harmonics])
