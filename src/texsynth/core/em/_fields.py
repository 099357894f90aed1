"""Neighbourhoods in local frames: the orientation and magnification fields' term of the EM steps.

The M-step reads each output neighbourhood on a grid turned and scaled around its centre; the E-step adds
the matched exemplar neighbourhood back at the same positions with the same bilinear weights (the adjoint
of the sampling). The frames are those of Zhang et al. 2003 (:func:`texsynth.core.fields.frames`).
"""

from __future__ import annotations

import numpy as np

from ..fields import frames, sample, scatter, taps
from ._patches import BLOCK_VALUES

__all__ = ["WarpedPatches"]


# Fields: the bilinear taps of a stage's rotated neighbourhoods are kept while they take at most this
# many bytes (256^2 outputs: about 80 MB), else computed at every use
_WARP_CACHE_BYTES = 2**28


class WarpedPatches:
    """The rotated and scaled neighbourhoods ``x_p`` of one stage (orientation and magnification fields).

    Neighbourhood ``p`` is read on the grid ``p + A(p) d``, ``A = S R(theta)``
    (:func:`texsynth.core.fields.frames`, as in Zhang et al. 2003), ``d`` the
    offsets of a ``w x w`` patch from its centre pixel ``w // 2``: the
    bilinear samples of the output there are the neighbourhood compared
    with the exemplar's plain ``z_p`` in the M-step, and the E-step adds the
    values of ``z_p`` back at the same positions with the same bilinear
    weights (:func:`texsynth.core.fields.splat`, the adjoint of the
    sampling). So a ``z_p`` appears in the output turned by ``theta(p)`` and
    magnified by ``S(p)``.
    """

    def __init__(self, centers, patch_size, orientation, magnification, shape, mode):
        self.a, self.inverse = frames(orientation[centers[:, 0], centers[:, 1]],
                                      magnification[centers[:, 0], centers[:, 1]])
        i = np.arange(patch_size, dtype=np.float64) - patch_size // 2
        self.d = np.stack(np.meshgrid(i, i, indexing="ij"), -1).reshape(-1, 2)
        self.centers, self.w, self.shape, self.wrap = centers, patch_size, tuple(shape), mode == "wrap"
        self.row = np.full(self.shape, -1, np.int64)  # centre -> its row in ``centers``
        self.row[centers[:, 0], centers[:, 1]] = np.arange(len(centers))
        self.cache = None  # the taps of every sample, computed once per stage where they fit the budget
        if len(centers) * patch_size * patch_size * 4 * 16 <= _WARP_CACHE_BYTES:
            self.cache = self._taps(centers)

    def _taps(self, at):
        """Flat pixel indices and bilinear weights ``(n, w * w, 4)`` of the samples of the neighbourhoods at ``at``."""
        if self.cache is not None:
            rows = self.row[at[:, 0], at[:, 1]]
            return self.cache[0][rows], self.cache[1][rows]
        return taps(self.positions(at), self.shape[0], self.shape[1], self.wrap)

    def positions(self, at):
        """``(n, w * w, 2)``: where the neighbourhoods centred at ``at`` (centres of the stage) read the output."""
        rows = self.row[at[:, 0], at[:, 1]]
        a, c, (dr, dc) = self.a[rows, :, :, None], self.centers[rows], self.d.T
        return np.stack([c[:, :1] + a[:, 0, 0] * dr + a[:, 0, 1] * dc,
                         c[:, 1:] + a[:, 1, 0] * dr + a[:, 1, 1] * dc], -1)

    def extract(self, x, at):
        """The neighbourhoods ``(n, w, w, C)`` of ``x`` centred at ``at``, bilinear samples in their frames
        (a few thousand neighbourhoods at a time: the taps take eight times the samples' memory)."""
        out = np.empty((len(at), self.w, self.w, x.shape[-1]), x.dtype)
        step = max(1, BLOCK_VALUES // out[0].size)
        for a in range(0, len(at), step):
            part = slice(a, a + step)
            out[part] = sample(x, *self._taps(at[part]))[0].reshape(out[part].shape)
        return out

    def add(self, sums, patches, at, patch_weights, pixel_weights):
        """Add ``patches`` ``(n, w, w, C)`` centred at ``at`` into ``sums = [values, weights]``."""
        n, c = len(at), patches.shape[-1]
        weights = np.asarray(patch_weights, np.float64)[:, None] * pixel_weights.reshape(1, -1)
        index, tap = self._taps(at)
        v, t = scatter(patches.reshape(n, -1, c), index, tap * weights[..., None], self.shape)
        sums[0] += v
        sums[1] += t
