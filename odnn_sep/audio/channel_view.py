"""One channel of an audio source, read as a source of its own (the per-channel retry of
lockcomb.py tests a channel alone without a copy of the input)."""
from __future__ import annotations


class ChannelView:
    """Channel ``channel`` of ``source`` (an ArraySource or FileSource) as a mono source.

    Parameters
    ----------
    source : ArraySource or FileSource
        The input; not closed by :meth:`close` (views from :meth:`reopen` close their own copy).
    channel : int
        Index of the channel.

    Examples
    --------
    >>> import numpy as np
    >>> from odnn_sep.audio.io import ArraySource
    >>> v = ChannelView(ArraySource(np.arange(8.0).reshape(4, 2), 8000), 1)
    >>> v.frames, v.channels, v.read(1, 2).ravel().tolist()
    (4, 1, [3.0, 5.0])
    """

    def __init__(self, source, channel: int, *, owns: bool = False):
        self.source, self.channel, self._owns = source, int(channel), owns
        self.sr, self.frames, self.channels, self.mono = source.sr, source.frames, 1, True
        self.name = f"{source.name} (channel {self.channel})"

    def read(self, start: int, n: int):
        return self.source.read(start, n)[:, self.channel: self.channel + 1]

    def reopen(self) -> ChannelView:
        other = self.source.reopen()
        return ChannelView(other, self.channel, owns=other is not self.source)

    def close(self):
        if self._owns:
            self.source.close()
