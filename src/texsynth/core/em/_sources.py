"""Where each output pixel came from: the correspondence of an EM synthesis with its exemplar.

:func:`dominant_sources` gives the source-coordinate map (``docs/conventions.md``) of the final matches,
:func:`source_map` the dense correspondence of a grid of matches, :func:`carried_field` the last stage's
matches carried to the next stage's grid (Section 3.2's up-sampling).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..fields import taps
from ..neighborhood import grid_axes

__all__ = ["source_map", "dominant_sources", "carried_field", "extend_nearest"]


def carried_field(record, level, centers):
    """The last stage's ``z_p`` (of a :class:`Record`) carried to ``centers`` at ``level``: each centre's exemplar
    position as
    the nearest old centre's source plus the offset to it (Section 3.2's up-sampling, for the field)."""
    prev = record.stages[-1]
    dense = source_map(record.centers, record.sources, prev.shape)
    f = 2 ** (prev.level - level)
    pos = np.minimum(centers // f, np.asarray(prev.shape) - 1)
    return np.rint(dense[pos[:, 0], pos[:, 1]] * f + (centers - pos * f)).astype(np.int64)


def source_map(centers, sources, shape):
    """Dense correspondence of a frame: exemplar position of every pixel, from the
    ``z_p`` whose centre is nearest (``sources + (q - centre)``). ``centers``: a row-major grid, or a
    part of one (hard constraints: :func:`touching_free`)."""
    if grid_axes(centers[:, 0], centers[:, 1]) is None:  # a part of a grid: the nearest centre by distance
        at = np.zeros(tuple(shape) + (2,), np.float64)
        defined = np.zeros(tuple(shape), bool)
        at[centers[:, 0], centers[:, 1]], defined[centers[:, 0], centers[:, 1]] = sources, True
        return extend_nearest(at, defined)
    q = np.stack(np.meshgrid(np.arange(shape[0]), np.arange(shape[1]), indexing="ij"), axis=-1)
    near = []
    for axis, length in enumerate(shape):
        grid = np.unique(centers[:, axis])
        pos = np.arange(length)
        k = np.clip(np.searchsorted(grid, pos), 1, len(grid) - 1)
        near.append(np.where(pos - grid[k - 1] <= grid[k] - pos, k - 1, k) if len(grid) > 1 else np.zeros_like(pos))
    k = near[0][:, None] * len(np.unique(centers[:, 1])) + near[1][None, :]
    return (sources[k] + q - centers[k]).astype(np.float64)


def dominant_sources(exemplar, centers, matches, patch_weights, shape, mode, warp=None):
    """``(H, W, 2)``: at every pixel, the exemplar pixel of the ``z_p`` of largest ``ω_p g(x - p)``.

    For one offset inside the neighbourhood, distinct centres give distinct pixels, so the largest
    weight is kept by plain assignment, offset by offset. With fields (:class:`WarpedPatches`) the weight is
    ``ω_p g(d)`` times the bilinear weight of the sample on the pixel. A pixel that no
    neighbourhood covers (hard constraints, away from the free pixels: :func:`touching_free`) takes
    the source of the nearest covered pixel, offset by the distance to it and kept inside the
    exemplar, so the map stays a copy map.
    """
    if warp is not None:
        return exemplar.to_exemplar(_dominant_warped(exemplar, matches, patch_weights, shape, warp))
    out, best = _dominant_grid(exemplar, centers, matches, patch_weights, shape, mode)
    out = exemplar.to_exemplar(out)  # augmented copies: the exemplar pixel each copied pixel shows
    covered = best > -np.inf
    if covered.all() or not covered.any():
        return out
    return np.clip(extend_nearest(out, covered), 0, np.asarray(exemplar.original.shape[:2]) - 1)  # covered: unchanged


def extend_nearest(positions, defined):
    """``positions`` ``(H, W, 2)`` where ``defined``; elsewhere the nearest defined pixel's, moved by the
    offset to it (a map that continues its nearest copy)."""
    near = ndimage.distance_transform_edt(~defined, return_distances=False, return_indices=True)
    return positions[near[0], near[1]] + np.moveaxis(np.indices(defined.shape) - near, 0, -1)


def _dominant_grid(ex, centers, zidx, omega, shape, mode):
    """:func:`dominant_sources` of plain neighbourhoods: the map and the largest weight at every pixel
    (-inf where no neighbourhood reaches)."""
    w = ex.size
    corner_out = centers - w // 2  # the E-step's patch placement (PatchSum: centred at the centre)
    corner_ex = ex.corner[zidx]
    best = np.full(tuple(shape), -np.inf)
    out = np.zeros(tuple(shape) + (2,), np.int64)
    for i in range(w):
        for j in range(w):
            r, c = corner_out[:, 0] + i, corner_out[:, 1] + j
            if mode == "wrap":
                r, c = r % shape[0], c % shape[1]
            else:
                keep = (r >= 0) & (r < shape[0]) & (c >= 0) & (c < shape[1])
                r, c = r[keep], c[keep]
            value = (omega * ex.g[i, j]) if mode == "wrap" else (omega * ex.g[i, j])[keep]
            src = corner_ex + (i, j) if mode == "wrap" else (corner_ex + (i, j))[keep]
            better = value > best[r, c]
            best[r[better], c[better]] = value[better]
            out[r[better], c[better]] = src[better]
    return out, best


def _dominant_warped(ex, zidx, omega, shape, warp):
    """:func:`dominant_sources` of rotated, scaled neighbourhoods: each sample ``p + A(p) d`` gives its
    exemplar pixel ``z_p(d)`` to its four bilinear taps, weighted ``ω_p g(d)`` times the tap's weight."""
    w = ex.size
    corner_ex = ex.corner[zidx]
    best = np.full(shape[0] * shape[1], -np.inf)
    out = np.zeros((shape[0] * shape[1], 2), np.int64)
    for k, d in enumerate(warp.d):
        index, tap = taps(warp.centers + warp.a @ d, shape[0], shape[1], warp.wrap)
        value = ((omega * ex.g.flat[k])[:, None] * tap).reshape(-1)
        src = np.repeat(corner_ex + divmod(k, w), 4, axis=0)
        order = np.argsort(value, kind="stable")  # ascending: of repeated pixels the largest is assigned last
        index, value, src = index.reshape(-1)[order], value[order], src[order]
        better = value > best[index]
        best[index[better]] = value[better]
        out[index[better]] = src[better]
    return out.reshape(tuple(shape) + (2,))
