"""Efros & Freeman's image quilting: overlapping blocks joined along minimum-error boundary cuts.

Image quilting (Efros & Freeman 2001, Section 2) covers the output with square
blocks of the exemplar on a grid, in raster order, each overlapping its
already placed neighbours by ``overlap`` pixels:

1. every block of the exemplar is scored by its *overlap error*, the sum of
   squared differences with what the output already shows in the overlap
   (left strip, top strip, or both: the L-shaped case);
2. one block is drawn at random among those whose error is within
   ``error_tolerance`` (the paper's 0.1) of the best;
3. it is pasted on its side of the *minimum-error boundary cut*, the cheapest
   seam through the overlap's error surface
   ``E_ij = e_ij + min(E_{i-1,j-1}, E_{i-1,j}, E_{i-1,j+1})``
   (:mod:`texsynth.core.seams`); in the L-shaped case a vertical and a
   horizontal cut, the block keeping what lies beyond both.

Section 3's *texture transfer* renders a pattern image in the texture: the
error of a block becomes ``alpha`` times the overlap error plus ``1 - alpha``
times the squared difference between the correspondence maps (luminance) of
the block and of the pattern under it, over ``N`` passes with blocks a third
smaller each time, ``alpha_i = 0.8 (i - 1) / (N - 1) + 0.1``, and from the
second pass on the block matched against the previous pass's whole block too.

The overlap error of every exemplar block at once is a masked template search
(:class:`texsynth.core.search.WindowSearch`, FFT correlation), the paper's
suggestion for speed; the cuts are :func:`texsynth.core.seams.minimum_error_boundary`.
The block grid and its raster loop here are shared with patch-based sampling
(:mod:`texsynth.patch._patch_sampling`), which blends its boundary zones instead.

What could not be checked against the paper's text (it was not at hand;
the steps and defaults follow its published description, as an ETH report
and tutorial pages quote it): the exact form of the
tolerance (taken on the squared error), how the L-shaped cuts are combined
(here: the block keeps the pixels beyond both cuts), the number of transfer
passes (3 here), and the weighting of overlap and correspondence errors
(here both are mean squared errors per pixel and channel, so ``alpha`` means
the same for every block size).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (
    MAX_ITERATIONS,
    as_image,
    as_rng,
    as_size,
    check_bool,
    check_in_range,
    check_memory,
    check_positive_float,
    check_positive_int,
    restore_channels,
    with_channels,
)
from ..core.seams import minimum_error_boundary, seam_mask
from ..core.search import WindowSearch, is_auto, window_search, within_tolerance
from ._patchwork_transfer import prescale_pattern

__all__ = ["QuiltInfo", "QuiltTransferInfo", "quilt", "quilt_transfer"]

OVERLAP_FRACTION = 1 / 6  # the paper's overlap: a sixth of the block
ERROR_TOLERANCE = 0.1  # blocks within 10 % of the best overlap error qualify (Section 2.1)
BLOCK_FRACTION = 1 / 4  # default block: a quarter of the exemplar's shorter side
TRANSFER_SHRINK = 2 / 3  # transfer: each pass's block is a third smaller (Section 3)
TRANSFER_ITERATIONS = 3


@dataclass
class QuiltInfo:
    """What :func:`quilt` (or one pass of :func:`quilt_transfer`) chose, block by block in raster order.

    Attributes
    ----------
    corners : numpy.ndarray
        ``(n, 2)`` int, the top-left pixel of each block in the output
        (for tileable output, modulo the output size).
    sources : numpy.ndarray
        ``(n, 2)`` int, the top-left pixel of the exemplar block pasted there.
    errors : numpy.ndarray
        ``(n,)``, the chosen block's error: the overlap's sum of squared
        differences (synthesis) or the combined mean squared error
        (transfer); 0 for blocks with nothing to match.
    best_errors : numpy.ndarray
        ``(n,)``, the smallest error of any exemplar block at that place.
    candidates : numpy.ndarray
        ``(n,)`` int, how many exemplar blocks were within the tolerance.
    block, overlap : int
        The block side and the overlap width of the grid.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"search"`` (scoring every exemplar block) and ``"paste"`` (cuts and
        pasting); transfer passes as ``"pass 1"``, ``"pass 2"``, ...
    coordinates : numpy.ndarray
        The source-coordinate map (``docs/conventions.md``): ``(H, W, 2)``
        int, the exemplar pixel ``(row, col)`` each output pixel was copied
        from (after the cuts); for a method that blends
        (:func:`~texsynth.patch.patch_sampling`), ``(H, W, K, 2)`` with
        ``weights``. Render other channels through it with
        :func:`texsynth.apply_coordinates`.
    weights : numpy.ndarray or None
        ``(H, W, K)`` blend weights, largest first, summing to 1 (None where
        every pixel is a copy).
    """

    corners: np.ndarray
    sources: np.ndarray
    errors: np.ndarray
    best_errors: np.ndarray
    candidates: np.ndarray
    block: int
    overlap: int
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None


@dataclass
class QuiltTransferInfo:
    """What :func:`quilt_transfer` did, pass by pass.

    Attributes
    ----------
    passes : list of QuiltInfo
        One per iteration, in order (block sizes shrinking).
    alphas : numpy.ndarray
        ``alpha_i`` of each pass.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"pass 1"``, ``"pass 2"``, ...: the wall time of each pass.
    """

    passes: list
    alphas: np.ndarray
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)

    @property
    def coordinates(self):
        """``(H, W, 2)``: the texture pixel each output pixel was copied from (the last pass's map)."""
        return self.passes[-1].coordinates

    @property
    def weights(self):
        """None: every pixel of a transfer is a copy."""
        return self.passes[-1].weights


# --------------------------------------------------------------------------
# Checks


def check_block(block, exemplar_shape, name="exemplar"):
    """The block side: ``"auto"`` is a quarter of the exemplar's shorter side; never larger than the exemplar."""
    shortest = min(exemplar_shape)
    if is_auto(block):
        return max(2, min(shortest, round(shortest * BLOCK_FRACTION)))
    b = check_positive_int(block, "block", minimum=2)
    if b > shortest:
        raise ValueError(
            f"block {b} is larger than the {name} ({exemplar_shape[0]}x{exemplar_shape[1]}); pass block <= "
            f"{shortest} (a quarter of it, {max(2, round(shortest * BLOCK_FRACTION))}, is a good start) "
            f"or a larger {name}"
        )
    return b


def check_overlap(overlap, block):
    """The overlap width: ``"auto"`` is a sixth of the block (the paper's); it must be smaller than the block."""
    if is_auto(overlap):
        return max(1, round(block * OVERLAP_FRACTION))
    o = check_positive_int(overlap, "overlap", minimum=0)
    if o >= block:
        raise ValueError(
            f"overlap {o} must be smaller than block {block} (the paper uses block / 6 = "
            f"{max(1, round(block * OVERLAP_FRACTION))}); pass overlap < {block} or a larger block"
        )
    return o


def check_tolerance(error_tolerance, name="error_tolerance", paper=ERROR_TOLERANCE):
    if isinstance(error_tolerance, (int, float, np.integer, np.floating)) and not isinstance(error_tolerance, bool) \
            and error_tolerance < 0:
        raise ValueError(
            f"{name} must be >= 0 (the paper's {paper} accepts blocks within {paper:.0%} of the best error; 0 "
            f"takes only the best), got {error_tolerance}"
        )
    # (1e6 times the best error already admits every block; far beyond, the products overflow)
    return check_positive_float(error_tolerance, name, allow_zero=True, maximum=1e6)


# --------------------------------------------------------------------------
# The block grid, visited in raster order (shared with patch-based sampling)


class Grid:
    """Block corners along both axes and the canvas they cover.

    Plain output: corners ``k (B - O)`` and a canvas ``(n - 1)(B - O) + B``
    long, cropped to the output size at the end (the paper's ``n(B - O) + O``).
    Tileable output: the canvas is the output itself, indexed modulo its size;
    ``n = ceil(size / (B - O))`` corners spread evenly round it, so every step is
    at most ``B - O`` (overlaps of ``O`` or a pixel more) and the last blocks
    overlap the first ones across the border.
    """

    def __init__(self, size, block, overlap, tileable):
        self.block = block
        self.tileable = tileable
        step = block - overlap
        check_memory(16.0 * (size[0] / step + 2) * (size[1] / step + 2), tuple(size), "size", "the block grid")
        axes = [self._axis(n, block, overlap, tileable) for n in size]
        (self.rows, self.canvas_h), (self.cols, self.canvas_w) = axes
        self.canvas_shape = (self.canvas_h, self.canvas_w)
        self.n_blocks = len(self.rows) * len(self.cols)

    @staticmethod
    def _axis(length, block, overlap, tileable):
        step = block - overlap
        if not tileable:
            n = max(1, math.ceil((length - block) / step) + 1)
            corners = np.arange(n) * step
            return corners, int(corners[-1] + block)
        n = max(2, math.ceil(length / step))
        corners = np.round(np.arange(n) * length / n).astype(np.int64)
        steps = np.diff(np.r_[corners, length])
        if np.min(steps + np.roll(steps, 1)) <= block:  # a block's two neighbours would cover all of it
            raise ValueError(
                f"size {length} is too small for tileable output with block {block} and overlap {overlap}: "
                f"a block's neighbours on both sides would cover it whole; pass a larger size, a smaller "
                f"overlap or a smaller block"
            )
        return corners, int(length)

    def window(self, r, c):
        """Index arrays (for ``np.ix_``) of the block whose top-left pixel is ``(r, c)``."""
        b = np.arange(self.block)
        return np.ix_((r + b) % self.canvas_h, (c + b) % self.canvas_w)

    def corners(self):
        return np.stack(np.meshgrid(self.rows, self.cols, indexing="ij"), -1).reshape(-1, 2)


def overlap_widths(known):
    """Widths of the known strips along the block's left, top, right and bottom sides."""
    def leading(full):
        return full.size if full.all() else int(np.argmin(full))

    cols, rows = known.all(axis=0), known.all(axis=1)
    return leading(cols), leading(rows), leading(cols[::-1]), leading(rows[::-1])


class _SourceMap:
    """Which exemplar pixels every canvas pixel shows, and with what weights: the source-coordinate map.

    Bookkeeping beside the canvas (it never changes what is pasted). Cuts (bool
    joins) keep one flat exemplar index per pixel. Blends keep up to ``slots``
    (flat exemplar index, weight) pairs per pixel: pasting a block with weight
    ``w`` scales the pixel's weights by ``1 - w`` and adds the new source with
    ``w``, exactly as the canvas takes ``(1 - w) old + w new``; a pixel the new
    block takes whole (``w = 1``) starts over.
    """

    def __init__(self, grid, exemplar_shape):
        self.grid = grid
        self.width = exemplar_shape[1]
        self.block = np.arange(grid.block)
        self.index = self.weight = self.count = None

    def _start(self, blend):
        shape = self.grid.canvas_shape
        if not blend:
            self.index = np.zeros(shape + (1,), np.intp)
            return
        coverage = np.zeros(shape, np.intp)
        for r, c in self.grid.corners():
            coverage[self.grid.window(r, c)] += 1
        self.index = np.zeros(shape + (int(coverage.max()),), np.intp)
        self.weight = np.zeros(shape + (int(coverage.max()),))
        self.count = np.zeros(shape, np.intp)

    def paste(self, window, top, left, weight):
        blend = weight.dtype != np.bool_
        if self.index is None:
            self._start(blend)
        source = (top + self.block)[:, None] * self.width + (left + self.block)[None, :]
        if not blend:  # a cut: the pixels the new block takes show its exemplar pixels
            index = self.index[window][..., 0]
            index[weight] = source[weight]
            self.index[window] = index[..., None]
            return
        w = weight.astype(np.float64)
        index, wt, count = self.index[window], self.weight[window], self.count[window]
        wt *= (1.0 - w)[..., None]
        whole = w == 1.0
        count[whole] = 0
        wt[whole] = 0.0
        take = w > 0
        rows, cols = np.nonzero(take)
        slot = count[rows, cols]
        index[rows, cols, slot] = source[rows, cols]
        wt[rows, cols, slot] = w[rows, cols]
        count[take] += 1
        self.index[window], self.weight[window], self.count[window] = index, wt, count

    def result(self, size):
        """``(coordinates, weights)`` of the output ``size``: ``(H, W, 2)`` and None where every pixel is a copy."""
        from ..core.coordinates import compact_slots

        index = self.index[: size[0], : size[1]]
        coords = np.stack(np.divmod(index, self.width), -1).astype(np.int64)
        if self.weight is None:
            return coords[:, :, 0], None
        coords, weight = compact_slots(coords, self.weight[: size[0], : size[1]])
        if coords.shape[2] == 1 and np.all(weight == 1.0):
            return coords[:, :, 0], None
        return coords, weight


def paste_blocks(exemplar, grid, choose, join, progress, desc, track=False):
    """Visit the grid in raster order and paste one exemplar block per position.

    ``choose(window, region, known) -> (top, left, error, best, candidates)`` picks the
    exemplar block for the output pixels ``window`` (which show ``region``, known
    where ``known``); ``join(region, block, known) -> weight`` says how much of the
    new block each pixel takes (bool for a cut, float for a blend).
    Returns the canvas and the records of :class:`QuiltInfo`, plus the seconds spent choosing
    and, with ``track``, the :class:`_SourceMap` (else None).
    """
    B = grid.block
    canvas = np.zeros(grid.canvas_shape + (exemplar.shape[2],))
    filled = np.zeros(grid.canvas_shape, dtype=bool)
    records, searching = [], 0.0
    sources = _SourceMap(grid, exemplar.shape[:2]) if track else None
    with Progress(progress, grid.n_blocks, desc) as bar:
        for r, c in grid.corners():
            window = grid.window(r, c)
            region, known = canvas[window], filled[window]
            started = time.perf_counter()
            top, left, *scores = choose(window, region, known)
            searching += time.perf_counter() - started
            block = exemplar[top : top + B, left : left + B]
            weight = join(region, block, known)
            if weight.dtype == np.bool_:
                region[weight] = block[weight]
            else:
                region += weight[..., None] * (block - region)
            canvas[window] = region
            filled[window] = True
            if sources is not None:
                sources.paste(window, top, left, weight)
            records.append((top, left, *scores))
            bar.advance()
    return canvas, records, searching, sources


def _draw(distances, error_tolerance, gen):
    """One block drawn uniformly among those within the tolerance: (row, col, error, best, candidates)."""
    chosen = within_tolerance(distances, error_tolerance)
    k = int(chosen[gen.integers(chosen.size)])
    top, left = divmod(k, distances.shape[1])
    return top, left, float(distances.flat[k]), float(distances.min()), int(chosen.size)


def quilt_info(grid, records, overlap, started, searching, source_map=None, size=None):
    rec = np.array(records, dtype=np.float64).reshape(-1, 5)
    total = time.perf_counter() - started
    coordinates, weights = source_map.result(size) if source_map is not None else (None, None)
    return QuiltInfo(corners=grid.corners(), sources=rec[:, :2].astype(np.int64), errors=rec[:, 2],
                     best_errors=rec[:, 3], candidates=rec[:, 4].astype(np.int64), block=grid.block,
                     overlap=overlap, seconds=total, stage_seconds={"search": searching, "paste": total - searching},
                     coordinates=coordinates, weights=weights)


# --------------------------------------------------------------------------
# Section 2.1: the minimum-error boundary cut


def _boundary_cut(old, new, known):
    """Which pixels of a block the new block takes after the minimum-error boundary cuts (Section 2.1).

    Along every side of the block whose strip is already known (left, top,
    and, for tileable output, right and bottom) the cheapest seam through the
    error surface ``e = ||old - new||^2`` of that strip is cut; the new block
    keeps the pixels beyond every seam (the seam's own pixels included), the
    old output the rest. Unknown pixels always take the new block.
    """
    return cut_through(((old - new) ** 2).sum(-1), known)


def cut_through(e, known):
    """:func:`_boundary_cut` for a given error surface ``e`` ``(h, w)`` of the block: the pixels the new block
    takes after the cheapest seam through every known strip (near-regular synthesis weights ``e`` first)."""
    h, w = known.shape
    take = np.ones((h, w), dtype=bool)
    left, top, right, bottom = overlap_widths(known)
    if left:
        take[:, :left] &= ~seam_mask(minimum_error_boundary(e[:, :left]), (h, left))
    if right:
        take[:, w - right:] &= seam_mask(minimum_error_boundary(e[:, w - right:]) + 1, (h, right))
    if top:
        seam = minimum_error_boundary(e[:top], direction="horizontal")
        take[:top] &= ~seam_mask(seam, (top, w), direction="horizontal")
    if bottom:
        seam = minimum_error_boundary(e[h - bottom:], direction="horizontal")
        take[h - bottom:] &= seam_mask(seam + 1, (bottom, w), direction="horizontal")
    return take


def _paste_over(old, new, known):
    """Figure 1(b): the new block simply covers the overlap."""
    return np.ones(known.shape, dtype=bool)


def check_canvas_memory(grid, channels, exemplar_shape, name="size", value=None):
    """The canvas (float64), its filled mask, and the exemplar's spectra."""
    h, w = grid.canvas_shape
    eh, ew = exemplar_shape
    check_memory(float(h) * w * (channels * 8 * 2 + 1) + 16.0 * eh * ew * (channels + 4) * 2,
                 value if value is not None else grid.canvas_shape, name)


def finish(canvas, size, dtype, was_grey):
    out = np.clip(canvas[: size[0], : size[1]], 0.0, 1.0)
    return restore_channels(out.astype(dtype, copy=False), was_grey)


def quilt(exemplar, size, *, block="auto", overlap="auto", error_tolerance=ERROR_TOLERANCE, cut=True, tileable=False,
          augment="none", rng=None, return_info=False, progress=False):
    """Synthesise a texture by image quilting (Efros & Freeman 2001, Section 2).

    Examples
    --------
    >>> import texsynth
    >>> brick = texsynth.data.load("brick")[:96, :96]
    >>> out, info = texsynth.quilt(brick, 160, block=32, rng=0, return_info=True)
    >>> out.shape[:2], info.block, info.overlap, len(info.sources)
    ((160, 160), 32, 5, 36)

    Pastes square blocks of the exemplar in raster order, each drawn among
    those that match the output best where they overlap it, and joins each
    block to the output along the minimum-error boundary cut through the
    overlap [1]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture: ``(H, W)`` grey or ``(H, W, C)``; any accepted dtype.
    size : int or (int, int)
        Output size ``(height, width)``; any size.
    block : int or "auto"
        Side ``B`` of the square blocks, in pixels: "big enough to capture the
        relevant structures in the texture, but small enough so that the
        interaction between these structures is left up to the algorithm"
        (the paper). ``"auto"`` (default): a quarter of the exemplar's shorter side; at
        most the exemplar's shorter side.
    overlap : int or "auto"
        Width ``O`` of the overlap between neighbouring blocks. ``"auto"``
        (default): ``B / 6`` (the paper's), rounded; 0 places blocks side by side with
        nothing to match (random blocks, the paper's Figure 1a). Must be
        smaller than ``block``.
    error_tolerance : float
        A block qualifies if its overlap error is at most ``(1 +
        error_tolerance)`` times the best block's (paper: 0.1); one of the
        qualifying blocks is drawn uniformly. 0 takes the best (ties, such as
        the exact copies of a periodic exemplar, drawn among). Must be >= 0.
    cut : bool
        Join the blocks along the minimum-error boundary cut (True, the
        paper's method); False pastes each block over the whole overlap
        (Figure 1b, "neighboring blocks constrained by overlap").
    tileable : bool
        Make the output tile seamlessly: the block grid wraps around, so the
        last blocks of a row (column) are matched and cut against the first
        ones as well. Needs a ``size`` of at least about twice the block.
    augment : {"none", "flips", "rotations", "both"}
        Also paste blocks of the exemplar's mirror images (``"flips"``),
        quarter turns (``"rotations"``) or both, each block from one copy,
        as ``Search(augment=...)`` does for the neighbourhood-matching
        methods (:func:`~texsynth.core.search.augmented_set`). Default
        ``"none"``. ``info.sources`` and ``info.coordinates`` still point
        into the exemplar (a source: the exemplar pixel that the block's
        top-left pixel shows).
    rng : None, int or numpy.random.Generator
        Random source for the choice of blocks; an int seed reproduces the
        output bit for bit.
    return_info : bool
        Also return a :class:`QuiltInfo` with every block's position, source
        and error.
    progress : bool or callable
        Report progress per block (True: tqdm bar; a callable receives
        ``(step, total, info)``).

    Returns
    -------
    image : numpy.ndarray
        ``(height, width)`` or ``(height, width, C)``, the exemplar's channel
        layout; float32 for float32 input, float64 otherwise.
    info : QuiltInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If ``block`` is larger than the exemplar, ``overlap >= block``,
        ``error_tolerance < 0``, or a tileable ``size`` is too small for the
        block; if the output would not fit in memory.

    Notes
    -----

    Blocks are placed in raster order with a step of ``B - O``; the first is
    drawn at random. For each later block, every ``B x B`` block ``b`` of the
    exemplar is scored by its overlap error with the output ``o`` in the
    known strips ``Ω`` (left, top, or both),

    .. math:: \\varepsilon(b) = \\sum_{x \\in \\Omega} \\|b(x) - o(x)\\|^2,

    all at once by FFT correlation (:class:`texsynth.core.search.WindowSearch`).
    One of the blocks with ``ε(b) <= (1 + error_tolerance) min ε`` is drawn
    uniformly. The minimum-error boundary cut through each strip's error
    surface ``e_ij = ||b(x) - o(x)||^2`` is

    .. math:: E_{i,j} = e_{i,j} + \\min(E_{i-1,j-1}, E_{i-1,j}, E_{i-1,j+1})

    traced back from the smallest ``E`` of the last row
    (:func:`texsynth.core.seams.minimum_error_boundary`); horizontal strips
    likewise, transposed. In the L-shaped case the block keeps the pixels
    beyond both cuts. The output is cut from a canvas of ``n (B - O) + O``
    pixels.

    The paper's Figure 1 in three calls: random blocks
    ``quilt(ex, size, overlap=0)``, blocks matched in the overlap but
    pasted over it ``quilt(ex, size, cut=False)``, and the method itself
    ``quilt(ex, size)``.

    Quilting works from stochastic to regular textures; it fails where no
    exemplar block continues the overlap (too small an exemplar, large
    structures larger than the block), where it tends to repeat the same
    blocks (the paper's "excessive repetition"), and its seams follow the
    grid, which can show on smooth gradients.

    References
    ----------
    .. [1] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001, pp. 341-346.
       :doi:`10.1145/383259.383296`
    """
    started = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey = with_channels(image)
    size = as_size(size)
    B = check_block(block, ex.shape[:2])
    O = check_overlap(overlap, B)
    tolerance = check_tolerance(error_tolerance)
    join = _boundary_cut if check_bool(cut, "cut") else _paste_over
    grid = Grid(size, B, O, check_bool(tileable, "tileable"))
    gen = as_rng(rng)
    check_canvas_memory(grid, ex.shape[2], ex.shape[:2], value=size)
    search, atlas = window_search(ex.astype(np.float64), (B, B), augment)  # atlas: the exemplar's copies too
    exf = search.image

    def choose(window, region, known):
        if not known.any():  # nothing to match: any block
            top, left = search.draw(gen)
            return top, left, 0.0, 0.0, search.n_positions
        return _draw(search.sq_distances(region, known), tolerance, gen)

    canvas, records, searching, sources = paste_blocks(exf, grid, choose, join, progress, "quilt", return_info)
    out = finish(canvas, size, image.dtype, grey)
    if return_info:
        return out, augmented_info(quilt_info(grid, records, O, started, searching, sources, size), atlas)
    return out


def augmented_info(info, atlas):
    """``info`` with its sources and coordinates in the exemplar's pixels when blocks came from an ``atlas`` of its
    flipped and rotated copies (:func:`~texsynth.core.search.window_search`); ``info`` itself without one."""
    if atlas is not None:
        info.sources = atlas.to_exemplar(info.sources)
        info.coordinates = atlas.to_exemplar(info.coordinates)
    return info


# --------------------------------------------------------------------------
# Section 3: texture transfer


def _luminance(image):
    """The luminance of a channels-last image (scikit-image's rgb2gray weights); grey stays as it is."""
    if image.shape[2] >= 3:
        from skimage.color import rgb2gray

        return rgb2gray(image[..., :3])[..., None]
    return image[..., :1]


def _correspondence_maps(correspondence, texture, pattern):
    """The correspondence maps of the texture and the pattern, channels-last."""
    if isinstance(correspondence, str):
        if correspondence != "luminance":
            raise ValueError(f"correspondence must be 'luminance' or a pair of maps (texture_map, pattern_map), "
                             f"got {correspondence!r}")
        return _luminance(texture), _luminance(pattern)
    try:
        texture_map, pattern_map = correspondence
    except (TypeError, ValueError):
        raise TypeError("correspondence must be 'luminance' or a pair of maps (texture_map, pattern_map)") from None
    maps = []
    for name, value, shape in (("texture map", texture_map, texture.shape[:2]),
                               ("pattern map", pattern_map, pattern.shape[:2])):
        m, _ = with_channels(as_image(value, f"correspondence's {name}"))
        if m.shape[:2] != shape:
            raise ValueError(f"correspondence's {name} has shape {m.shape[:2]} but its image has {shape}; pass "
                             f"maps of the texture's and the pattern's sizes")
        maps.append(m.astype(np.float64))
    if maps[0].shape[2] != maps[1].shape[2]:
        raise ValueError(f"the correspondence maps have {maps[0].shape[2]} and {maps[1].shape[2]} channels; "
                         "pass maps with the same number of channels")
    return maps


def _alphas(alpha, iterations):
    """The weight of the overlap error in each pass: the paper's schedule, or one value for every pass."""
    if is_auto(alpha):
        if iterations == 1:
            return np.array([0.1])
        return 0.8 * np.arange(iterations) / (iterations - 1) + 0.1  # alpha_i = 0.8 (i-1)/(N-1) + 0.1
    return np.full(iterations, check_in_range(alpha, "alpha", 0.0, 1.0))


def _pad_to(image, shape):
    """``image`` extended (mirrored) to cover a canvas of ``shape``."""
    pads = ((0, shape[0] - image.shape[0]), (0, shape[1] - image.shape[1]), (0, 0))
    return np.pad(image, pads, mode="symmetric")


def quilt_transfer(texture, pattern, *, block="auto", overlap="auto", iterations=TRANSFER_ITERATIONS, alpha="auto",
                   error_tolerance=ERROR_TOLERANCE, correspondence="luminance", prescale=True, rng=None,
                   return_info=False, progress=False):
    """Render a pattern image in a texture by image quilting (Efros & Freeman 2001, Section 3).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> texture = texsynth.data.load("bread")[:96, :96]
    >>> pattern = np.tile(np.linspace(0, 1, 64), (48, 1))  # a ramp
    >>> out, info = texsynth.quilt_transfer(texture, pattern, block=24, rng=0, return_info=True)
    >>> out.shape, [p.block for p in info.passes], info.alphas.tolist()
    ((48, 64, 3), [24, 16, 11], [0.1, 0.5, 0.9])

    Quilts the pattern's size in passes of shrinking blocks, choosing each
    block by its overlap error with the output (the texture) weighed against
    how well its correspondence map (luminance) matches the pattern under
    it [1]_.

    Parameters
    ----------
    texture : array_like
        The source texture: ``(H, W)`` grey or ``(H, W, C)``.
    pattern : array_like
        The target image whose appearance the output follows (grey or
        colour); the output has its size and the texture's channels.
    block : int or "auto"
        Block side of the first pass; each later pass's is a third smaller.
        ``"auto"`` (default): a quarter of the texture's shorter side.
    overlap : int or "auto"
        Overlap of the first pass, shrinking with the block. ``"auto"``
        (default): ``B / 6``.
    iterations : int
        Number of passes ``N`` (default 3; the paper's ``N`` is not known here).
    alpha : float or "auto"
        Weight of the overlap (texture) error against the correspondence
        error, in [0, 1]; 0 follows the pattern only, 1 ignores it.
        ``"auto"`` (default): the paper's schedule ``alpha_i = 0.8 (i - 1) / (N - 1) + 0.1``
        (0.1 in the first pass, 0.9 in the last).
    error_tolerance : float
        As :func:`quilt`: blocks within ``(1 + error_tolerance)`` of the best
        combined error qualify (default 0.1).
    correspondence : "luminance" or (array_like, array_like)
        The correspondence maps compared between texture and pattern: their
        luminance (the paper's default), or a pair ``(texture_map,
        pattern_map)`` of images of the texture's and the pattern's sizes
        with the same number of channels (blurred luminance, orientation, ...).
    prescale : bool
        Rescale the pattern's map to the mean and range of the texture's
        first, so a dark pattern can be rendered in a light texture.
    rng : None, int or numpy.random.Generator
        Random source for the choice of blocks.
    return_info : bool
        Also return a :class:`QuiltTransferInfo` (one :class:`QuiltInfo` per pass).
    progress : bool or callable
        Report progress per pass (True: tqdm bar; a callable receives
        ``(step, total, info)`` with the pass's block and alpha).

    Returns
    -------
    image : numpy.ndarray
        The pattern's height and width, the texture's channels; float32 for
        a float32 texture, float64 otherwise.
    info : QuiltTransferInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If a pass's block would be larger than the texture or smaller than
        2 pixels, ``overlap >= block``, ``alpha`` is outside [0, 1],
        ``error_tolerance < 0``, or the maps do not match their images.

    Notes
    -----

    Pass ``i`` quilts the pattern's size with blocks of ``B_i = B (2/3)^(i-1)``
    and scores every texture block ``b`` at an output position by

    .. math:: \\varepsilon(b) = \\alpha_i\\, \\varepsilon_{overlap}(b) + (1 - \\alpha_i)\\, \\varepsilon_{corr}(b)

    with ``ε_overlap`` the squared difference with the output in the
    overlap (from pass 2 on, with the previous pass's output over the rest
    of the block as well) and ``ε_corr`` the squared difference between the
    block's correspondence map and the pattern's under it. Both are means
    per pixel and channel (a choice of this implementation: the paper weighs
    the two errors without saying how they are normalised), so ``alpha``
    does not depend on the block size. Blocks are joined along
    minimum-error boundary cuts as in :func:`quilt`.

    Transfer keeps the texture's appearance at the scale of the blocks and
    follows the pattern at the scale of the last pass's block; fine detail
    of the pattern smaller than that block is lost, and a texture without
    the pattern's range of luminance cannot follow it (``prescale`` helps).

    References
    ----------
    .. [1] A. A. Efros and W. T. Freeman, "Image quilting for texture
       synthesis and transfer", SIGGRAPH 2001, pp. 341-346.
       :doi:`10.1145/383259.383296`
    """
    started = time.perf_counter()
    tex_image = as_image(texture, "texture")
    tex, grey = with_channels(tex_image)
    pat, _ = with_channels(as_image(pattern, "pattern"))
    size = pat.shape[:2]
    n_passes = check_positive_int(iterations, "iterations", maximum=MAX_ITERATIONS)
    alphas = _alphas(alpha, n_passes)
    tolerance = check_tolerance(error_tolerance)
    prescale = check_bool(prescale, "prescale")
    first = check_block(block, tex.shape[:2], "texture")
    blocks = [round(first * TRANSFER_SHRINK**i) for i in range(n_passes)]
    if blocks[-1] < 2:
        raise ValueError(f"block {first} shrinks below 2 pixels in pass {n_passes} (blocks {blocks}); pass a larger "
                         f"block or fewer iterations")
    first_overlap = check_overlap(overlap, first)
    overlaps = [first_overlap if i == 0 else round(first_overlap * TRANSFER_SHRINK**i) for i in range(n_passes)]
    gen = as_rng(rng)
    tex_map, pat_map = _correspondence_maps(correspondence, tex.astype(np.float64), pat.astype(np.float64))
    if prescale:
        pat_map = prescale_pattern(pat_map, tex_map)
    texf = tex.astype(np.float64)
    channels, map_channels = texf.shape[2], tex_map.shape[2]

    passes, previous, stages = [], None, {}
    with Progress(progress, n_passes, "quilt transfer") as bar:
        for i, (B, O, a) in enumerate(zip(blocks, overlaps, alphas)):
            pass_started = time.perf_counter()
            grid = Grid(size, B, O, False)
            check_canvas_memory(grid, channels + map_channels, tex.shape[:2], "pattern", pat.shape[:2])
            search, match = WindowSearch(texf, (B, B)), WindowSearch(tex_map, (B, B))
            target = _pad_to(pat_map, grid.canvas_shape)
            before = None if previous is None else _pad_to(previous, grid.canvas_shape)

            def choose(window, region, known, a=a, B=B, search=search, match=match, target=target, before=before):
                corr = match.sq_distances(target[window]) / (B * B * map_channels)
                if before is None:  # pass 1: the overlap only
                    overlap_error = search.sq_distances(region, known) / max(1.0, known.sum() * channels)
                else:  # later passes: the overlap, and the previous pass's output over the rest
                    overlap_error = search.sq_distances(np.where(known[..., None], region, before[window])) \
                        / (B * B * channels)
                return _draw(a * overlap_error + (1 - a) * corr, tolerance, gen)

            canvas, records, searching, sources = paste_blocks(texf, grid, choose, _boundary_cut, False, "",
                                                               track=return_info)
            previous = canvas[: size[0], : size[1]]
            passes.append(quilt_info(grid, records, O, pass_started, searching, sources, size))
            stages[f"pass {i + 1}"] = time.perf_counter() - pass_started
            bar.advance({"block": B, "alpha": float(a)})
    out = finish(previous, size, tex_image.dtype, grey)
    if return_info:
        return out, QuiltTransferInfo(passes=passes, alphas=alphas, seconds=time.perf_counter() - started,
                                      stage_seconds=stages)
    return out
