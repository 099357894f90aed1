"""Kwatra et al.'s graph-cut textures: patches placed by matching and joined along minimum cuts.

Graph-cut textures (Kwatra, Schödl, Essa, Turk & Bobick 2003) build the output
from pieces of the exemplar like image quilting, but let the seam between the
output ``A`` and a new patch ``B`` take any shape: it is the minimum cut of a
graph over their overlap (Section 3), with *seam nodes* that remember the old
seams, so a patch may also be placed over output that is already covered and
replace the worst seams there. The algorithm, as this module runs it:

1. **Patch placement** (Section 4): an *error region* of the output is chosen
   (while covering: around the first empty pixel in raster order, straddling
   filled and empty output; during refinement: the region with the highest
   seam cost), a block window ``B x B`` of the output around it, and the
   exemplar window to paste there, in one of three ways:

   - ``"random"``: any exemplar window (fastest; random textures);
   - ``"entire"``: entire patch matching, the cost of every exemplar window
     being its mean squared difference with the output over the whole overlap,
     ``C(t) = 1/|A_t| sum_{p in A_t} |I(p - t) - O(p)|^2``;
   - ``"subpatch"``: sub-patch matching, the same over the error region only
     (a sub-patch ``S_O`` of the block);

   and one window is drawn with probability ``P(t) ∝ exp(-C(t) / (k σ²))``,
   ``σ²`` the variance of the exemplar's values, among translations not used
   before. Every window's cost comes at once from an FFT correlation
   (:class:`texsynth.core.search.WindowSearch`). With ``block="whole"`` (the
   paper's patch) the whole exemplar is placed instead, at one of the output
   translations that cover the error region, scored the same three ways
   (:class:`texsynth.core.search.TemplateSearch`).
2. **Patch fitting** (Section 3): :func:`texsynth.core.seams.graph_cut` over
   the overlap, with the paper's matching cost ``M`` or its gradient-normalised
   ``M'`` (:func:`texsynth.core.seams.gradient_matching_cost`), pixels next to
   old-only output tied to ``A``, pixels next to new-only ones tied to ``B``,
   and a seam node for every old seam inside the overlap. A patch placed over
   covered output (a *surrounded region*) has its border tied to ``A``; its
   seam nodes connect the inside to ``B``, so the cut replaces old seams
   exactly where the new patch is cheaper.
3. **Refinement** (Section 4, Figure 5): once the output is covered, further
   patches are placed over the regions of highest seam cost; each cut can only
   lower the total seam cost.

The paper places the *whole* input at an output translation ``t``
(``block="whole"``, ``preset="paper"``); by default a ``block`` window of the
exemplar is pasted at an output window chosen around the error region and the
search runs over the exemplar's windows (the same question with the roles of
output and exemplar exchanged, which lets the block be smaller than the
exemplar: the whole input is copied in large verbatim pieces).

What could not be checked against the paper's text (it was not at hand;
this follows its published description): the discretisation of the
gradients in ``M'`` (here the finite difference along each arc, see
:func:`~texsynth.core.seams.gradient_matching_cost`), the size of the error
region and sub-patch (here half the block), how refinement regions are ranked
(here seam cost per window, damped by how often a pixel was tried already),
a default ``k`` (the option ``temperature``; the paper varies it from 0.001 to 1), and the section
numbers quoted (Section 3 patch fitting, Section 4 placement and refinement).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (
    as_binary_map,
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_memory,
    check_positive_float,
    check_positive_int,
    restore_channels,
    with_channels,
)
from ..core.seams import check_disjoint, edge_cost_function, graph_cut
from ..core.search import TemplateSearch, WindowSearch, is_auto

__all__ = ["GraphcutInfo", "GraphcutMergeInfo", "graphcut_merge", "graphcut_texture"]

PLACEMENTS = ("entire", "subpatch", "random")
PRESETS = ("default", "paper")
# preset "default": chosen by looking at 256 -> 512 px outputs of bricks, pebbles, text and water (see the docs)
DEFAULTS = {
    "default": {"placement": "entire", "block_fraction": 1 / 2, "temperature": 0.02, "edge_cost": "plain", "refine": 2},
    # preset "paper": the whole input placed at output translations, entire patch matching, the plain cost M
    # of Section 3, one refinement pass (the paper's k and refinement length are not known here)
    "paper": {"placement": "entire", "block_fraction": "whole", "temperature": 0.01, "edge_cost": "plain",
              "refine": 1},
}
OVERLAP_FRACTION = 1 / 3  # while covering, a new block overlaps what is filled by a third of its side
REGION_FRACTION = 1 / 2  # the error region (and sub-patch) is half the block
MIN_BLOCK = 4
MAX_REFINE = 100  # refinement passes: beyond a few, nothing changes


@dataclass
class GraphcutInfo:
    """What :func:`graphcut_texture` placed, patch by patch in the order it placed them.

    Attributes
    ----------
    corners : numpy.ndarray
        ``(n, 2)`` int, the top-left pixel of each patch's window in the
        output (modulo the output size for tileable output).
    sources : numpy.ndarray
        ``(n, 2)`` int, the top-left pixel of the exemplar window pasted there.
    costs : numpy.ndarray
        ``(n,)``, the matching cost ``C`` of the chosen window (mean squared
        difference per pixel over the compared pixels; 0 with nothing to
        compare or for random placement).
    changed : numpy.ndarray
        ``(n,)`` int, how many output pixels the patch took.
    labels : numpy.ndarray
        ``(H, W)`` int, which patch each output pixel comes from (an index
        into ``corners``).
    n_initial : int
        How many patches covered the output; the rest refined it.
    block, overlap : int
        The block side and the overlap of the covering pass.
    seam_cost : float
        The total cost of the output's seams at the end (``energy[-1]``).
    energy : numpy.ndarray
        The total seam cost after each patch: the sum of ``edge_cost`` over
        every pair of neighbours from different patches. It grows while the
        output is covered and, with the plain cost ``M``, never rises during
        refinement.
    stage : numpy.ndarray
        ``(n,)`` int, 0 for the covering pass, ``i`` for refinement pass ``i``.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Per pass: ``"cover"``, ``"refine 1"``, ``"refine 2"``, ...
    cut_seconds : float
        Of all that, the time spent fitting patches: building the graphs and
        cutting them (the rest: the FFT search and the seam costs).
    coordinates : numpy.ndarray
        ``(H, W, 2)`` int, the exemplar pixel ``(row, col)`` each output
        pixel was copied from: ``sources[k] + (p - corners[k])`` for its patch
        ``k = labels[p]`` (the source-coordinate map of ``docs/conventions.md``;
        render other channels through it with :func:`texsynth.apply_coordinates`).
    weights : None
        Every pixel is a copy.
    """

    corners: np.ndarray
    sources: np.ndarray
    costs: np.ndarray
    changed: np.ndarray
    labels: np.ndarray
    n_initial: int
    block: int
    overlap: int
    seam_cost: float
    energy: np.ndarray
    stage: np.ndarray
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    cut_seconds: float = 0.0
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None


@dataclass
class GraphcutMergeInfo:
    """What :func:`graphcut_merge` cut.

    Attributes
    ----------
    labels : numpy.ndarray
        ``(H, W)`` bool, True where the merged image comes from ``b``.
    seam_cost : float
        The cost of the seam: ``edge_cost`` summed over the neighbouring
        pairs it separates.
    energy : numpy.ndarray
        ``[seam_cost]`` (one cut).
    stage : numpy.ndarray
        ``[0]``.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"cut"``.
    """

    labels: np.ndarray
    seam_cost: float
    energy: np.ndarray
    stage: np.ndarray
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)


# --------------------------------------------------------------------------
# Checks


def _check_choice(value, name, choices):
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def _check_block(block, exemplar_shape, fraction):
    """The patch side, or ``"whole"`` (the exemplar itself, the paper's patch)."""
    shortest = min(exemplar_shape)
    if shortest < MIN_BLOCK:
        raise ValueError(f"exemplar is {exemplar_shape[0]}x{exemplar_shape[1]}; graph-cut textures need an "
                         f"exemplar of at least {MIN_BLOCK}x{MIN_BLOCK} pixels")
    if is_auto(block) and fraction == "whole" or isinstance(block, str) and block == "whole":
        return "whole"
    if is_auto(block):
        return max(MIN_BLOCK, min(shortest, round(shortest * fraction)))
    if isinstance(block, str):
        raise TypeError(f"block must be an integer >= {MIN_BLOCK}, 'whole' (the whole exemplar, the paper's "
                        f"patch) or 'auto' (the preset's), got {block!r}")
    b = check_positive_int(block, "block", minimum=MIN_BLOCK)
    if b > shortest:
        raise ValueError(f"block {b} is larger than the exemplar ({exemplar_shape[0]}x{exemplar_shape[1]}); pass "
                         f"block <= {shortest} (half of it, {max(MIN_BLOCK, shortest // 2)}, is the default) or "
                         f"a larger exemplar")
    return b


def _check_overlap(overlap, block):
    """The covering overlap: 1 to ``block - 1`` (``block``: the patch's shorter side)."""
    if is_auto(overlap):
        return max(1, round(block * OVERLAP_FRACTION))
    o = check_positive_int(overlap, "overlap", minimum=1)
    if o >= block:
        raise ValueError(f"overlap {o} must be smaller than block {block} (default block / 3 = "
                         f"{max(1, round(block * OVERLAP_FRACTION))}); pass overlap < {block} or a larger block")
    return o


def _check_mask(mask, shape, name):
    """A user's binary stroke map (None: no pixel)."""
    if mask is None:
        return np.zeros(shape, dtype=bool)
    return as_binary_map(mask, shape, name, "where the pixel must come from that image")


# --------------------------------------------------------------------------
# The output: patches as translations of the exemplar


class _Output:
    """The output under construction: its values, which patch each pixel came from, and the patches.

    Patch ``k`` is the exemplar window of ``block`` at ``sources[k]`` pasted at
    the output window at ``corners[k]``; pixel ``p`` of its window shows
    ``exemplar[sources[k] + (p - corners[k])]``. So that the seam between two
    patches can be priced on both of its sides, a patch also has values one
    pixel beyond its window, where the exemplar has them; where it has none, the
    output's own value stands in (that half of ``M`` is then 0).
    """

    def __init__(self, exemplar, size, patch_shape, tileable, edge_cost, whole):
        self.ex = exemplar
        self.H, self.W = size
        self.tileable = tileable
        self.edge_cost = edge_cost
        self.bh, self.bw = patch_shape
        if not (tileable or whole):  # blocks stay inside the output; the whole exemplar may hang over its edges
            self.bh, self.bw = min(self.bh, self.H), min(self.bw, self.W)
        self.canvas = np.zeros((self.H, self.W, exemplar.shape[2]))
        self.labels = np.full((self.H, self.W), -1, dtype=np.int64)
        self.corners, self.sources = [], []

    def window(self, r0, c0):
        """``(rows, cols, i, j)``: the output rows and columns of the patch window whose top-left pixel is
        ``(r0, c0)`` (wrapped for tileable output, else cut to the output) and their rows and columns in the patch."""
        i, j = np.arange(self.bh), np.arange(self.bw)
        rows, cols = r0 + i, c0 + j
        if self.tileable:
            return rows % self.H, cols % self.W, i, j
        keep_r, keep_c = (rows >= 0) & (rows < self.H), (cols >= 0) & (cols < self.W)
        return rows[keep_r], cols[keep_c], i[keep_r], j[keep_c]

    def values_of(self, k, rows, cols):
        """Patch ``k``'s values at pixels ``(rows, cols)`` (arrays of one shape, ``k`` broadcast with them)."""
        corners, sources = np.asarray(self.corners), np.asarray(self.sources)
        i, j = rows - corners[k, 0], cols - corners[k, 1]
        if self.tileable:  # one pixel before the window is -1, not H - 1
            i, j = i % self.H, j % self.W
            i, j = np.where(i == self.H - 1, -1, i), np.where(j == self.W - 1, -1, j)
        sr, sc = sources[k, 0] + i, sources[k, 1] + j
        inside = ((i >= -1) & (i <= self.bh) & (j >= -1) & (j <= self.bw) & (sr >= 0) & (sc >= 0)
                  & (sr < self.ex.shape[0]) & (sc < self.ex.shape[1]))
        out = self.canvas[rows, cols].copy()
        out[inside] = self.ex[sr[inside], sc[inside]]
        return out

    def coordinates(self):
        """``(H, W, 2)``: the exemplar pixel every output pixel shows, from its patch's window."""
        corners, sources = np.asarray(self.corners).reshape(-1, 2), np.asarray(self.sources).reshape(-1, 2)
        rows, cols = np.indices((self.H, self.W))
        k = self.labels
        i, j = rows - corners[k, 0], cols - corners[k, 1]
        if self.tileable:
            i, j = i % self.H, j % self.W
        return np.stack([sources[k, 0] + i, sources[k, 1] + j], -1).astype(np.int64)

    def seam_pairs(self):
        """Flat indices ``(s, t)`` of neighbouring pixels from different patches (both covered)."""
        lab = self.labels
        flat = np.arange(self.H * self.W).reshape(self.H, self.W)
        pairs = []
        for axis in (1, 0):
            t_lab, t_idx = np.roll(lab, -1, axis), np.roll(flat, -1, axis)
            seam = (lab != t_lab) & (lab >= 0) & (t_lab >= 0)
            if not self.tileable:  # no pair across the border
                if axis == 1:
                    seam[:, -1] = False
                else:
                    seam[-1, :] = False
            pairs.append((flat[seam], t_idx[seam]))
        return np.concatenate([p[0] for p in pairs]), np.concatenate([p[1] for p in pairs])

    def seam_costs(self):
        """The pairs of :meth:`seam_pairs` and the cost ``edge_cost(A_s, A_t)`` of the old seam between them."""
        s, t = self.seam_pairs()
        rs, cs = np.divmod(s, self.W)
        rt, ct = np.divmod(t, self.W)
        ks, kt = self.labels[rs, cs], self.labels[rt, ct]
        a_s, b_t = self.canvas[rs, cs], self.canvas[rt, ct]  # each pixel's own patch
        a_t, b_s = self.values_of(ks, rt, ct), self.values_of(kt, rs, cs)  # ... and the other's
        costs = np.asarray(self.edge_cost(a_s, a_t, b_s, b_t), dtype=np.float64) if s.size else np.zeros(0)
        return s, t, costs

    def paste(self, r0, c0, top, left):
        """Fit the exemplar window at ``(top, left)`` into the output window at ``(r0, c0)`` by a graph cut.

        Returns how many pixels it took.
        """
        rows, cols, i, j = self.window(r0, c0)
        box = np.ix_(rows, cols)
        new = self.ex[np.ix_(top + i, left + j)]
        old, lab = self.canvas[box], self.labels[box]
        filled = lab >= 0
        take = ~filled
        if filled.any():
            old_mask, new_mask = self._constraints(rows, cols, filled)
            used = np.unique(lab[filled])
            layers = np.stack([self.values_of(np.full(lab.shape, k), *np.meshgrid(rows, cols, indexing="ij"))
                               for k in used])
            local = np.searchsorted(used, np.where(filled, lab, used[0]))
            side, _ = graph_cut(old, new, mask=filled, old_mask=old_mask, new_mask=new_mask, labels=local,
                                patches=layers, edge_cost=self.edge_cost)
            take |= side
        k = len(self.corners)
        self.corners.append((r0, c0))
        self.sources.append((top, left))
        region = self.canvas[box]
        region[take] = new[take]
        self.canvas[box] = region
        lab = lab.copy()
        lab[take] = k
        self.labels[box] = lab
        return int(take.sum())

    def _constraints(self, rows, cols, filled):
        """Overlap pixels next to old-only output (tied to A) and next to new-only pixels (tied to B).

        The window is looked at with a ring of one pixel: a filled neighbour outside the window is
        old-only output, an empty one inside it is new-only. A pixel next to both is left free.
        """
        h, w = filled.shape
        if self.tileable:
            ring_r, ring_c = np.r_[rows[0] - 1, rows, rows[-1] + 1] % self.H, np.r_[cols[0] - 1, cols, cols[-1] + 1] % self.W
            outside = np.ones((h + 2, w + 2), bool)
            outside[1:-1, 1:-1] = False
            old_only = outside & (self.labels[np.ix_(ring_r, ring_c)] >= 0)
        else:
            ring_r, ring_c = np.r_[rows[0] - 1, rows, rows[-1] + 1], np.r_[cols[0] - 1, cols, cols[-1] + 1]
            ok_r, ok_c = (ring_r >= 0) & (ring_r < self.H), (ring_c >= 0) & (ring_c < self.W)
            old_only = np.zeros((h + 2, w + 2), bool)
            inner = self.labels[np.ix_(ring_r[ok_r], ring_c[ok_c])] >= 0
            old_only[np.ix_(ok_r, ok_c)] = inner
            old_only[1:-1, 1:-1] = False
        new_only = np.zeros((h + 2, w + 2), bool)
        new_only[1:-1, 1:-1] = ~filled

        def next_to(m):
            return m[:-2, 1:-1] | m[2:, 1:-1] | m[1:-1, :-2] | m[1:-1, 2:]

        to_old, to_new = filled & next_to(old_only), filled & next_to(new_only)
        both = to_old & to_new
        return to_old & ~both, to_new & ~both


# --------------------------------------------------------------------------
# Section 4: patch placement


class _Placement:
    """Chooses the exemplar window for an output window: random, entire patch or sub-patch matching."""

    def __init__(self, exemplar, output, placement, temperature, gen):
        self.ex, self.out, self.placement, self.gen = exemplar, output, placement, gen
        self.search = WindowSearch(exemplar, (output.bh, output.bw)) if placement != "random" else None
        self.positions = (exemplar.shape[0] - output.bh + 1, exemplar.shape[1] - output.bw + 1)
        variance = float(exemplar.reshape(-1, exemplar.shape[2]).var(axis=0).sum())
        self.temperature = temperature * (variance if variance > 0 else 1.0)  # the paper's k sigma^2
        self.used = set()

    def _unused(self, r0, c0):
        """Exemplar windows whose translation (output minus exemplar position) was not used before."""
        ny, nx = self.positions
        ty, tx = r0 - np.arange(ny), c0 - np.arange(nx)
        if self.out.tileable:
            ty, tx = ty % self.out.H, tx % self.out.W
        free = np.ones((ny, nx), bool)
        for uy, ux in self.used:
            free[np.ix_(ty == uy, tx == ux)] = False
        return free

    def choose(self, r0, c0, region):
        """``(top, left, cost)``: the exemplar window for the output window at ``(r0, c0)``.

        ``region`` is a bool mask over the window: the error region (sub-patch matching compares it only).
        """
        out = self.out
        rows, cols, _, _ = out.window(r0, c0)
        known = out.labels[np.ix_(rows, cols)] >= 0
        free = self._unused(r0, c0)
        if not free.any():
            free[:] = True
        if self.placement == "subpatch":
            known = known & region
        if self.placement == "random" or not known.any():
            top, left = divmod(_draw(None, free, self.temperature, self.gen), self.positions[1])
            cost = 0.0
        else:
            # C(t) = 1/|A_t| sum_{p in A_t} |I(p - t) - O(p)|^2 for every window at once (FFT)
            costs = self.search.sq_distances(out.canvas[np.ix_(rows, cols)], known) / known.sum()
            top, left = divmod(_draw(costs, free, self.temperature, self.gen), self.positions[1])
            cost = float(costs[top, left])
        ty, tx = r0 - top, c0 - left
        if out.tileable:
            ty, tx = ty % out.H, tx % out.W
        self.used.add((ty, tx))
        return top, left, cost


class _TranslationPlacement:
    """The paper's placement of the whole exemplar: among the output translations that cover the error region.

    Entire patch matching compares every covered output pixel under the placed exemplar, sub-patch matching
    those of the error region only (:class:`texsynth.core.search.TemplateSearch`, by FFT).
    """

    def __init__(self, exemplar, output, placement, temperature, gen):
        self.ex, self.out, self.placement, self.gen = exemplar, output, placement, gen
        self.search = TemplateSearch(exemplar)
        variance = float(exemplar.reshape(-1, exemplar.shape[2]).var(axis=0).sum())
        self.temperature = temperature * (variance if variance > 0 else 1.0)  # the paper's k sigma^2
        self.used = set()

    def choose(self, er, ec, eh, ew):
        """``(r0, c0, cost)``: where the exemplar goes, so that it covers the error region at ``(er, ec)``."""
        out, (bh, bw) = self.out, (self.out.bh, self.out.bw)
        r0s, c0s = er + eh - bh + np.arange(bh - eh + 1), ec + ew - bw + np.arange(bw - ew + 1)
        # the output under every such placement: rows er + eh - bh ... er + bh - 1 (and columns likewise)
        rows, cols = er + eh - bh + np.arange(2 * bh - eh), ec + ew - bw + np.arange(2 * bw - ew)
        if out.tileable:
            rows, cols = rows % out.H, cols % out.W
            r0s, c0s = r0s % out.H, c0s % out.W
            inside = np.ones((rows.size, cols.size), bool)
        else:
            inside = ((rows >= 0) & (rows < out.H))[:, None] & ((cols >= 0) & (cols < out.W))[None, :]
            rows, cols = np.clip(rows, 0, out.H - 1), np.clip(cols, 0, out.W - 1)
        box = np.ix_(rows, cols)
        known = inside & (out.labels[box] >= 0)
        if self.placement == "subpatch":  # the error region only
            region = np.zeros_like(known)
            region[bh - eh:bh, bw - ew:bw] = True
            known &= region
        free = np.ones((r0s.size, c0s.size), bool)
        for uy, ux in self.used:
            free[np.ix_(r0s == uy, c0s == ux)] = False
        if not free.any():
            free[:] = True
        if self.placement == "random" or not known.any():
            costs = None
        else:
            d, n = self.search.sq_distances(np.where(known[..., None], out.canvas[box], 0.0), known)
            costs = np.where(n > 0, d / np.maximum(n, 1), np.inf)  # C(t): mean over the overlap A_t
        a, b = divmod(_draw(costs, free, self.temperature, self.gen), c0s.size)
        r0, c0 = int(r0s[a]), int(c0s[b])
        self.used.add((r0, c0))
        return r0, c0, 0.0 if costs is None else float(costs[a, b])


def _draw(costs, free, temperature, gen):
    """A flat index among the ``free`` ones: uniform (``costs`` None), else ``P ∝ exp(-C / (k σ²))``."""
    c = None if costs is None else np.where(free, costs, np.inf)
    if c is None or not np.isfinite(c).any():
        flat = np.flatnonzero(free)
        return int(flat[gen.integers(flat.size)])
    weights = np.exp(-(c - c.min()) / temperature).ravel()  # relative to the best, for the numerical range
    return int(gen.choice(weights.size, p=weights / weights.sum()))


def _error_region_at_first_empty(output, overlap):
    """While covering with the whole exemplar: a region of ``2 overlap`` pixels whose centre is the first empty
    pixel in raster order (straddling filled and empty output)."""
    empty = np.flatnonzero(output.labels.ravel() < 0)
    r, c = divmod(int(empty[0]), output.W)
    eh, ew = min(2 * overlap, output.bh, output.H), min(2 * overlap, output.bw, output.W)
    er, ec = r - overlap, c - overlap
    if output.tileable:
        return er % output.H, ec % output.W, eh, ew
    return min(max(er, 0), output.H - eh), min(max(ec, 0), output.W - ew), eh, ew


def _first_empty_window(output, overlap):
    """The output window of the next covering patch: the first empty pixel in raster order ``overlap`` pixels
    inside it (the error region straddles filled and empty output), and the error region around that pixel."""
    empty = np.flatnonzero(output.labels.ravel() < 0)
    r, c = divmod(int(empty[0]), output.W)
    if output.tileable:
        r0, c0 = (r - overlap) % output.H, (c - overlap) % output.W
        dr, dc = overlap, overlap
    else:
        r0 = min(max(r - overlap, 0), output.H - output.bh)
        c0 = min(max(c - overlap, 0), output.W - output.bw)
        dr, dc = r - r0, c - c0
    return r0, c0, _region_mask(output, dr, dc)


def _region_mask(output, dr, dc):
    """The error region: a window of half the block centred on ``(dr, dc)`` of the block window."""
    eh, ew = max(1, round(output.bh * REGION_FRACTION)), max(1, round(output.bw * REGION_FRACTION))
    r1 = min(max(dr - eh // 2, 0), output.bh - eh)
    c1 = min(max(dc - ew // 2, 0), output.bw - ew)
    region = np.zeros((output.bh, output.bw), bool)
    region[r1:r1 + eh, c1:c1 + ew] = True
    return region


def _worst_region(output, tries):
    """Refinement's error region ``(er, ec, eh, ew, score)``: the window of half the patch of highest seam cost.

    Every seam pair's cost goes half to each of its pixels; a pixel's cost is divided by one plus the
    number of refinement patches placed over it already, so regions that could not be improved give way.
    """
    s, t, costs = output.seam_costs()
    per_pixel = np.zeros(output.H * output.W)
    np.add.at(per_pixel, s, costs / 2)
    np.add.at(per_pixel, t, costs / 2)
    per_pixel = per_pixel.reshape(output.H, output.W) / (1.0 + tries)
    eh, ew = max(1, round(output.bh * REGION_FRACTION)), max(1, round(output.bw * REGION_FRACTION))
    eh, ew = min(eh, output.H), min(ew, output.W)
    score = _box_sums(per_pixel, eh, ew, output.tileable)
    er, ec = np.unravel_index(int(np.argmax(score)), score.shape)
    return int(er), int(ec), eh, ew, float(score[er, ec])


def _worst_window(output, tries):
    """Refinement with blocks: the block window centred on the error region of highest seam cost."""
    er, ec, eh, ew, score = _worst_region(output, tries)
    if output.tileable:
        r0, c0 = (er - (output.bh - eh) // 2) % output.H, (ec - (output.bw - ew) // 2) % output.W
    else:
        r0 = min(max(er - (output.bh - eh) // 2, 0), output.H - output.bh)
        c0 = min(max(ec - (output.bw - ew) // 2, 0), output.W - output.bw)
    dr, dc = (er - r0) % output.H + eh // 2, (ec - c0) % output.W + ew // 2
    return r0, c0, _region_mask(output, dr, dc), score


def _box_sums(image, eh, ew, wrap):
    """``out[r, c]`` = the sum of ``image`` over the ``eh x ew`` window whose top-left pixel is ``(r, c)``
    (windows wrap round for tileable output; plain output: windows inside the image only)."""
    if wrap:
        padded = np.pad(image, ((0, eh - 1), (0, ew - 1)), mode="wrap")
    else:
        padded = image
    sums = np.cumsum(np.cumsum(np.pad(padded, ((1, 0), (1, 0))), 0), 1)
    return sums[eh:, ew:] - sums[:-eh, ew:] - sums[eh:, :-ew] + sums[:-eh, :-ew]


# --------------------------------------------------------------------------
# The method


def _resolve(preset, exemplar_shape, placement, block, overlap, temperature, edge_cost, refine):
    """The options with every ``"auto"`` replaced by the preset's value, checked."""
    defaults = DEFAULTS[_check_choice(preset, "preset", PRESETS)]
    placement = _check_choice(defaults["placement"] if is_auto(placement) else placement, "placement", PLACEMENTS)
    B = _check_block(block, exemplar_shape, defaults["block_fraction"])
    O = _check_overlap(overlap, min(exemplar_shape) if B == "whole" else B)
    temperature = (defaults["temperature"] if is_auto(temperature)
                   else check_positive_float(temperature, "temperature", maximum=1e6))
    edge_cost = edge_cost_function(defaults["edge_cost"] if is_auto(edge_cost) else edge_cost)
    refine = defaults["refine"] if is_auto(refine) else check_positive_int(refine, "refine", minimum=0)
    if refine > MAX_REFINE:
        raise ValueError(f"refine must be at most {MAX_REFINE} passes (later passes change next to nothing; the "
                         f"default is 2), got {refine}")
    return placement, B, O, temperature, edge_cost, refine


def graphcut_texture(exemplar, size, *, preset="default", placement="auto", block="auto", overlap="auto",
                     temperature="auto", edge_cost="auto", refine="auto", tileable=False, rng=None, return_info=False,
                     progress=False):
    """Synthesise a texture by graph-cut textures (Kwatra et al. 2003).

    Examples
    --------
    >>> import texsynth
    >>> brick = texsynth.data.load("brick")[:64, :64]
    >>> out, info = texsynth.graphcut_texture(brick, 96, block=32, refine=1, rng=0, return_info=True)
    >>> out.shape, info.block
    ((96, 96, 3), 32)

    Covers the output with patches of the exemplar, each placed where it
    matches what is already there (Section 4) and joined to it along the
    cheapest seam, a minimum graph cut (Section 3), then pastes further
    patches over the costliest seams (refinement) [1]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture: ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    size : int or (int, int)
        Output size ``(height, width)``.
    preset : {"default", "paper"}
        Where the options left ``"auto"`` come from. ``"default"``: half-exemplar
        blocks, entire patch matching with ``temperature=0.02``, the plain cost ``M``
        and two refinement passes (chosen by looking at 256 -> 512 px
        outputs). ``"paper"``: the paper's patch, the whole exemplar placed at
        output translations (``block="whole"``), entire patch matching,
        ``temperature=0.01``, ``M``, one refinement pass.
    placement : {"entire", "subpatch", "random", "auto"}
        How a patch's exemplar window is chosen (Section 4): entire patch
        matching (the whole overlap compared), sub-patch matching (the error
        region only), or random placement.
    block : int, "whole" or "auto"
        Side of the square patches, at most the exemplar's shorter side
        (``"auto"``: half of it), or ``"whole"``: the whole exemplar is the patch
        and the search runs over the output translations that put it over
        the error region (the paper's placement; ``preset="paper"``).
    overlap : int or "auto"
        While the output is being covered, how far (pixels) each new patch
        reaches back over what is filled, ``1 <= overlap < block``.
        ``"auto"``: a third of the block.
    temperature : float or "auto"
        How random the choice of patch positions is: small values take the
        best matches only, large ones approach random placement. It is the
        paper's ``k`` of ``P(t) ∝ exp(-C(t) / (k σ²))``, the temperature of
        the draw relative to the exemplar's variance ``σ²`` (the
        paper varies it from 0.001 to 1). ``"auto"``: 0.02 (``"paper"``: 0.01).
    edge_cost : {"plain", "gradient", "auto"} or callable
        The cost of a seam between neighbours: the paper's ``M``
        (:func:`~texsynth.core.seams.matching_cost`, default),
        its gradient-normalised ``M'``
        (:func:`~texsynth.core.seams.gradient_matching_cost`), or any
        ``edge_cost(a_s, a_t, b_s, b_t)``.
    refine : int or "auto"
        Refinement passes after the output is covered; each places as many
        patches as it takes to cover the output once on the block grid
        (``ceil(H / (block - overlap)) * ceil(W / (block - overlap))``), over
        the regions of highest seam cost.
        ``"auto"``: 2 (``"paper"``: 1); 0 stops once the output is covered.
    tileable : bool
        Make the output tile seamlessly: windows, seams and costs wrap round
        its border. Needs a size of at least the block plus 2 pixels.
    rng : None, int or numpy.random.Generator
        Random source for the placements; an int seed reproduces the output
        bit for bit.
    return_info : bool
        Also return a :class:`GraphcutInfo`.
    progress : bool or callable
        Report progress per patch (True: tqdm bar; a callable receives
        ``(step, total, info)`` with the total seam cost).

    Returns
    -------
    image : numpy.ndarray
        ``(height, width)`` or ``(height, width, C)``, the exemplar's channel
        layout; float32 for float32 input, float64 otherwise. Every pixel is a
        copy of an exemplar pixel.
    info : GraphcutInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        If ``block`` is larger than the exemplar (or below 4, or a word other
        than ``"whole"``), ``overlap >=
        block``, ``temperature <= 0``, ``refine`` outside 0..100, an option is not one of its
        choices, a tileable ``size`` is smaller than the block plus 2, or the
        output would not fit in memory.

    Notes
    -----
    *Placement* (Section 4). While covering, the output window is put so that
    the first empty pixel in raster order lies ``overlap`` pixels inside it;
    during refinement it is centred on the window of half the block with the
    highest seam cost (with ``block="whole"``: the error region is
    ``2 overlap`` pixels centred on the first empty pixel, or that window of
    half the exemplar, and the exemplar goes to one of the translations that
    cover it). The cost of every exemplar window (translation) ``t`` is

    .. math:: C(t) = \\frac{1}{|A_t|} \\sum_{p \\in A_t} |I(p - t) - O(p)|^2

    over the covered pixels ``A_t`` of the output window (``"subpatch"``:
    those of the error region), all at once by FFT correlation, and one is
    drawn with

    .. math:: P(t) \\propto \\exp\\left(-\\frac{C(t)}{k \\sigma^2}\\right)

    (``σ²`` the variance of the exemplar's values summed over channels) among
    the translations not used before.

    *Fitting* (Section 3). :func:`texsynth.core.seams.graph_cut` labels the
    overlap old or new by a minimum cut with the matching cost

    .. math:: M(s, t, A, B) = \\|A(s) - B(s)\\| + \\|A(t) - B(t)\\|

    or ``M' = M / (||G^d_A(s)|| + ||G^d_A(t)|| + ||G^d_B(s)|| + ||G^d_B(t)||)``;
    overlap pixels next to old-only output are tied to ``A``, those next to
    new-only pixels to ``B``, and every old seam gets a seam node whose arcs
    are ``M(s, t, A_s, B)``, ``M(s, t, B, A_t)`` and ``M(s, t, A_s, A_t)``. In
    refinement the whole window is covered: its border is tied to ``A`` and
    the seam nodes connect its inside to ``B`` ("surrounded regions"), so the
    cut keeps the old output unless the new patch lowers the seam cost; with
    ``M`` (a metric, so the seam nodes charge exactly the seams kept) the
    total seam cost (``info.energy``) never rises there, as in the example
    above:

    >>> bool(np.all(np.diff(info.energy[info.stage == 1]) <= 1e-9))
    True

    *Blocks and the whole input.* The paper pastes the whole input at an
    output translation (``block="whole"``: the translations that cover the
    error region are searched by :class:`texsynth.core.search.TemplateSearch`).
    By default a ``block`` window of the exemplar is pasted at an output
    window chosen around the error region instead, and the search runs over
    the exemplar's windows (:class:`texsynth.core.search.WindowSearch`): the
    same question with the roles of output and exemplar exchanged. With the
    whole input as the patch, a 256 px exemplar in a 512 px output shows up
    in large verbatim pieces; half-exemplar blocks copy at most a quarter of
    its area in one piece. The paper's values of ``k``, of the refinement
    length and of the error region are not known here.

    Graph-cut textures work from stochastic to structured textures; their
    seams follow the texture's own edges. They fail where no exemplar window
    continues the output (structures larger than the block, strong
    perspective), and on smooth gradients, where every seam shows.

    References
    ----------
    .. [1] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
       textures: image and video synthesis using graph cuts", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 277-286. :doi:`10.1145/882262.882264`
    """
    started = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey = with_channels(image)
    size = as_size(size)
    placement, B, O, temperature, cost_fn, refine = _resolve(preset, ex.shape[:2], placement, block, overlap,
                                                             temperature, edge_cost, refine)
    tileable = check_bool(tileable, "tileable")
    whole = B == "whole"
    patch_shape = ex.shape[:2] if whole else (B, B)
    if tileable and (size[0] < patch_shape[0] + 2 or size[1] < patch_shape[1] + 2):
        raise ValueError(f"size {size} is too small for tileable output with block {B} ({patch_shape[0]}x"
                         f"{patch_shape[1]}): every side must be at least the patch's + 2; pass a larger size or a "
                         f"smaller block")
    gen = as_rng(rng)
    # the canvas, labels and seam maps (about a dozen image-sized arrays), and the exemplar's spectra
    check_memory(float(size[0]) * size[1] * (ex.shape[2] * 8 * 4 + 96), size, "size")
    exf = np.ascontiguousarray(ex, dtype=np.float64)
    output = _Output(exf, size, patch_shape, tileable, cost_fn, whole)
    chooser = (_TranslationPlacement if whole else _Placement)(exf, output, placement, temperature, gen)
    step_h, step_w = patch_shape[0] - O, patch_shape[1] - O
    covers = size[0] > patch_shape[0] or size[1] > patch_shape[1]
    per_pass = math.ceil(size[0] / step_h) * math.ceil(size[1] / step_w) if covers else 1
    records, energy, stages, timing = [], [], [], {"cut": 0.0}
    stage_seconds = {}

    def place(r0, c0, region, stage, bar):
        if whole:  # region: the error region (er, ec, eh, ew); the exemplar's translation is chosen
            r0, c0, cost = chooser.choose(*region)
            top = left = 0
        else:  # region: a mask over the block window at (r0, c0); the exemplar window is chosen
            top, left, cost = chooser.choose(r0, c0, region)
        t1 = time.perf_counter()
        changed = output.paste(r0, c0, top, left)
        timing["cut"] += time.perf_counter() - t1
        total = float(output.seam_costs()[2].sum())
        records.append((cost, changed))
        energy.append(total)
        stages.append(stage)
        if bar is not None:
            bar.advance({"seam cost": total})

    with Progress(progress, per_pass * (1 + refine), "graphcut") as bar:
        t_stage = time.perf_counter()
        n_cover = 0
        while (output.labels < 0).any():  # cover the output
            if whole:
                r0 = c0 = None
                region = _error_region_at_first_empty(output, O)
            else:
                r0, c0, region = _first_empty_window(output, O)
            n_cover += 1
            place(r0, c0, region, 0, bar if n_cover <= per_pass else None)  # (the bar counts per_pass)
        if n_cover < per_pass:
            bar.advance({"seam cost": energy[-1]}, n=per_pass - n_cover)
        stage_seconds["cover"] = time.perf_counter() - t_stage
        tries = np.zeros(size)
        for p in range(1, refine + 1):  # place patches over the regions of highest seam cost
            t_stage = time.perf_counter()
            for _ in range(per_pass):
                if whole:
                    er, ec, eh, ew, score = region = _worst_region(output, tries)
                    region, r0, c0 = region[:4], None, None
                    rows, cols = (er + np.arange(eh)) % size[0], (ec + np.arange(ew)) % size[1]
                else:
                    r0, c0, region, score = _worst_window(output, tries)
                    rows, cols, _, _ = output.window(r0, c0)
                if score <= 0:  # no seam left
                    bar.advance({"seam cost": energy[-1]})
                    continue
                tries[np.ix_(rows, cols)] += 1
                place(r0, c0, region, p, bar)
            stage_seconds[f"refine {p}"] = time.perf_counter() - t_stage

    out = restore_channels(np.clip(output.canvas, 0.0, 1.0).astype(image.dtype, copy=False), grey)
    if not return_info:
        return out
    rec = np.array(records, dtype=np.float64).reshape(-1, 2)
    return out, GraphcutInfo(corners=np.array(output.corners, dtype=np.int64).reshape(-1, 2),
                             sources=np.array(output.sources, dtype=np.int64).reshape(-1, 2), costs=rec[:, 0],
                             changed=rec[:, 1].astype(np.int64), labels=output.labels.copy(), n_initial=n_cover,
                             block=min(patch_shape) if whole else B, overlap=O, seam_cost=float(energy[-1]) if energy else 0.0,
                             energy=np.array(energy), stage=np.array(stages, dtype=np.int64),
                             seconds=time.perf_counter() - started, stage_seconds=stage_seconds,
                             cut_seconds=timing["cut"], coordinates=output.coordinates())


# --------------------------------------------------------------------------
# Interactive merging


def graphcut_merge(a, b, *, from_a, from_b, edge_cost="gradient", return_info=False):
    """Merge two images along the cheapest seam, keeping the pixels the user marked (Kwatra et al. 2003).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> a, b = texsynth.data.load("brick")[:48, :64], texsynth.data.load("wood")[:48, :64]
    >>> from_a, from_b = np.zeros((48, 64), bool), np.zeros((48, 64), bool)
    >>> from_a[:, :8], from_b[:, -8:] = True, True  # the left strip from a, the right one from b
    >>> merged, info = texsynth.graphcut_merge(a, b, from_a=from_a, from_b=from_b, return_info=True)
    >>> bool(np.array_equal(merged[:, :8], a[:, :8])), info.labels.shape
    (True, (48, 64))

    Every pixel comes from ``a`` or ``b``: one minimum graph cut puts the
    seam between them where it costs least under ``edge_cost`` and keeps the
    marked pixels from their image (the interactive merging of graph-cut
    textures [1]_).

    Parameters
    ----------
    a, b : array_like
        The two images, of one shape ``(H, W)`` or ``(H, W, C)`` (placed
        where they should overlap: crop or pad them first).
    from_a, from_b : array_like of bool, shape (H, W)
        Pixels that must come from ``a`` and from ``b`` (the user's strokes);
        no pixel may be in both, and each must mark at least one pixel.
    edge_cost : {"gradient", "plain"} or callable
        The seam's cost between neighbours: the gradient-normalised ``M'``
        (default: seams hide in busy regions and along edges), the plain
        ``M``, or any ``edge_cost(a_s, a_t, b_s, b_t)``.
    return_info : bool
        Also return a :class:`GraphcutMergeInfo` with the label map.

    Returns
    -------
    image : numpy.ndarray
        The merged image, the inputs' shape; float32 if both are float32,
        float64 otherwise. Pixels of ``from_a`` are ``a``'s, those of
        ``from_b`` are ``b``'s, exactly.
    info : GraphcutMergeInfo
        Only with ``return_info=True``; ``info.labels`` is True where the
        merged image comes from ``b``.

    Raises
    ------
    ValueError, TypeError
        If the images differ in shape, a mask has the wrong shape or is not
        binary, a pixel is in both masks, or a mask marks nothing.

    Notes
    -----

    The paper's interactive merging (the lecture's "Interactive Merging"):
    one graph cut (:func:`texsynth.core.seams.graph_cut`) over
    every pixel with ``a`` as the source terminal and ``b`` as the sink, the
    user's pixels tied to their image by infinite arcs. The seam is the
    cheapest under ``edge_cost``; with ``M'`` it prefers places where the
    images agree or where both have strong gradients.

    References
    ----------
    .. [1] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
       textures: image and video synthesis using graph cuts", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 277-286. :doi:`10.1145/882262.882264`
    """
    started = time.perf_counter()
    ia, ib = as_image(a, "a"), as_image(b, "b")
    if ia.shape != ib.shape:
        raise ValueError(f"a and b must have the same shape, got {ia.shape} and {ib.shape}; crop or pad them to "
                         f"where they overlap first")
    shape = ia.shape[:2]
    keep_a, keep_b = _check_mask(from_a, shape, "from_a"), _check_mask(from_b, shape, "from_b")
    check_disjoint(keep_a, keep_b, ("from_a", "from_b"),
                   "a pixel can come from one image only: remove it from one of the masks")
    for name, m in (("from_a", keep_a), ("from_b", keep_b)):
        if not m.any():
            raise ValueError(f"{name} marks no pixel; mark at least one pixel that must come from "
                             f"{name[-1]} (without one the merge is simply the other image)")
    cost_fn = edge_cost_function(edge_cost)
    check_memory(256.0 * shape[0] * shape[1], shape, "a", "the graph of the cut")
    va, vb = with_channels(ia)[0].astype(np.float64), with_channels(ib)[0].astype(np.float64)
    t0 = time.perf_counter()
    from_b_side, cost = graph_cut(va, vb, old_mask=keep_a, new_mask=keep_b, edge_cost=cost_fn)
    cut_seconds = time.perf_counter() - t0
    merged = np.where(from_b_side.reshape(shape + (1,) * (ia.ndim - 2)), ib, ia)
    dtype = np.float32 if ia.dtype == ib.dtype == np.float32 else np.float64
    merged = merged.astype(dtype, copy=False)
    if not return_info:
        return merged
    return merged, GraphcutMergeInfo(labels=from_b_side, seam_cost=cost, energy=np.array([cost]),
                                     stage=np.zeros(1, dtype=np.int64), seconds=time.perf_counter() - started,
                                     stage_seconds={"cut": cut_seconds})
