"""How an input is cut into fit blocks: one :class:`BlockPlan` (block length, hop, count, windows)
shared by the tracker, the block-length choice and the block fit, and the one sin^2 window.

Blocks are ``2 hop`` samples long and centred at ``b hop`` (b = 0 .. count - 1), so they overlap
by half, the first and last are cut by the signal's ends, and their sin^2 cross-fade windows sum
to one.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


def sin2_window(pos, length) -> np.ndarray:
    """``sin^2(pi pos / length)``: the cross-fade and fit window at positions ``pos`` (samples or
    chunk times) of a window ``length`` long (a Hann window over ``[0, length]``).

    Parameters
    ----------
    pos : array-like
        Positions, in the units of ``length``.
    length : float
        Window length.

    Returns
    -------
    float array like ``pos``

    Examples
    --------
    >>> sin2_window(np.arange(4) + 0.5, 4).round(3).tolist()
    [0.146, 0.854, 0.854, 0.146]
    """
    return np.sin(np.pi * pos / length) ** 2


def hop_samples(block_s: float, sr) -> int:
    """Hop (half a block) in samples for blocks of ``block_s`` seconds.

    Parameters
    ----------
    block_s : float
        Block length (s).
    sr : int
        Sample rate (Hz).

    Returns
    -------
    int
        ``round(block_s sr / 2)``, at least 1.

    Examples
    --------
    >>> hop_samples(8.0, 8000), hop_samples(0.0001, 8000)
    (32000, 1)
    """
    return max(1, int(round(block_s * sr / 2)))


@dataclass(frozen=True)
class BlockPlan:
    """Blocks of ``length = 2 hop`` samples centred at ``b hop`` over ``n_frames`` samples.

    Examples
    --------
    >>> p = BlockPlan.from_block_s(8.0, 1000, 20000)
    >>> p.hop, p.length, p.count, p.block_s
    (4000, 8000, 6, 8.0)
    """

    sr: int
    n_frames: int
    hop: int

    @classmethod
    def from_block_s(cls, block_s: float, sr, n_frames: int) -> BlockPlan:
        return cls(sr=sr, n_frames=int(n_frames), hop=hop_samples(block_s, sr))

    @property
    def length(self) -> int:
        return 2 * self.hop

    @property
    def count(self) -> int:
        """Blocks needed to cover the input (the first and last reach past its ends)."""
        return (self.n_frames - 1) // self.hop + 2

    @property
    def block_s(self) -> float:
        return 2 * self.hop / self.sr

    @property
    def centres_s(self) -> np.ndarray:
        """Block centres (s)."""
        return np.arange(self.count) * self.hop / self.sr

    def window(self) -> np.ndarray:
        """The sin^2 window of a full block at sample midpoints (sums to one across blocks)."""
        return sin2_window(np.arange(self.length) + 0.5, self.length)

    def cut_window(self, start: int, n: int) -> np.ndarray:
        """The full block's window over its samples ``start .. start + n`` (counted from the
        block's first sample): the visible part of a block cut by the signal's ends."""
        return sin2_window(np.arange(start, start + n) + 0.5, self.length)
