"""Graph-cut video: spatio-temporal patches of a clip joined along 3-D minimum cuts (Kwatra et al. 2003, Section 5).

Graph-cut textures (:func:`texsynth.graphcut_texture`) treat an image as a grid
graph and join every new patch to the output along the minimum cut of their
overlap. Section 5 of the paper does the same for video: the clip is a volume
``(T, H, W)``, a patch is a *spatio-temporal block* of it (a run of frames of a
window of the frame), and the seam between the output ``A`` and a new patch
``B`` is a minimum cut of the 6-connected voxel graph over their overlap: a
surface in space and time, so each pixel switches from old to new at a frame
of its own. The module reads top-down as the paper does:

1. **Patch placement** (Section 4, for video mostly temporal offsets): the
   output is covered in raster order (time, rows, columns); the next block
   window of the output is put so that the first empty voxel lies ``overlap``
   voxels inside it, and the block of the clip to paste there is drawn with
   ``P(t) ∝ exp(-C(t) / (k σ²))`` among the offsets not used before, ``C(t)``
   the mean squared difference over the voxels already filled (*entire patch
   matching*), or uniformly (*random placement*). With the defaults the block is
   whole frames (the output's frame size), so the only choice is the
   *temporal offset* between output and clip, the paper's way of extending a
   clip in time; a block smaller than the frame also picks its offset in space.
   ``C`` of every offset comes from FFT correlations, one frame of the clip at
   a time (:class:`texsynth.core.search.WindowSearch`).
2. **Patch fitting** (Section 3, in 3-D): :func:`texsynth.core.seams.graph_cut`
   with ``spatial_dims=3`` over the overlap, with the matching cost ``M`` (or
   ``M'``), voxels next to old-only output tied to ``A``, voxels next to
   new-only ones tied to ``B``, and a seam node for every old seam in the
   overlap (old seams are remembered as in 2-D).
3. **Loops**: with ``loop=True`` the time axis wraps as ``graphcut_texture``'s
   ``tileable`` wraps space: windows, constraints and seams run from the last
   frame into the first, so the last patch is cut into the first one too and
   the clip plays in a loop without a jump.

References
----------
.. [1] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut textures: image and video synthesis
   using graph cuts", ACM TOG 22(3) (SIGGRAPH 2003), pp. 277-286, doi:10.1145/882262.882264.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import time

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_choice, check_memory,
                              check_positive_float, check_positive_int, restore_channels, with_channels)
from ..core.seams import edge_cost_function, graph_cut
from ..core.search import WindowSearch

__all__ = ["graphcut_video", "GraphcutVideoInfo"]

PLACEMENTS = ("entire", "random")
#: The default block: half the clip's frames (so that there are temporal offsets to choose from) ...
TIME_FRACTION = 1 / 2
#: ... of whole output frames where they fit in the clip's, else half the clip's side (graphcut_texture's half
#: exemplar): whole-frame blocks side by side show the clip's frame at one place only, and their seams ran
#: straight through unrelated content (waves, 128 -> 192 px); half-frame blocks also choose offsets in space
SPACE_FRACTION = 1 / 2
#: ... and a new block overlaps what is filled by half its frames (a run of frames in which each pixel can
#: choose its own frame to change block: with 2 frames the cut is forced to the straight one) ...
TIME_OVERLAP_FRACTION = 1 / 2
#: ... and by a third of its side in space (graphcut_texture's)
OVERLAP_FRACTION = 1 / 3
#: Refinement: the box of highest seam cost is this fraction of the block along each axis (graph-cut textures')
REGION_FRACTION = 1 / 2
#: Refinement passes at most (each places as many patches as covered the output)
MAX_REFINE = 10
MIN_FRAMES = 2  # a block holds at least two frames
MIN_SIDE = 4  # and at least 4 x 4 pixels (graphcut_texture's smallest block)
# bytes per output voxel and channel (canvas, a copy, the clip) and per voxel (labels, masks, seam maps)
_BYTES_PER_VALUE = 8 * 3
_BYTES_PER_VOXEL = 64


@dataclasses.dataclass(frozen=True, eq=False)
class GraphcutVideoInfo:
    """What :func:`graphcut_video` placed and cut, patch by patch in the order it placed them.

    Attributes
    ----------
    corners : numpy.ndarray
        ``(n, 3)`` int, the first ``(frame, row, column)`` of each patch's
        window in the output (the frame modulo ``n_frames`` with ``loop=True``).
    sources : numpy.ndarray
        ``(n, 3)`` int, the first ``(frame, row, column)`` of the block of the
        clip pasted there; ``corners - sources`` are the patches' offsets
        (``[:, 0]`` the temporal offset: output frame ``t`` of patch ``k``
        shows clip frame ``t - offsets[k, 0]``).
    costs : numpy.ndarray
        ``(n,)``, the matching cost ``C`` of the chosen offset (mean squared
        difference per voxel over the filled voxels of the window; 0 for the
        first patch and for random placement).
    changed : numpy.ndarray
        ``(n,)`` int, how many output voxels the patch took.
    seam_costs : numpy.ndarray
        ``(n,)``, the cost of the cut that fitted each patch (``graph_cut``'s
        ``cut_cost``: ``M`` over the pairs of voxels it separates, plus the old
        seams it keeps); 0 where a patch had no overlap.
    baseline_costs : numpy.ndarray
        ``(n,)``, the cost, counted the same way, of cutting the same overlap
        along a straight plane in its middle instead: every overlap voxel goes
        to the side (old or new) whose own voxels are nearer (for a run of
        whole frames, the plane between its two middle frames). 0 where a patch
        had no overlap.
    labels : numpy.ndarray
        ``(n_frames, H, W)`` int, which patch each output voxel comes from.
    block, overlap : tuple of int
        ``(frames, height, width)`` of the blocks and of their overlap (along
        an axis that one block spans, the overlap plays no part).
    seam_cost : float
        The total cost of the output's seams at the end: ``edge_cost`` summed
        over every pair of 6-neighbours from different patches (across the
        loop's wrap too, with ``loop=True``).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Of that: ``"placement"`` (choosing the offsets: the FFT search),
        ``"fitting"`` (building and cutting the graphs, pasting),
        ``"baseline"`` (pricing the straight cuts), ``"seams"`` (the final
        ``seam_cost``).
    cut_seconds : float
        Of that, building and cutting the graphs of the patches.
    baseline_seconds : float
        Of that, the cuts that priced the straight baseline.
    """

    corners: np.ndarray
    sources: np.ndarray
    costs: np.ndarray
    changed: np.ndarray
    seam_costs: np.ndarray
    baseline_costs: np.ndarray
    labels: np.ndarray
    block: tuple
    overlap: tuple
    seam_cost: float
    seconds: float
    stage_seconds: dict
    cut_seconds: float
    baseline_seconds: float


# --------------------------------------------------------------------------
# Checks


def _triple(value, name):
    """An int (the same on every axis) or three ints ``(frames, height, width)``."""
    if isinstance(value, numbers.Integral) and not isinstance(value, bool):
        return (int(value),) * 3
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 3:
        raise TypeError(f"{name} must be 'auto', an int or three ints (frames, height, width), got {value!r}")
    return tuple(check_positive_int(v, name, minimum=0) for v in value)


def _check_block(block, clip_shape, out_shape, loop):
    """``(bt, bh, bw)``: a block of at most the clip's (and, but for a loop's time, the output's) extent."""
    T, H, W = clip_shape
    N, Ho, Wo = out_shape
    longest_t = N - 2 if loop else N  # a loop's blocks must leave room to overlap themselves round the wrap
    if isinstance(block, str):  # "auto"
        bt = min(max(MIN_FRAMES, min(T, round(T * TIME_FRACTION), longest_t)), longest_t)
        return (bt,) + tuple(o if o <= n else max(MIN_SIDE, round(n * SPACE_FRACTION)) for n, o in ((H, Ho), (W, Wo)))
    bt, bh, bw = _triple(block, "block")
    for b, limit, what in ((bt, T, "frames"), (bh, H, "rows"), (bw, W, "columns")):
        low = MIN_FRAMES if what == "frames" else MIN_SIDE
        if b < low or b > limit:
            raise ValueError(f"block {(bt, bh, bw)} must hold {low} to {limit} {what} (the clip's {what}); pass "
                             f"block='auto' or (frames, height, width) within the clip {clip_shape}")
    if loop and bt > longest_t:
        raise ValueError(f"n_frames={N} is too short for a loop of {bt}-frame blocks: a loop needs n_frames >= "
                         f"block frames + 2 = {bt + 2}; pass more n_frames or a shorter block")
    return (bt if loop else min(bt, N)), min(bh, Ho), min(bw, Wo)


def _check_overlap(overlap, block, out_shape, loop):
    """The overlap per axis; along an axis the block spans (no second block), at most the block's extent - 1."""
    spans = [b >= n and not (axis == 0 and loop) for axis, (b, n) in enumerate(zip(block, out_shape))]
    if isinstance(overlap, str):  # "auto"
        over = tuple(max(1, round(b * f)) for b, f in zip(block, (TIME_OVERLAP_FRACTION,) + (OVERLAP_FRACTION,) * 2))
    else:
        over = _triple(overlap, "overlap")
        for o, b, span in zip(over, block, spans):
            if not span and not 1 <= o < b:
                raise ValueError(f"overlap {over} must be 1 to block - 1 on every axis (block {block}); pass "
                                 f"overlap='auto' (half the block's frames, a third of its side) or smaller values")
    return tuple(min(o, b - 1) if span else o for o, b, span in zip(over, block, spans))


# --------------------------------------------------------------------------
# The output volume: blocks of the clip at offsets


class _Volume:
    """The output under construction: its voxels, which patch each came from, and the patches' offsets.

    Patch ``k`` is the block of the clip at ``sources[k]`` pasted at the output window at ``corners[k]``;
    voxel ``p`` of the window shows ``clip[sources[k] + (p - corners[k])]``. So that a seam can be priced on
    both sides, a patch also has values one voxel beyond its window where the clip has them; elsewhere the
    output's own value stands in (that half of ``M`` is then 0), as in 2-D.
    """

    def __init__(self, clip, shape, block, loop, edge_cost):
        self.clip, self.loop, self.edge_cost = clip, loop, edge_cost
        self.N, self.H, self.W = shape
        self.block = block
        self.canvas = np.zeros(shape + (clip.shape[3],))
        self.labels = np.full(shape, -1, dtype=np.int64)
        self.corners, self.sources = [], []

    def window(self, corner):
        """Output frames, rows and columns of the window whose first voxel is ``corner`` (frames wrapped in a loop)."""
        t0, r0, c0 = corner
        bt, bh, bw = self.block
        frames = t0 + np.arange(bt)
        return (frames % self.N if self.loop else frames), r0 + np.arange(bh), c0 + np.arange(bw)

    def values_of(self, k, t, r, c):
        """Patch ``k``'s values at voxels ``(t, r, c)`` (arrays of one shape; ``k`` broadcast with them)."""
        corners, sources = np.asarray(self.corners), np.asarray(self.sources)
        i, j, l = t - corners[k, 0], r - corners[k, 1], c - corners[k, 2]
        if self.loop:  # one frame before the window is -1, not N - 1
            i = i % self.N
            i = np.where(i == self.N - 1, -1, i)
        st, sr, sc = sources[k, 0] + i, sources[k, 1] + j, sources[k, 2] + l
        T, H, W = self.clip.shape[:3]
        bt, bh, bw = self.block
        inside = ((i >= -1) & (i <= bt) & (j >= -1) & (j <= bh) & (l >= -1) & (l <= bw) & (st >= 0) & (sr >= 0)
                  & (sc >= 0) & (st < T) & (sr < H) & (sc < W))
        out = self.canvas[t, r, c].copy()
        out[inside] = self.clip[st[inside], sr[inside], sc[inside]]
        return out

    def seam_cost(self):
        """``edge_cost`` summed over every pair of 6-neighbours from different patches."""
        return float(self.voxel_seam_costs().sum())

    def voxel_seam_costs(self):
        """Every seam pair's ``edge_cost``, half to each of its two voxels: ``(N, H, W)``."""
        lab = self.labels
        grid = np.indices(lab.shape)
        per_voxel = np.zeros(lab.shape)
        for axis in (2, 1, 0):
            t_lab = np.roll(lab, -1, axis)
            seam = (lab != t_lab) & (lab >= 0) & (t_lab >= 0)
            if not (self.loop and axis == 0):  # no pair across the border, but round a loop's wrap
                index = [slice(None)] * 3
                index[axis] = -1
                seam[tuple(index)] = False
            s = tuple(g[seam] for g in grid)
            t = tuple(np.roll(g, -1, axis)[seam] for g in grid)
            if s[0].size == 0:
                continue
            ks, kt = lab[s], lab[t]
            a_s, b_t = self.canvas[s], self.canvas[t]  # each voxel's own patch ...
            a_t, b_s = self.values_of(ks, *t), self.values_of(kt, *s)  # ... and the other's
            costs = np.asarray(self.edge_cost(a_s, a_t, b_s, b_t), dtype=np.float64)
            np.add.at(per_voxel, s, costs / 2)
            np.add.at(per_voxel, t, costs / 2)
        return per_voxel

    def paste(self, corner, source, baseline):
        """Fit the clip's block at ``source`` into the output window at ``corner`` by a 3-D graph cut.

        Returns ``(changed, cut_cost, baseline_cost, cut_seconds, baseline_seconds)``; the baseline (the
        straight cut of the same overlap) is priced only if ``baseline``.
        """
        frames, rows, cols = self.window(corner)
        box = np.ix_(frames, rows, cols)
        st, sr, sc = source
        bt, bh, bw = self.block
        new = self.clip[st:st + bt, sr:sr + bh, sc:sc + bw]
        old, lab = self.canvas[box], self.labels[box]
        filled = lab >= 0
        take = ~filled
        cut = base = seconds = base_seconds = 0.0
        if filled.any():
            old_only, new_only = self._sides(frames, rows, cols, filled)
            to_old, to_new = filled & _next_to(old_only), filled & _next_to(new_only)
            both = to_old & to_new
            used = np.unique(lab[filled])
            grid = np.meshgrid(frames, rows, cols, indexing="ij")
            layers = np.stack([self.values_of(np.full(lab.shape, k), *grid) for k in used])
            local = np.searchsorted(used, np.where(filled, lab, used[0]))
            kwargs = dict(mask=filled, labels=local, patches=layers, edge_cost=self.edge_cost, spatial_dims=3)
            t1 = time.perf_counter()
            side, cut = graph_cut(old, new, old_mask=to_old & ~both, new_mask=to_new & ~both, **kwargs)
            seconds = time.perf_counter() - t1
            if baseline and old_only.any() and new_only.any():
                t1 = time.perf_counter()
                base = _straight_cost(old, new, filled, old_only, new_only, kwargs)
                base_seconds = time.perf_counter() - t1
            take |= side
        k = len(self.corners)
        self.corners.append(tuple(int(v) for v in corner))
        self.sources.append(tuple(int(v) for v in source))
        region = self.canvas[box]
        region[take] = new[take]
        self.canvas[box] = region
        lab = lab.copy()
        lab[take] = k
        self.labels[box] = lab
        return int(take.sum()), cut, base, seconds, base_seconds

    def _sides(self, frames, rows, cols, filled):
        """The window with a ring of one voxel: filled voxels of the ring (old-only output) and the window's
        empty voxels (new-only), each ``(bt + 2, bh + 2, bw + 2)``."""
        ring = []
        for index, extent, wraps in ((frames, self.N, self.loop), (rows, self.H, False), (cols, self.W, False)):
            around = np.r_[index[0] - 1, index, index[-1] + 1]
            if wraps:
                around = around % extent
            ring.append((around, (around >= 0) & (around < extent)))
        (ft, okt), (fr, okr), (fc, okc) = ring
        ok = okt[:, None, None] & okr[None, :, None] & okc[None, None, :]
        old_only = np.zeros(ok.shape, bool)
        old_only[ok] = (self.labels[np.ix_(np.clip(ft, 0, self.N - 1), np.clip(fr, 0, self.H - 1),
                                           np.clip(fc, 0, self.W - 1))] >= 0)[ok]
        old_only[1:-1, 1:-1, 1:-1] = False
        new_only = np.zeros(ok.shape, bool)
        new_only[1:-1, 1:-1, 1:-1] = ~filled
        return old_only, new_only


def _next_to(mask):
    """Voxels of the window (the inside of the ring) with a 6-neighbour in ``mask``."""
    return (mask[:-2, 1:-1, 1:-1] | mask[2:, 1:-1, 1:-1] | mask[1:-1, :-2, 1:-1] | mask[1:-1, 2:, 1:-1]
            | mask[1:-1, 1:-1, :-2] | mask[1:-1, 1:-1, 2:])


def _straight_cost(old, new, filled, old_only, new_only, kwargs):
    """The cost of the straight cut of an overlap: each voxel to the side whose own voxels are nearer (ties old).

    Priced by the same :func:`graph_cut` with every overlap voxel tied to its side, so that the old seams are
    counted exactly as in the real cut.
    """
    from scipy import ndimage

    d_old = ndimage.distance_transform_edt(~old_only)[1:-1, 1:-1, 1:-1]
    d_new = ndimage.distance_transform_edt(~new_only)[1:-1, 1:-1, 1:-1]
    old_side = filled & (d_old <= d_new)
    _, cost = graph_cut(old, new, old_mask=old_side, new_mask=filled & ~old_side, **kwargs)
    return cost


# --------------------------------------------------------------------------
# Section 4 (for video): offsets of the blocks


class _Offsets:
    """Chooses the clip's block for an output window: entire patch matching or random placement.

    The cost of every offset ``(st, sr, sc)`` is ``C = 1/|A| sum_{p in A} |I(p + s) - O(p)|^2`` over the filled
    voxels ``A`` of the window: per frame of the window, an FFT correlation over the clip's frame it meets
    (:class:`~texsynth.core.search.WindowSearch`), summed over the frames.
    """

    def __init__(self, clip, volume, placement, temperature, gen):
        self.clip, self.volume, self.placement, self.gen = clip, volume, placement, gen
        bt, bh, bw = volume.block
        self.positions = (clip.shape[0] - bt + 1, clip.shape[1] - bh + 1, clip.shape[2] - bw + 1)
        self._searches = {}
        variance = float(clip.reshape(-1, clip.shape[3]).var(axis=0).sum())
        self.temperature = temperature * (variance if variance > 0 else 1.0)  # the paper's k sigma^2
        self.used = set()

    def _search(self, f):
        if f not in self._searches:
            self._searches[f] = WindowSearch(self.clip[f], self.volume.block[1:])
        return self._searches[f]

    def _translation(self, corner, st, sr, sc):
        dt = corner[0] - st
        return (dt % self.volume.N if self.volume.loop else dt, corner[1] - sr, corner[2] - sc)

    def choose(self, corner):
        """``(source, cost)``: the block of the clip for the output window at ``corner``."""
        vol = self.volume
        frames, rows, cols = vol.window(corner)
        known = vol.labels[np.ix_(frames, rows, cols)] >= 0
        nt, ny, nx = self.positions
        free = np.ones(self.positions, bool)
        dt, dy, dx = self._translation(corner, np.arange(nt), np.arange(ny), np.arange(nx))
        for ut, uy, ux in self.used:
            free[np.ix_(dt == ut, dy == uy, dx == ux)] = False
        if not free.any():
            free[:] = True
        costs = None
        if self.placement == "entire" and known.any():
            costs = np.zeros(self.positions)
            for k in np.flatnonzero(known.any(axis=(1, 2))):
                template = vol.canvas[frames[k]][np.ix_(rows, cols)]
                mask = known[k].astype(np.float64)
                for st in range(nt):
                    costs[st] += self._search(st + k).sq_distances(template, mask)
            costs /= known.sum()
        flat = _draw(costs, free, self.temperature, self.gen)
        st, sr, sc = np.unravel_index(flat, self.positions)
        self.used.add(self._translation(corner, int(st), int(sr), int(sc)))
        return (int(st), int(sr), int(sc)), 0.0 if costs is None else float(costs[st, sr, sc])


def _draw(costs, free, temperature, gen):
    """A flat index among the ``free`` ones: uniform (``costs`` None), else ``P ∝ exp(-C / (k σ²))``."""
    if costs is None:
        candidates = np.flatnonzero(free)
        return int(candidates[gen.integers(candidates.size)])
    c = np.where(free, costs, np.inf)
    weights = np.exp(-(c - c.min()) / temperature).ravel()  # relative to the best, for the numerical range
    return int(gen.choice(weights.size, p=weights / weights.sum()))


def _loop_reach(volume, point, o, b):
    """How many filled frames before the first empty voxel ``point`` a loop's next block reaches back over.

    The last block of a loop closes a gap of empty frames between two filled runs and must overlap both by
    at least ``m`` frames (``max(3, o / 2)``: with 2 the frame next to each side is tied to it and the cut is
    forced straight), so it is centred on a gap of at most ``b - 2m`` frames; a block before it covers less
    than ``b - o`` new frames where needed, so that what it leaves can be closed.
    """
    extent = volume.N
    ahead = volume.labels[(int(point[0]) + np.arange(extent)) % extent, point[1], point[2]] >= 0
    gap = int(np.argmax(ahead)) if ahead.any() else extent
    m = min(max(3, math.ceil(o / 2)), (b - 1) // 2)
    if gap <= b - 2 * m:
        return (b - gap) // 2
    return b - min(b - o, gap - (b - 2 * m))


def _first_empty_corner(volume, overlap):
    """The window of the next covering block: the first empty voxel in raster order (frame, row, column) lies
    ``overlap`` voxels inside it along every axis (time wrapped in a loop, else the window kept in the output)."""
    empty = np.flatnonzero(volume.labels.ravel() < 0)
    point = np.unravel_index(int(empty[0]), volume.labels.shape)
    corner = []
    for axis, (p, o, b, extent) in enumerate(zip(point, overlap, volume.block, volume.labels.shape)):
        if axis == 0 and volume.loop:
            corner.append((int(p) - _loop_reach(volume, point, o, b)) % extent)
        else:
            corner.append(min(max(int(p) - o, 0), extent - b))
    return tuple(corner)


def _worst_window(volume, tries):
    """Refinement's window ``(corner, score)``: the block window centred on the box of half the block with the
    highest seam cost, each voxel's cost divided by one plus the refinement patches placed over it already (as
    in 2-D: regions that could not be improved give way); time wraps round a loop."""
    per_voxel = volume.voxel_seam_costs() / (1.0 + tries)
    region = tuple(max(1, round(b * REGION_FRACTION)) for b in volume.block)
    if volume.loop:  # windows round the loop's wrap
        per_voxel = np.concatenate([per_voxel, per_voxel[:region[0] - 1]])
    sums = np.pad(per_voxel, [(1, 0)] * 3)
    for axis in range(3):
        sums = np.cumsum(sums, axis=axis)
    (et, er, ec) = region
    box = (sums[et:, er:, ec:] - sums[:-et, er:, ec:] - sums[et:, :-er, ec:] - sums[et:, er:, :-ec]
           + sums[:-et, :-er, ec:] + sums[:-et, er:, :-ec] + sums[et:, :-er, :-ec] - sums[:-et, :-er, :-ec])
    best = np.unravel_index(int(np.argmax(box)), box.shape)
    corner = []
    for axis, (p, e, b, extent) in enumerate(zip(best, region, volume.block, volume.labels.shape)):
        start = int(p) - (b - e) // 2
        corner.append(start % extent if (axis == 0 and volume.loop) else min(max(start, 0), extent - b))
    return tuple(corner), float(box[best])


# --------------------------------------------------------------------------
# The public function


def graphcut_video(frames, n_frames, *, size=None, block="auto", overlap="auto", placement="entire",
                   temperature=0.02, edge_cost="plain", refine=0, loop=False, rng=None, return_info=False,
                   progress=False):
    """Extend a clip in time and space from spatio-temporal patches joined along 3-D minimum cuts (Kwatra et al. 2003).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> clip = texsynth.data.clip("waves", 12, 32)
    >>> video, info = texsynth.graphcut_video(clip, 20, rng=0, return_info=True)
    >>> video.shape, info.block
    ((20, 32, 32, 3), (6, 32, 32))
    >>> bool(info.seam_costs.sum() <= info.baseline_costs.sum())  # cheaper than straight cuts
    True
    >>> loop = texsynth.graphcut_video(clip, 20, loop=True, rng=0)  # its last frame leads into its first

    The output is built from blocks of the clip (a run of frames of a window
    of the frame, the paper's spatio-temporal patches), each joined to what
    is there along the minimum cut of the 6-connected voxel graph of their
    overlap (:func:`texsynth.core.seams.graph_cut` with ``spatial_dims=3``):
    a surface in space and time, so each pixel switches from the old block to
    the new one at a frame of its own, where the two agree best. With the
    defaults the blocks are whole frames and half the clip long, and the
    choice is the *temporal offset* of each block, drawn by how well it
    matches the frames already there: the paper's temporal extension of a
    clip. A larger ``size`` extends the frames too (blocks of half the
    clip's frame, offset in time and space, tiled in space); ``loop=True``
    makes a clip whose last frame leads into its first.

    Parameters
    ----------
    frames : array_like or str
        The clip, ``(T, H, W)`` or ``(T, H, W, C)``: at least 2 frames of at
        least 4 x 4 pixels (or a file of frames).
    n_frames : int
        Number of output frames (with ``loop=True``: the loop's length, at
        least the block's frames + 2).
    size : None, int or (int, int)
        Output frame size ``(height, width)``; None (default): the clip's.
    block : "auto", int or (int, int, int)
        The spatio-temporal patch ``(frames, height, width)`` (an int: a
        cube), within the clip. ``"auto"``: half the clip's frames (at most
        ``n_frames``, a loop's ``n_frames - 2``) of whole output frames
        where the output's frame fits in the clip's (along each axis), else
        of half the clip's side.
    overlap : "auto", int or (int, int, int)
        While covering, how far a new block reaches back over filled output
        along ``(frames, rows, columns)`` (an int: every axis), 1 to the
        block's extent - 1. ``"auto"``: half the block's frames in time, a
        third of its side in space.
    placement : {"entire", "random"}
        How the offset of each block is chosen: entire patch matching
        (``P(t) ∝ exp(-C(t) / (k σ²))``, ``C`` the mean squared difference
        over the filled voxels of the window) or random placement.
    temperature : float
        The paper's ``k``: small picks the best-matching offsets only,
        large is random. Default 0.02 (``graphcut_texture``'s).
    edge_cost : {"plain", "gradient"} or callable
        The cost of a seam between neighbouring voxels: the paper's ``M``
        (default), its gradient-normalised ``M'`` (gradients along each arc,
        in time as well as space) or any ``edge_cost(a_s, a_t, b_s, b_t)``.
    refine : int
        Refinement passes after the output is covered (Section 4): each
        places as many patches as the covering did, each over the window
        whose central box (half the block along each axis) holds the highest
        seam cost, fitted with the old seams' seam nodes so that it replaces
        them where it agrees better; at most 10. 0 (the default): a pass
        took 2.7 times the covering's time and lowered the total seam cost by
        3.7 % on a spatial extension (waves, 24 frames of 48² to 32 of 80²,
        seed 0; 2 passes 4.4 %), with no visible change.
    loop : bool
        Make a temporally looping clip: the time axis wraps (windows,
        constraints and seams run from the last frame into the first).
    rng : None, int or numpy.random.Generator
        Random source of the offsets; an int seed reproduces the output bit
        for bit.
    return_info : bool
        Also return a :class:`GraphcutVideoInfo`; it also prices every
        overlap's straight cut (``baseline_costs``), about doubling the
        time of the cuts.
    progress : bool or callable
        Report progress per block (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    video : numpy.ndarray
        ``(n_frames, height, width[, C])`` in [0, 1], the clip's channel
        layout; float32 for float32 input, float64 otherwise. Every voxel is
        a copy of a voxel of the clip.
    info : GraphcutVideoInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For a clip of fewer than 2 frames or smaller than 4 x 4 pixels, a
        ``block`` outside the clip, an ``overlap`` not smaller than the block,
        a loop too short for its blocks, ``temperature <= 0``, an option not
        one of its choices, or an output that would not fit in memory.

    Notes
    -----
    *Placement.* The output is covered block by block in raster order
    (frames, rows, columns), each window put so that the first empty voxel
    lies ``overlap`` inside it. The block of the clip to paste there, at
    offset ``s``, is drawn with

    .. math:: P(s) \\propto \\exp\\left(-\\frac{C(s)}{k \\sigma^2}\\right), \\qquad
              C(s) = \\frac{1}{|A|} \\sum_{p \\in A} |I(p + s) - O(p)|^2

    over the filled voxels ``A`` of the window (``σ²`` the clip's variance
    summed over channels), among the offsets (translations between output
    and clip) not used before. The paper places the *whole* clip at
    temporal offsets with an overlap that varies with the offset; here the
    window and its overlap are fixed and the block of the clip varies, which
    is the same choice of translation with a fixed overlap.

    *Fitting.* The overlap's voxels are labelled old (``A``) or new (``B``)
    by the minimum cut with ``M(s, t, A, B) = ||A(s) - B(s)|| + ||A(t) -
    B(t)||`` over 6-neighbours (in time as well as in space), voxels next to
    old-only output tied to ``A``, those next to the block's new-only voxels
    to ``B``, and a seam node for every old seam in the overlap (Section 3,
    in 3-D). The seam is a surface in space and time: each pixel changes
    block at the frame where the two blocks agree best there.

    *Loops.* The time axis wraps: the last block overlaps the first frames
    and is cut into them as into the frames before it, so frame
    ``n_frames - 1`` is followed by frame 0 as any frame by the next.

    *Refinement* (``refine``): further patches over the costliest seams,
    as in graph-cut textures, each voxel's seam cost divided by one plus the
    refinement patches already placed over it; every such cut can only lower
    the total seam cost (keeping the old voxels is one of its cuts).

    Not in this implementation: the paper's sub-patch matching, and its
    exact values of ``k``, block length and overlap for video (not at hand).

    References
    ----------
    .. [1] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
       textures: image and video synthesis using graph cuts", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 277-286. :doi:`10.1145/882262.882264`
    """
    started = time.perf_counter()
    video = as_image(frames, "frames", spatial_dims=3)
    clip, grey = with_channels(video, spatial_dims=3)
    if clip.shape[0] < MIN_FRAMES or min(clip.shape[1:3]) < MIN_SIDE:
        raise ValueError(f"frames has shape {video.shape}; graph-cut video needs at least {MIN_FRAMES} frames of "
                         f"at least {MIN_SIDE}x{MIN_SIDE} pixels")
    N = check_positive_int(n_frames, "n_frames")
    frame = tuple(clip.shape[1:3]) if size is None else as_size(size)
    loop = check_bool(loop, "loop")
    if loop and N < MIN_FRAMES + 2:
        raise ValueError(f"n_frames={N} is too short for a loop: it needs at least {MIN_FRAMES + 2} frames")
    out_shape = (N,) + tuple(frame)
    if (isinstance(block, str) and block != "auto") or block is None:
        raise TypeError(f"block must be 'auto', an int or three ints (frames, height, width), got {block!r}")
    B = _check_block(block, clip.shape[:3], out_shape, loop)
    if (isinstance(overlap, str) and overlap != "auto") or overlap is None:
        raise TypeError(f"overlap must be 'auto', an int or three ints (frames, height, width), got {overlap!r}")
    O = _check_overlap(overlap, B, out_shape, loop)
    placement = check_choice(placement, "placement", PLACEMENTS)
    temperature = check_positive_float(temperature, "temperature")
    cost_fn = edge_cost_function(edge_cost)
    refine = check_positive_int(refine, "refine", minimum=0, maximum=MAX_REFINE)
    return_info = check_bool(return_info, "return_info")
    gen = as_rng(rng)
    voxels = float(math.prod(out_shape))
    window = float(math.prod(B))
    # the canvas, labels and masks; a block's layers and the graph of its cut (graph_cut's own ~256 B per voxel)
    check_memory(voxels * (clip.shape[3] * _BYTES_PER_VALUE + _BYTES_PER_VOXEL) + window * (clip.shape[3] * 64 + 512),
                 N, "n_frames", "the output and the graphs of its cuts", also={"size": frame})

    volume = _Volume(np.ascontiguousarray(clip, dtype=np.float64), out_shape, B, loop, cost_fn)
    chooser = _Offsets(volume.clip, volume, placement, temperature, gen)
    steps = [b - o for b, o in zip(B, O)]
    expected = math.prod(max(1, math.ceil((n - (0 if (a == 0 and loop) else o)) / s))
                         for a, (n, o, s) in enumerate(zip(out_shape, O, steps)))
    records, timing = [], {"cut": 0.0, "baseline": 0.0, "placement": 0.0, "fitting": 0.0}
    with Progress(progress, expected * (1 + refine), "graphcut_video") as bar:
        placed = 0
        while (volume.labels < 0).any():
            t0 = time.perf_counter()
            corner = _first_empty_corner(volume, O)
            source, cost = chooser.choose(corner)
            t1 = time.perf_counter()
            changed, cut, base, seconds, base_seconds = volume.paste(corner, source, return_info)
            timing["placement"] += t1 - t0
            timing["fitting"] += time.perf_counter() - t1 - base_seconds
            timing["cut"] += seconds
            timing["baseline"] += base_seconds
            records.append((cost, changed, cut, base))
            placed += 1
            if placed <= expected:
                bar.advance({"seam cost": cut})
        if placed < expected:
            bar.advance({}, n=expected - placed)
        n_cover, tries = placed, np.zeros(out_shape)
        for _ in range(refine * n_cover):  # refinement: patches over the costliest seams (Section 4)
            t0 = time.perf_counter()
            corner, score = _worst_window(volume, tries)
            if score <= 0:  # no seam left
                bar.advance({"seam cost": 0.0})
                continue
            frames_, rows, cols = volume.window(corner)
            tries[np.ix_(frames_, rows, cols)] += 1
            source, cost = chooser.choose(corner)
            t1 = time.perf_counter()
            changed, cut, base, seconds, base_seconds = volume.paste(corner, source, False)
            timing["placement"] += t1 - t0
            timing["fitting"] += time.perf_counter() - t1
            timing["cut"] += seconds
            records.append((cost, changed, cut, base))
            bar.advance({"seam cost": cut})

    out = restore_channels(np.clip(volume.canvas, 0.0, 1.0).astype(video.dtype, copy=False), grey)
    if not return_info:
        return out
    rec = np.array(records, dtype=np.float64).reshape(-1, 4)
    t0 = time.perf_counter()
    seam_cost = volume.seam_cost()
    stages = {"placement": timing["placement"], "fitting": timing["fitting"], "baseline": timing["baseline"],
              "seams": time.perf_counter() - t0}
    return out, GraphcutVideoInfo(
        corners=np.array(volume.corners, dtype=np.int64).reshape(-1, 3),
        sources=np.array(volume.sources, dtype=np.int64).reshape(-1, 3), costs=rec[:, 0],
        changed=rec[:, 1].astype(np.int64), seam_costs=rec[:, 2], baseline_costs=rec[:, 3],
        labels=volume.labels.copy(), block=B, overlap=O, seam_cost=seam_cost,
        seconds=time.perf_counter() - started, stage_seconds=stages, cut_seconds=timing["cut"], baseline_seconds=timing["baseline"])
