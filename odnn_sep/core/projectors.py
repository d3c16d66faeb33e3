"""Projectors of the shipped subspace classes that never form a basis matrix.

Reflections average over orbits of index permutations (``Even``), whole-step periods average over
labels (``Periodic``), bands mask DFT bins (``Band``). Each is an exact orthogonal projector with
the :class:`~odnn_sep.core.projection.BaseProjector` interface.
"""
from __future__ import annotations

from typing import Any

import numpy as np

from odnn_sep.core.projection import BaseProjector

__all__ = ["OrbitProjector", "LabelProjector", "FFTProjector"]


class OrbitProjector(BaseProjector):
    """Average over the orbits of a group of index permutations (reflections).

    Examples
    --------
    >>> import numpy as np
    >>> P = OrbitProjector([np.arange(4), np.arange(4)[::-1]])       # mirror symmetry
    >>> P.rank, P.project(np.array([1.0, 2.0, 4.0, 8.0])).tolist()
    (2, [4.5, 3.0, 3.0, 4.5])
    """

    def __init__(self, perms: list[np.ndarray]):
        self.perms = perms
        n = perms[0].size
        # number of orbits = rank of the averaging projector
        self.rank = int(round(sum(float((p == np.arange(n)).sum()) for p in perms) / len(perms)))

    def project(self, v: np.ndarray) -> np.ndarray:
        return sum(v[p] for p in self.perms) / len(self.perms)

    def project_torch(self, v: Any) -> Any:
        import torch
        return sum(v[torch.as_tensor(p)] for p in self.perms) / len(self.perms)


class LabelProjector(BaseProjector):
    """Mean over samples that share a label (e.g. the same phase of a period).

    Examples
    --------
    >>> import numpy as np
    >>> LabelProjector(np.array([0, 1, 0, 1])).project(np.array([1.0, 2.0, 3.0, 4.0])).tolist()
    [2.0, 3.0, 2.0, 3.0]
    """

    def __init__(self, labels: np.ndarray):
        self.labels = labels
        self.counts = np.bincount(labels).astype(float)
        self.rank = int((self.counts > 0).sum())

    def project(self, v: np.ndarray) -> np.ndarray:
        v = np.asarray(v)
        if v.ndim == 1:
            return (np.bincount(self.labels, weights=v, minlength=self.counts.size) / np.maximum(self.counts, 1))[self.labels]
        out = np.empty_like(v, dtype=float)
        for k in range(v.shape[1]):
            out[:, k] = self.project(v[:, k])
        return out

    def project_torch(self, v: Any) -> Any:
        import torch
        lab = torch.as_tensor(self.labels)
        sums = torch.zeros(self.counts.size, dtype=v.dtype).index_add(0, lab, v)
        return (sums / torch.as_tensor(np.maximum(self.counts, 1), dtype=v.dtype))[lab]


class FFTProjector(BaseProjector):
    """Keep the DFT bins where ``mask`` is true (band-limited functions on a uniform grid).

    Examples
    --------
    >>> import numpy as np
    >>> FFTProjector(4, np.array([True, False, False])).project(np.array([1.0, 2.0, 3.0, 4.0])).tolist()
    [2.5, 2.5, 2.5, 2.5]
    """

    def __init__(self, n: int, mask: np.ndarray):
        self.n = n
        self.mask = mask.astype(float)
        nyq = (n % 2 == 0)
        weights = np.full(mask.size, 2)
        weights[0] = 1
        if nyq:
            weights[-1] = 1
        self.rank = int((weights * mask).sum())

    def project(self, v: np.ndarray) -> np.ndarray:
        v = np.asarray(v, dtype=float)
        m = self.mask if v.ndim == 1 else self.mask[:, None]
        return np.fft.irfft(np.fft.rfft(v, axis=0) * m, n=self.n, axis=0)

    def project_torch(self, v: Any) -> Any:
        import torch
        m = torch.as_tensor(self.mask, dtype=v.dtype)
        return torch.fft.irfft(torch.fft.rfft(v) * m, n=self.n)
