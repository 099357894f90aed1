"""k-coherent candidates in Wei-Levoy synthesis (Ashikhmin 2001; Tong et al. 2002): ``candidates="k-coherent"``.

Ashikhmin [1]_ observed that in natural textures a pixel's best match often
continues the copy its neighbours were made from: if the neighbour ``p + d``
was copied from exemplar position ``s(p + d)``, then ``s(p + d) - d`` is a
candidate for ``p``. Comparing each pixel only with these few candidates,
instead of every exemplar neighbourhood, makes copies run on in pieces, which
keeps texture elements (bricks, tiles) whole, at a few distances per pixel.
Tong et al. [2]_ widen every candidate ``x`` to its *k-coherence set*: ``x``
and its ``k - 1`` most similar exemplar positions
(:class:`~texsynth.core.search.KCoherence`).

Here the candidates replace the full search of a level of Wei & Levoy's
multi-resolution scanline synthesis (:mod:`texsynth.pixel._wei_levoy`, which
calls :func:`coherent_level` for ``candidates="k-coherent"``); the pyramid,
the causal neighbourhood joined to its parent's and the distance stay as
they are, and so does Wei's eq. 1 with several sources, minimised over each
source's own candidates (:func:`texsynth.mix_textures`). The level objects it
works on are the engine's (``lv``: the output level, its sources and their
candidate pixels; ``run``: the options of the synthesis).

References
----------
.. [1] M. Ashikhmin, "Synthesizing natural textures", ACM Symposium on
   Interactive 3D Graphics 2001, pp. 217-226. :doi:`10.1145/364338.364405`
.. [2] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
   "Synthesis of bidirectional texture functions on arbitrary surfaces",
   SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
"""

from __future__ import annotations

import numpy as np

from ..core.neighborhood import causal_parts, mask_offsets, multilevel_vectors, wavefronts
from ..core.search import KCoherence, candidate_sq_distances, nearest_candidates, neighbor_sources

__all__ = ["coherent_level"]


def _predicted_cells(parent_cells, cen, shape):
    """Grid cells that the parent level's sources predict: child ``2 s + (p mod 2)`` of the parent's ``s``."""
    height, width = shape
    rows, cols = np.arange(height), np.arange(width)
    pixel = 2 * parent_cells[rows[:, None] // 2, cols[None, :] // 2]
    pixel[..., 0] += (rows % 2)[:, None]
    pixel[..., 1] += (cols % 2)[None, :]
    origin, last = cen[0], cen[-1]
    grid = np.clip(pixel, origin, last) - origin
    return grid[..., 0] * (last[1] - origin[1] + 1) + grid[..., 1]


class _CoherentSource:
    """One source at one level of the k-coherent scanline synthesis: its k-coherence sets and its map."""

    def __init__(self, lv, run, i, parent_cells):
        src, cen = self.src, self.cen = lv.sources[i], lv.centers[i]
        height, width, _ = lv.out.shape
        above, left, full = causal_parts(src.size, src.shape)
        self.causal = above | left
        grid = tuple(int(v) for v in cen[-1] - cen[0] + 1)
        self.vectors = src.vectors(lv.level, run.levels, cen, self.causal)
        self.pixels = src.pyramid[lv.level][cen[:, 0], cen[:, 1]]
        similar = full.copy()
        similar[src.size[0] // 2, src.size[1] // 2] = True  # x's own pixel counts in "similar to x"
        self.sets = KCoherence(src.vectors(lv.level, run.levels, cen, similar) if run.k > 1 else None,
                               grid, run.k, method=run.method, profile=run.profile,
                               rng=np.random.default_rng([run.seed, lv.level, 3] + ([i] if i else [])))
        self.draw = np.random.default_rng([run.seed, lv.level] + ([i] if i else []))
        if parent_cells is None:  # Ashikhmin: every pixel starts from a random exemplar position
            self.cells = self.draw.integers(0, len(cen), size=(height, width))
            self.offsets = mask_offsets(self.causal)
        else:
            self.cells = _predicted_cells(parent_cells, cen, (height, width))
            self.offsets = np.concatenate([mask_offsets(self.causal), mask_offsets(similar & ~self.causal)])
        self.flat_cells = self.cells.reshape(-1)

    def candidates(self, lv, centers):
        """The pixels' candidates ``(M, K)`` (cells) and their query vectors."""
        cands = self.sets.candidates(neighbor_sources(self.cells, centers, self.offsets), self.offsets, rng=self.draw)
        src = self.src
        q = multilevel_vectors(lv.out, lv.parent, centers, src.size, src.parent_size, mode="wrap", mask=self.causal,
                               parent_mask=src.parent_mask)
        return cands, q


def coherent_level(lv, run, bar, parent_cells):
    """One level in scanline order with k-coherent candidates; returns (E, steps per pixel, cells per source).

    Each pixel is compared only with the k-coherence sets of the positions
    its neighbours' sources suggest (``s(p + d) - d``): the causal
    neighbours, as synthesised at this level, and, below the coarsest level,
    every other pixel of the neighbourhood and ``p`` itself as the parent
    level predicts them. The distance is Wei & Levoy's: the causal
    neighbourhood at this level joined to the parent's full one. Pixels on
    one wavefront of the scanline order have no causal neighbour in common
    with each other, so they are chosen together. With several sources each
    keeps its own source map, and the run's ``mixture`` (a
    :class:`~texsynth.pixel._wei_levoy.Mixture`) minimises
    eq. 1 over each source's candidates.
    """
    srcs = [_CoherentSource(lv, run, i, None if parent_cells is None else parent_cells[i])
            for i in range(len(lv.sources))]
    height, width, _ = lv.out.shape
    flat_out = lv.out.reshape(-1, lv.out.shape[-1])
    weights = [w.reshape(-1) for w in lv.weights]
    if len(srcs) == 1:
        flat_out[:] = srcs[0].pixels[srcs[0].flat_cells]
    else:
        flat_out[:] = sum(w[:, None] * c.pixels[c.flat_cells] for w, c in zip(weights, srcs))
    step = max(c.src.size[1] // 2 + 1 for c in srcs)  # every source's causal neighbours on earlier wavefronts
    order, bounds = wavefronts(height, width, step)
    energy, steps = 0.0, 0.0
    for t in range(len(bounds) - 1):
        pix = order[bounds[t] : bounds[t + 1]]
        centers = np.stack(np.divmod(pix, width), 1)
        found = [c.candidates(lv, centers) for c in srcs]
        if len(srcs) == 1:
            (cands, q), c = found[0], srcs[0]
            choice, d2 = nearest_candidates(q, cands, vectors=c.vectors)
            best = cands[np.arange(len(pix)), choice]
            c.flat_cells[pix] = best
            flat_out[pix] = c.pixels[best]
            energy += float(d2.sum())
            steps += len(pix)
        else:
            nds = [candidate_sq_distances(q, cands, c.vectors) for (cands, q), c in zip(found, srcs)]
            colours = [c.pixels[cands] for (cands, _), c in zip(found, srcs)]
            a = np.stack([w[pix] for w in weights])
            p, e, ks, n = run.mixture.candidates(a, nds, colours, run.iterations)
            for (cands, _), c, k in zip(found, srcs, ks):
                c.flat_cells[pix] = cands[np.arange(len(pix)), k]
            flat_out[pix] = p
            energy += float(e.sum())
            steps += float(n.sum())
        if t >= width - 1 and (t - width + 1) % step == 0:  # row (t - width + 1) / step is complete
            bar.advance({"level": lv.level, "row": (t - width + 1) // step})
    return energy / (height * width), steps / (height * width), [c.cells for c in srcs]
