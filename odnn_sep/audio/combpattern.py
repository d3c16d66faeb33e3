"""Lines in the locked comb's own pattern that the first lock tests missed.

The first lock tests take every candidate harmonic on its own, Bonferroni-corrected over all of
them (40 to 200 at audio rates). The current of a phase-cut dimmer or of a rectifier keeps a
regular pattern far up (odd harmonics only, even ones only, or all), each line weak and falling
slowly (1/k or 1/k^2); under speech or music many of them miss that bar by a factor of a few
(p = 1e-5 to 1e-4 where it asks 5e-6) while their neighbours lock, and the lines left in then
hold most of what remains of the hum.

Once the comb has shown its pattern (step and residue of at least ``PATTERN_MIN`` locked lines),
its unlocked lines in that pattern, up to ``REACH`` times the highest locked one, form a second,
much smaller family of hypotheses: each is taken when the smaller of its two lock-test p-values
(the plain test and the test weighted by the content beside the line, lock.py, both against the
same settled track) passes the Bonferroni bar of that family (two tests per line), at the same
level. The error rate over both families is then at most twice the level,
and a note partial, which is not phase-locked, passes neither. The -50 dB floor of the first
tests is kept.
"""
from __future__ import annotations

from math import gcd

PATTERN_MIN = 4     # locked lines that establish the comb's pattern
REACH = 2           # pattern lines tested up to this times the highest locked harmonic


def pattern(ks) -> tuple[int, int] | None:
    """Step and residue of the locked harmonics ``ks`` (every harmonic: ``(1, 0)``; odd ones
    only: ``(2, 1)``; even ones only: ``(2, 0)``), or None for fewer than ``PATTERN_MIN`` lines.

    Parameters
    ----------
    ks : sequence of int
        Locked harmonic numbers.

    Returns
    -------
    (int, int) or None

    Examples
    --------
    >>> pattern([1, 3, 5, 9, 11]), pattern([2, 4, 6, 10]), pattern([1, 2, 3, 5]), pattern([1, 3, 5])
    ((2, 1), (2, 0), (1, 0), None)
    """
    ks = sorted(int(k) for k in ks)
    if len(ks) < PATTERN_MIN:
        return None
    step = 0
    for k in ks[1:]:
        step = gcd(step, k - ks[0])
    return step, ks[0] % step


def candidates(ks, tested) -> list[int]:
    """The lines of ``tested`` in the pattern of the locked ``ks`` that are not locked, up to
    ``REACH`` times the highest locked harmonic (none without a pattern).

    Examples
    --------
    >>> candidates([1, 3, 5, 9], range(1, 30))
    [7, 11, 13, 15, 17]
    """
    pat = pattern(ks)
    if pat is None:
        return []
    step, res = pat
    top = REACH * max(ks)
    return [int(k) for k in sorted(tested) if k not in ks and k <= top and k % step == res]


def pattern_lines(ks, lock: dict, lock_w: dict, *, alpha: float, floor_rel: float) -> list[int]:
    """The unlocked lines of the comb's pattern that pass the second family's test.

    Parameters
    ----------
    ks : sequence of int
        Locked harmonics.
    lock : dict
        Harmonic -> ``(p, lock index, amplitude)`` of every line tested (lockcomb.Comb.lock).
    lock_w : dict
        Harmonic -> p of the weighted lock test (lock.weighted_locked), where it was run: the
        smaller of the two p-values counts, and the Bonferroni count is doubled for it.
    alpha : float
        Significance level.
    floor_rel : float
        A line must reach this share of the strongest locked line's amplitude.

    Returns
    -------
    list of int

    Examples
    --------
    >>> lock = {k: (1e-30, 0.99, 1.0 / k) for k in (1, 3, 5, 9, 11)}
    >>> lock.update({7: (2e-5, 0.8, 0.1), 13: (5e-4, 0.7, 0.07), 2: (1e-5, 0.8, 0.1), 15: (0.2, 0.1, 0.01)})
    >>> pattern_lines([1, 3, 5, 9, 11], lock, {}, alpha=1e-3, floor_rel=3e-3)   # 3 lines, 6 tests
    [7]
    >>> pattern_lines([1, 3, 5, 9, 11], lock, {13: 1e-9}, alpha=1e-3, floor_rel=3e-3)
    [7, 13]
    """
    cand = candidates(ks, lock)
    if not cand:
        return []
    strongest = max((lock[k][2] for k in ks if k in lock), default=0.0)
    n = 2 * len(cand)
    return [int(k) for k in cand
            if min(lock[k][0], lock_w.get(k, 1.0)) * n < alpha and lock[k][2] > floor_rel * strongest]
