"""Harrison's patchwork texture synthesis: random Voronoi patches with invisible joins.

Harrison (2002) copies random patches of the exemplar into the output, one per
cell of a Voronoi diagram over jittered grid points ``p_i``, and hides the
joins by blending the patches with weights ``w_i(x) = d(x, p_i)^-f`` while
controlling the standard deviation of every blended pixel (eq. 2). Section 4
extends this to video (intermediate sequences, eqs. 3-6:
:mod:`texsynth.patch._patchwork_video`) and Section 5 to texture transfer
(source points matched to a pattern image, eq. 7:
:mod:`texsynth.patch._patchwork_transfer`). This module holds Sections 2-3,
the image synthesis and the parts the other two share: the jittered grid
(:class:`Geometry`), the weights of eq. 1 and the blend of eqs. 2 and 7
(:func:`blend`).

Symbols follow the paper (its Table 1):

``O(x)``
    output image; ``I(x)`` input image (exemplar); ``P(x)`` pattern image.
``p_i``
    points in the output (one per Voronoi cell, on a jittered grid).
``q_i``
    points in the input; cell ``i`` copies ``I(x - p_i + q_i)``.
``f``
    sharpness of the patch borders (``sharpness``).
``a``
    the input's mean colour (eq. 2); ``a_i`` local means for transfer (eq. 7).
``d(a, b)``
    Euclidean distance.

Cost and the neighbour bound
----------------------------
Eq. 2 sums over every cell; "terms with small weight may be omitted". Here a
pixel ``x`` sums over the cells of an ``m x m`` block of neighbouring grid
points (``neighbors=m``, default 4): with grid spacing ``s`` the block is
chosen so that ``x`` lies in its central region, every omitted point is at
least ``(m - 1) s / 2`` away from ``x`` along one axis, while the point of
``x``'s own grid square is at most ``sqrt(2) s`` away (and typically about
``0.5 s``). The cost is ``m^2`` vectorized passes over the output:
O(number of output pixels), with memory bounded by processing bands of rows.

Smooth truncation (a departure from the paper)
----------------------------------------------
Omitting the small terms outright makes each weight jump to 0 where the
pixel's block moves on (every ``s`` pixels, along straight rows and
columns). At ``f = 2`` (transfer's default), where the weights fall off
slowly, the jumps showed as faint straight seams, worst in eq. 7, whose
second term uses the first power of the weights. So every weight is
multiplied by a window that reaches 0 exactly where the cell stops being
summed: ``w_i(x) phi_i(x)``, with ``phi_i`` the product over the two axes of

.. math:: \\phi = \\tfrac12 - \\tfrac12 \\cos\\big(\\pi \\min(e / (s/2), 1)\\big)

where ``e`` is the distance from ``x`` to the nearer end of the cell's
*reach* (the span ``m s`` wide centred on its own grid square, where it is
summed). ``phi_i`` is 1 except over the outer half grid spacing of the reach,
so never over the pixel's own square and, for ``m >= 4``, not over the
adjacent squares either; it is a raised-cosine ramp like the paper's temporal
transitions (eqs. 3-4). The weight field, the sums of eqs. 2 and 7 and the
output are then continuous; the same ``w_i phi_i`` serves eq. 2 (images,
video) and eq. 7 (transfer). Where every reach covers the whole output with
the ramp to spare (a few cells and a large ``m``), ``phi_i = 1`` and eqs. 2
and 7 hold exactly over every cell. With ``m = 4`` the taper and the bound
leave out 6e-5 of ``sum w_i^2`` on average at ``f = 6`` (the plain cut
6e-6) and 2.4% at ``f = 2`` (1.5%); ``benchmarks/bench_patchwork.py``
measures both against the all-cells sum. With ``m = 2`` or 3 the block is
too small for the ramp to miss the adjacent cells, and joins change shape a
little (the plain cut showed strong seams there instead). The ``q_i`` are
drawn as without the window (:meth:`Geometry.influence` measures "near the
cell" with the plain and the tapered weights and keeps the union; for
``m >= 4`` the tapered region lies inside the plain one).
"""

from __future__ import annotations

import math
import time
import warnings
from dataclasses import dataclass, field

import numpy as np

from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_memory, check_positive_int,
                              restore_channels, with_channels)

__all__ = ["patchwork", "voronoi_weights", "PatchworkInfo"]

_BAND_PIXELS = 1 << 16  # pixels per band: keeps the m*m weight arrays of a band in cache
_NEAR = 0.01  # "near the cell": normalised weight above this must be sampled inside the input
# cells kept per pixel in info.coordinates: those whose coefficient in eq. 2 is at least this (rendering
# the exemplar through the map then reproduces the output to about 0.005, tests/test_coordinates.py)
SOURCE_MIN_WEIGHT = 1 / 512
_TAPER = 0.5  # the weights taper to 0 over the outer half grid spacing of each cell's reach


@dataclass
class PatchworkInfo:
    """What :func:`patchwork` and friends chose.

    Attributes
    ----------
    p : numpy.ndarray
        ``(n, 2)`` float, the points ``p_i`` (row, col) in the output. They lie
        on pixel corners (half-integer coordinates), so no pixel is at
        distance 0 from a point.
    q : numpy.ndarray
        ``(n, 2)`` float, the matching points ``q_i`` in the input; cell ``i``
        copies ``I(x - p_i + q_i)`` (an integer offset).
    cells : numpy.ndarray
        ``(H, W)`` int, index ``i`` of the cell with the largest weight at each
        output pixel (the Voronoi cell of ``p_i``).
    grid_shape : tuple of int
        Number of grid points (rows, columns); ``n`` is their product.
    spacing : tuple of float
        Grid spacing actually used (rows, columns); equal to ``grid_spacing``
        except for tileable output, where it is adjusted so the grid wraps.
    neighbors : int
        Size ``m`` of the ``m x m`` block of cells summed per pixel (each
        weight tapered to 0 at the edge of its reach, see the module notes).
    exact_sources : bool
        True when every sample ``x - p_i + q_i`` of every contributing cell
        lies inside the input. ``q_i`` always keeps the part of the cell
        where its normalised weight exceeds 0.01 inside (the paper's "in or
        near the cell"); beyond it the far tails may leave the input and are
        mirrored at the input border, which changes a pixel by less than 0.01
        per mirrored cell.
    clipped : float
        Fraction of output values clipped to [0, 1] after eq. 2 or 7.
    local_means : numpy.ndarray or None
        ``(n, C)`` local averages ``a_i`` (transfer, eq. 7); None otherwise.
    frame_keys : numpy.ndarray or None
        Video only: ``(n, k)`` key frames ``p_{i,k}`` of each cell's
        intermediate sequence (eqs. 3-6).
    frame_sources : numpy.ndarray or None
        Video only: ``(n, k)`` matching input frames ``q_{i,k}``.
    seconds : float
        Total wall time.
    stage_seconds : dict
        ``"matching"`` (transfer: choosing the ``q_i``) and ``"blending"``
        (eq. 2 or 7 over the output).
    coordinates : numpy.ndarray or None
        :func:`patchwork`: ``(H, W, K, 2)`` int, the input pixels
        ``x - p_i + q_i`` of the ``K`` cells that weigh most at each pixel,
        largest first (mirrored back into the input where a far tail leaves
        it); the source-coordinate map of ``docs/conventions.md``.
        :func:`patchwork_video`: ``(n_frames, H, W, K, 2)``, one such map
        per output frame, each cell's slot split into the three terms of
        eq. 6 (see :attr:`source_index`). None for :func:`patchwork_transfer`
        (eq. 7's local means ``a_i`` are averages over whole texture
        patches, which a map of a few pixels per output pixel cannot
        express) and with ``chunks=``.
    weights : numpy.ndarray or None
        ``(H, W, K)`` float32 (video: ``(n_frames, H, W, K)``), their
        coefficients ``w_i / sqrt(sum_j w_j^2)`` of eq. 2 (video: times
        eq. 6's ``w_1 / n``, ``w_2 / n`` or ``1 - 1/n``, ``n = sqrt(w_1^2 +
        w_2^2)``; the last is negative), largest magnitude first. They sum
        to more than 1; :func:`texsynth.apply_coordinates` takes the rest
        from the channel's mean ``a``, as eq. 2 does, so rendering the input
        through the map gives the output up to the cells left out (those of
        coefficient below 1/512) and the clipping to [0, 1].
    source_index : numpy.ndarray or None
        :func:`patchwork_video` only: ``(n_frames, H, W, K)`` int, the input
        frame each slot reads (``I(x - p_i + q_i, tau)`` of eq. 6), or -1
        for the average frame ``A(x - p_i + q_i)``. The input frames play
        the role of :func:`texsynth.mix_textures`' sources:
        :func:`texsynth.apply_coordinates` takes each channel as the list
        of its images, one per input frame, and returns ``(n_frames, H,
        W[, C])``.
    """

    p: np.ndarray
    q: np.ndarray
    cells: np.ndarray
    grid_shape: tuple
    spacing: tuple
    neighbors: int
    exact_sources: bool
    clipped: float = 0.0
    local_means: np.ndarray | None = None
    frame_keys: np.ndarray | None = None
    frame_sources: np.ndarray | None = None
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None
    source_index: np.ndarray | None = None


# --------------------------------------------------------------------------
# Validation helpers


def check_sharpness(sharpness):
    if not isinstance(sharpness, (int, float, np.integer, np.floating)) or isinstance(sharpness, bool):
        raise TypeError(f"sharpness f must be a positive number (paper: 6), got {sharpness!r}")
    if not np.isfinite(sharpness) or sharpness <= 0 or sharpness > 1000:
        raise ValueError(
            f"sharpness f must be a number in (0, 1000] (paper: 2, 6 or 20; default 6; at 1000 the joins are "
            f"already hard Voronoi edges), got {sharpness}"
        )
    return float(sharpness)


def check_grid_spacing(grid_spacing, input_shape, sharpness, neighbors, name="exemplar"):
    """``grid_spacing`` checked, or ``"auto"`` resolved: the largest spacing up to the paper's 64
    pixels whose cells, "in or near" region included, fit inside the input (:func:`_fitting_grid`)."""
    if isinstance(grid_spacing, str) and grid_spacing == "auto":
        return _fitting_grid(input_shape, sharpness, neighbors)
    s = check_positive_int(grid_spacing, "grid_spacing")
    if s > min(input_shape):
        raise ValueError(
            f"grid_spacing {s} is larger than the {name} ({input_shape[0]}x{input_shape[1]}); "
            f"pass grid_spacing <= {_fitting_grid(input_shape, sharpness, neighbors)} (or 'auto': whole cells "
            f"fit in the {name}) or a larger {name}"
        )
    return s


def _reach(sharpness, neighbors):
    """Extent of a cell's "in or near" region in grid spacings (measured on a probe grid of spacing 64)."""
    probe = Geometry((512, 512), (4096, 4096), 64, sharpness, neighbors, False, np.random.default_rng(0),
                      choose_q=False)
    near_y, near_x = probe.influence()
    return max(float((near_y[1] - near_y[0] + 1).max()), float((near_x[1] - near_x[0] + 1).max())) / 64.0


def _fitting_grid(input_shape, sharpness, neighbors):
    """The largest grid spacing, up to the paper's 64, whose cells' "in or near" regions fit in the input
    (so no ``q_i`` needs the mirrored input: Harrison chooses each ``q_i`` so the patch lies inside)."""
    return int(np.clip(min(input_shape) // _reach(sharpness, neighbors), 4, 64))


def warn_if_cells_leave(geom, s, input_shape, sharpness, neighbors, name="exemplar"):
    """Warn when cells reach beyond the input: their far parts are the mirrored input (symmetric motifs)."""
    if geom.cut:
        warnings.warn(
            f"grid_spacing {s} makes cells reach beyond the {name} ({input_shape[0]}x{input_shape[1]}): their "
            f"far parts copy the mirrored {name}, which shows as mirror-symmetric motifs; pass grid_spacing <= "
            f"{_fitting_grid(input_shape, sharpness, neighbors)} (the default 'auto' does) or a larger input",
            UserWarning, stacklevel=3,
        )


def check_neighbors(neighbors):
    m = check_positive_int(neighbors, "neighbors", minimum=2)
    if m > 8:
        raise ValueError(f"neighbors must be an integer in 2..8 (default 4), got {m}")
    return m


# --------------------------------------------------------------------------
# Section 3: the jittered grid of points p_i and the choice of q_i


class _Axis:
    """One axis of the jittered grid and of the block decomposition of the output.

    Grid square ``j`` spans ``[j*s, (j+1)*s)``; its point ``p_j`` lies inside it.
    Output coordinate ``r`` sums over the points ``k0(r) .. k0(r)+m-1`` with
    ``k0(r) = floor(r/s - m/2 + 1/2)`` (so ``r`` is in the middle of that block
    of squares). Rows with the same ``k0`` form a *block*; blocks are padded to
    a common length ``T`` so the work broadcasts as ``(blocks, T)`` arrays.
    """

    def __init__(self, n_out, spacing, m, tileable, step=1):
        self.n_out = n_out
        self.m = m
        self.tileable = tileable
        if tileable:
            self.n = max(1, round(n_out / spacing))
            self.s = n_out / self.n
        else:
            self.n = max(1, math.ceil(n_out / spacing))
            self.s = float(spacing)
        # every pixel (step 1), or a coarse sample of them to measure the cells' influence
        r = np.unique(np.r_[np.arange(0, n_out, step), n_out - 1])
        k0 = np.floor(r / self.s - m / 2 + 0.5).astype(np.intp)
        self.k0, start, counts = np.unique(k0, return_index=True, return_counts=True)
        self.T = int(counts.max())
        i = np.arange(self.T)
        # coordinates of the padded layout (a block shorter than T repeats its last row)
        self.coords = r[start[:, None] + np.minimum(i[None, :], counts[:, None] - 1)]
        self.block_of = np.repeat(np.arange(len(start)), counts)
        self.index_in_block = np.arange(len(r)) - start[self.block_of]
        self.windows = [self.window(a) for a in range(m)]
        self.untapered = [bool(np.all(w == 1)) for w in self.windows]  # inner neighbours: skip the product

    def window(self, a):
        """The taper ``phi`` of neighbour ``a`` of every block at every coordinate, ``(blocks, T)`` float32.

        Square ``J = k0 + a`` is summed for ``r`` in ``[lo, hi)``, ``lo, hi = (J + 1/2 -+ m/2) s``
        (its reach). With ``e = min(r - lo, hi - r)`` the distance to the nearer end of the reach,
        ``phi = 1/2 - cos(pi min(e / L, 1)) / 2`` with ``L = _TAPER * s``: 1 except in the outer
        ``L`` of the reach, 0 where the square stops being summed.
        """
        centre = (self.k0 + a + 0.5)[:, None] * self.s  # (blocks, 1)
        e = self.m * self.s / 2 - np.abs(self.coords - centre)  # >= 0 inside the reach
        u = np.clip(e / (_TAPER * self.s), 0.0, 1.0)
        return (0.5 - 0.5 * np.cos(np.pi * u)).astype(np.float32)

    def reach(self, j):
        """Offsets ``x - p`` of the output coordinates that sum over square ``j`` (lo, hi), before p."""
        lo = np.ceil((j - self.m / 2 + 0.5) * self.s)
        hi = np.ceil((j + self.m / 2 + 0.5) * self.s) - 1
        return lo, hi

    def neighbour(self, a):
        """Point index (mod n), periodic-image shift and validity for offset ``a`` of every block."""
        J = self.k0 + a
        if self.tileable:
            return np.mod(J, self.n), np.floor_divide(J, self.n) * self.n_out, np.ones(J.shape, bool)
        valid = (J >= 0) & (J < self.n)
        return np.clip(J, 0, self.n - 1), np.zeros(J.shape), valid


def _jitter(axis, shape, gen, along):
    """Jittered grid coordinates ``p`` on pixel corners: one point per grid square."""
    u = gen.random(shape)
    j = np.arange(axis.n).reshape((-1, 1) if along == 0 else (1, -1))
    cell = np.floor((j + u) * axis.s)
    lo = np.ceil(j * axis.s)
    hi = np.ceil((j + 1) * axis.s) - 1
    return np.clip(cell, lo, np.maximum(lo, hi)) + 0.5


def _source_bounds(p, n_in, near):
    """Allowed source pixels ``q_i - 1/2`` along one axis, so that ``x - p_i + q_i`` stays inside.

    ``near`` holds, per point, the offsets ``(lo, hi)`` of ``x - p_i`` "in or
    near" the cell: where its normalised weight exceeds ``_NEAR`` (measured
    by :meth:`Geometry.influence`). A window longer than the input is cut to
    the input's length around ``p_i``. Samples of the cell outside the window
    (its far tails) are mirrored at the input border.
    Returns the first and last allowed source pixel per point.
    """
    wlo = np.minimum(near[0], 0)
    whi = np.maximum(near[1], 0)
    before = (n_in - 1) // 2
    too_long = whi - wlo + 1 > n_in
    wlo = np.where(too_long, np.maximum(wlo, np.maximum(-before, whi - n_in + 1)), wlo)
    whi = np.where(too_long, wlo + n_in - 1, whi)
    return -wlo, n_in - 1 - whi


def draw_sources(first, last, gen, k=None):
    """Uniform random integers in ``[first, last]``; ``k`` draws per entry if given."""
    if k is None:
        return first + np.floor(gen.random(first.shape) * (last - first + 1))
    span = (last - first + 1)[..., None]
    return first[..., None] + np.floor(gen.random(first.shape + (k,)) * span)


class Geometry:
    """The points ``p_i``, ``q_i`` and the per-band weights ``w_i(x)`` (eq. 1)."""

    def __init__(self, out_size, in_size, spacing, sharpness, m, tileable, gen, choose_q=True):
        H, W = out_size
        self.f = sharpness
        self.m = m
        self.rows = _Axis(H, spacing, m, tileable)
        self.cols = _Axis(W, spacing, m, tileable)
        ny, nx = self.rows.n, self.cols.n
        self.grid_shape = (ny, nx)
        self.py = _jitter(self.rows, (ny, nx), gen, 0)
        self.px = _jitter(self.cols, (ny, nx), gen, 1)
        self.in_size = in_size
        self.qy = self.qx = None
        self.exact = False
        self.tileable = tileable
        self.spacing = spacing
        near_y, near_x = self.influence()
        self.bounds_y = _source_bounds(self.py, in_size[0], near_y)
        self.bounds_x = _source_bounds(self.px, in_size[1], near_x)
        # cells whose "in or near" region is longer than the input: cut, their far parts mirrored
        self.cut = bool(np.any(near_y[1] - near_y[0] + 1 > in_size[0]) or np.any(near_x[1] - near_x[0] + 1 > in_size[1]))
        if choose_q:  # Section 3: q_i at random
            self.set_sources(draw_sources(*self.bounds_y, gen) + 0.5, draw_sources(*self.bounds_x, gen) + 0.5)

    def set_sources(self, qy, qx):
        self.qy, self.qx = qy, qx
        self.exact = not any(self.pad())  # every contributing sample inside the input

    def pad(self):
        """Margins (top, bottom, left, right) the input needs so every sample exists."""
        j = np.arange(self.rows.n)[:, None]
        k = np.arange(self.cols.n)[None, :]
        lo, hi = self.rows.reach(j)
        top = int(max(0, -np.min(lo - self.py + self.qy)))
        bottom = int(max(0, np.max(hi - self.py + self.qy) - (self.in_size[0] - 1)))
        lo, hi = self.cols.reach(k)
        left = int(max(0, -np.min(lo - self.px + self.qx)))
        right = int(max(0, np.max(hi - self.px + self.qx) - (self.in_size[1] - 1)))
        return top, bottom, left, right

    def influence(self):
        """Offsets ``x - p_i`` (rows and columns) where cell ``i`` matters: "in or near" the cell.

        Measured on a coarse sample of the output (every ``s/8``-th pixel,
        widened by that step) as the extent of the region where
        ``w_i(x) / sqrt(sum_j w_j(x)^2) > _NEAR``, with the plain weights of
        eq. 1 or with the tapered weights ``w_i phi_i`` the synthesis uses
        (the union: tapering the far cells raises the normalised weight of the
        others slightly; for ``m >= 4`` the tapered region lies inside the
        plain one, so the taper leaves the ``q_i`` unchanged). Returns
        ``((lo, hi), (lo, hi))`` arrays of shape ``grid_shape``, in pixels
        from the pixel at ``p_i - 1/2``.
        """
        step = max(1, int(round(min(self.rows.s, self.cols.s) / 8)))
        axes = (
            _Axis(self.rows.n_out, self.spacing, self.m, self.tileable, step),
            _Axis(self.cols.n_out, self.spacing, self.m, self.tileable, step),
        )
        n = self.grid_shape[0] * self.grid_shape[1]
        ext = np.full((4, n), np.inf)
        ext[1::2] = -np.inf  # lo_y, hi_y, lo_x, hi_x
        for band in self.bands(axes):
            parts, _ = self.band_weights(band, axes=axes, taper=False)
            tapered = [
                w * axes[0].windows[n // self.m][band][:, :, None, None] * axes[1].windows[n % self.m][None, None]
                for n, (_, w, *_) in enumerate(parts)
            ]
            norm = np.sqrt(sum(w * w for _, w, _, _, _ in parts))
            norm_tapered = np.sqrt(sum(w * w for w in tapered))
            r = axes[0].coords[band].astype(np.float64)[:, :, None]  # (By, T, 1)
            c = axes[1].coords.astype(np.float64)[None, :, :]  # (1, Bx, T)
            for (ids, w, _, py, px), wt in zip(parts, tapered):
                near = (w > _NEAR * norm) | (wt > _NEAR * norm_tapered)
                dy = r - py[:, None, :] + 0.5  # (By, T, Bx)
                dx = c - px[:, :, None] + 0.5  # (By, Bx, T)
                hit_y, hit_x = near.any(3), near.any(1)
                for row, d, hit, red in ((0, dy, hit_y, 1), (2, dx, hit_x, 2)):
                    np.minimum.at(ext[row], ids.ravel(), np.where(hit, d, np.inf).min(red).ravel())
                    np.maximum.at(ext[row + 1], ids.ravel(), np.where(hit, d, -np.inf).max(red).ravel())
        ext[0::2] -= step  # the coarse sample may miss up to one step
        ext[1::2] += step
        unseen = ~np.isfinite(ext)  # a sliver of a cell between samples
        fallback = np.broadcast_to(np.array([-step, step, -step, step], float)[:, None], ext.shape)
        ext[unseen] = fallback[unseen]
        shape = self.grid_shape
        return (ext[0].reshape(shape), ext[1].reshape(shape)), (ext[2].reshape(shape), ext[3].reshape(shape))

    def bands(self, axes=None, blocks=None, col_blocks=None):
        """Slices of row blocks (of the slice ``blocks``, default all), each about ``_BAND_PIXELS``
        output pixels over ``col_blocks`` column blocks (default all)."""
        rows, cols = axes or (self.rows, self.cols)
        per_block = rows.T * (len(cols.k0) if col_blocks is None else col_blocks) * cols.T
        step = max(1, _BAND_PIXELS // per_block)
        first, last = (0, len(rows.k0)) if blocks is None else (blocks.start, blocks.stop)
        return [slice(b, min(last, b + step)) for b in range(first, last, step)]

    def tiles(self, rows, cols):
        """``(band, cband)`` pairs of row and column blocks that cover the output ``rows x cols``
        (slices), each about ``_BAND_PIXELS`` output pixels."""
        r = self.rows.block_of[[rows.start, rows.stop - 1]]
        c = self.cols.block_of[[cols.start, cols.stop - 1]]
        group = max(1, _BAND_PIXELS // (self.rows.T * self.cols.T))  # column blocks at a time
        cbands = [slice(b, min(int(c[1]) + 1, b + group)) for b in range(int(c[0]), int(c[1]) + 1, group)]
        return [(band, cband) for cband in cbands
                for band in self.bands(blocks=slice(int(r[0]), int(r[1]) + 1), col_blocks=cband.stop - cband.start)]

    def band_weights(self, band, padded_width=None, pads=(0, 0, 0, 0), need_cells=False, axes=None, taper=True,
                     cband=slice(None)):
        """Eq. 1 for every pixel of a band (of its column blocks ``cband``) and each of its ``m*m`` neighbouring cells.

        Returns a list of ``(ids, w, flat)`` per neighbour: ``ids`` the cell
        index ``(By, Bx)``, ``w`` the weights relative to the nearest cell
        ``(By, T, Bx, T)`` (float32, the scale cancels in eqs. 2 and 7),
        times the smooth truncation ``phi_i`` unless ``taper=False``,
        ``flat`` the flat index of ``x - p_i + q_i`` in the padded input (None
        without ``padded_width``); and the map of the nearest cell if
        ``need_cells``.
        """
        rows, cols = axes or (self.rows, self.cols)
        top, _, left, _ = pads
        r = rows.coords[band].astype(np.float64)  # (By, T)
        c = cols.coords[cband].astype(np.float64)  # (Bx, T)
        nx = self.grid_shape[1]
        parts = []
        for a in range(self.m):
            J, shift_y, valid_y = (v[band] for v in rows.neighbour(a))
            for b in range(self.m):
                K, shift_x, valid_x = (v[cband] for v in cols.neighbour(b))
                py = self.py[J[:, None], K[None, :]] + shift_y[:, None]  # (By, Bx), periodic image
                px = self.px[J[:, None], K[None, :]] + shift_x[None, :]
                dy2 = ((r[:, :, None] - py[:, None, :]) ** 2).astype(np.float32)[..., None]  # (By,T,Bx,1)
                dx2 = ((c[None, None, :, :] - px[:, None, :, None]) ** 2).astype(np.float32)  # (By,1,Bx,T)
                valid = (valid_y[:, None] & valid_x[None, :])[:, None, :, None]
                if not valid.all():  # non-tileable border: no grid point there
                    dy2 = np.where(valid, dy2, np.float32(np.inf))
                d2 = dy2 + dx2  # d(x, p_i)^2, (By, T, Bx, T)
                ids = J[:, None] * nx + K[None, :]
                if padded_width is None:
                    parts.append([ids, d2, None, py, px])
                    continue
                # source x - p_i + q_i as a flat index into the padded input (integer offsets)
                sy = (r[:, :, None] + (self.qy[J[:, None], K[None, :]] - py)[:, None, :] + top).astype(np.intp)
                sx = (c[None, :, :] + (self.qx[J[:, None], K[None, :]] - px)[:, :, None] + left).astype(np.intp)
                flat = sy[..., None] * padded_width + sx[:, None, :, :]
                parts.append([ids, d2, flat, py, px])
        d2min = parts[0][1].copy()
        for part in parts[1:]:
            np.minimum(d2min, part[1], out=d2min)
        cells = None
        if need_cells:
            cells = np.zeros(d2min.shape, np.intp)
            for ids, d2, *_ in parts:
                hit = d2 == d2min
                cells[hit] = np.broadcast_to(ids[:, None, :, None], d2.shape)[hit]
        half = self.f / 2
        for n, part in enumerate(parts):
            ratio = np.divide(d2min, part[1], out=part[1])  # (d_min / d_i)^2 in (0, 1]
            w = _power(ratio, half)  # w_i(x) = d(x, p_i)^-f, eq. 1, up to a per-pixel scale
            a, b = divmod(n, self.m)
            if taper and not rows.untapered[a]:  # w_i(x) phi_i(x): smooth truncation (module notes)
                w *= rows.windows[a][band][:, :, None, None]
            if taper and not cols.untapered[b]:
                w *= cols.windows[b][cband][None, None, :, :]
            part[1] = w
        return parts, cells

    def to_output(self, band, padded, cband=None):
        """Scatter a band (of the column blocks ``cband``) in the padded block layout back to output
        rows (and, with ``cband``, columns: ``(rows, cols, values)``)."""
        rows, cols = self.rows, self.cols
        sel = (rows.block_of >= band.start) & (rows.block_of < band.stop)
        by = rows.block_of[sel] - band.start
        iy = rows.index_in_block[sel]
        if cband is None:
            return np.flatnonzero(sel), padded[by[:, None], iy[:, None], cols.block_of[None, :],
                                               cols.index_in_block[None, :]]
        csel = (cols.block_of >= cband.start) & (cols.block_of < cband.stop)
        out = padded[by[:, None], iy[:, None], cols.block_of[csel][None, :] - cband.start,
                     cols.index_in_block[csel][None, :]]
        return np.flatnonzero(sel), np.flatnonzero(csel), out


def _power(ratio, exponent):
    """``ratio ** exponent`` for float32 arrays, by repeated multiplication for small integers."""
    if exponent == int(exponent) and 1 <= exponent <= 16:
        e = int(exponent)
        result = None
        base = ratio
        while e:
            if e & 1:
                result = base.copy() if result is None else np.multiply(result, base, out=result)
            e >>= 1
            if e:
                base = base * base
        return result
    return np.power(ratio, np.float32(exponent), dtype=np.float32)


def blend(parts, sample, channels, local_means=None):
    """Eq. 2 (``local_means`` None: samples already have ``a`` subtracted) or eq. 7.

    ``sample(n, ids, flat)`` returns the input values ``I(x - p_i + q_i)`` of
    neighbour ``n`` with shape ``flat.shape + (C,)``.
    """
    shape = parts[0][1].shape
    num = np.zeros(shape + (channels,), np.float32)
    den2 = np.zeros(shape, np.float32)
    if local_means is not None:
        mean_num = np.zeros(shape + (channels,), np.float32)
        den1 = np.zeros(shape, np.float32)
    for n, (ids, w, flat, *_) in enumerate(parts):
        values = sample(n, ids, flat)
        wc = w[..., None]
        if local_means is None:
            num += np.multiply(values, wc, out=values)  # sum_i (I(x - p_i + q_i) - a) w_i(x)
        else:
            a_i = local_means[ids][:, None, :, None, :]  # (By, 1, Bx, 1, C)
            num += (values - a_i) * wc  # sum_i (I(x - p_i + q_i) - a_i) w_i(x)
            mean_num += a_i * wc  # sum_i a_i w_i(x)
            den1 += w
        den2 += w * w
    num /= np.sqrt(den2)[..., None]  # divided by sqrt(sum_i w_i(x)^2)
    if local_means is not None:
        num += mean_num / den1[..., None]  # + sum_i a_i w_i / sum_i w_i   (eq. 7)
    return num


def _mirror(index, n):
    """Coordinates of np.pad's "symmetric" extension mapped back into ``0..n-1``."""
    index = np.where(index < 0, -index - 1, index)
    return np.where(index >= n, 2 * n - 1 - index, index)


def band_sources(parts, pads, width, in_size, with_cells=False):
    """The cells that weigh in eq. 2 at every pixel of a band, largest first: input coordinates
    ``(..., K, 2)`` and coefficients ``w_i / sqrt(sum_j w_j^2)`` ``(..., K)`` in the padded block
    layout, ``K`` the most cells of coefficient ``>= SOURCE_MIN_WEIGHT`` at any pixel of the band
    (``with_cells``: also the index ``i`` of each slot's cell, ``(..., K)``)."""
    weights = np.stack([w for _, w, *_ in parts], -1)  # (By, T, Bx, T, m*m)
    norm = np.sqrt(np.sum(weights.astype(np.float64) ** 2, -1, keepdims=True))
    weights = (weights / np.where(norm > 0, norm, 1)).astype(np.float32)
    weights[weights < SOURCE_MIN_WEIGHT] = 0
    order = np.argsort(-weights, axis=-1, kind="stable")
    k = max(1, int(np.count_nonzero(weights, axis=-1).max()))
    order = order[..., :k]
    w = np.take_along_axis(weights, order, -1)
    flats = np.take_along_axis(np.stack([flat for _, _, flat, *_ in parts], -1), order, -1)
    row, col = np.divmod(flats, width)
    coords = np.stack([_mirror(row - pads[0], in_size[0]), _mirror(col - pads[2], in_size[1])], -1)
    if with_cells:
        ids = np.stack([np.broadcast_to(i[:, None, :, None], w.shape[:-1]) for i, *_ in parts], -1)
        return coords, w, np.take_along_axis(ids, order, -1)
    return coords, w


def finish_output(out, dtype, was_grey):
    clipped = float(np.mean((out < 0) | (out > 1)))
    np.clip(out, 0, 1, out=out)
    return restore_channels(out.astype(dtype, copy=False), was_grey), clipped


def patchwork_info(geom, cells, clipped, start, matched=None, **extra):
    """The info of a run that began at ``start`` (perf_counter) and chose its q_i by ``matched``."""
    end = time.perf_counter()
    stages = {"blending": end - (matched or start)}
    if matched is not None:
        stages = {"matching": matched - start, **stages}
    p = np.stack([geom.py.ravel(), geom.px.ravel()], 1)
    q = np.stack([geom.qy.ravel(), geom.qx.ravel()], 1)
    return PatchworkInfo(
        p=p,
        q=q,
        cells=cells,
        grid_shape=geom.grid_shape,
        spacing=(geom.rows.s, geom.cols.s),
        neighbors=geom.m,
        exact_sources=geom.exact,
        clipped=clipped,
        seconds=end - start,
        stage_seconds=stages,
        **extra,
    )


def check_output_memory(size, channels, spacing, frames=1, cells=False, pixels=True):
    """Refuse an output that cannot fit: float32 while blending, the result in float64, the cell map,
    and about 100 bytes per grid point of the geometry (that alone without ``pixels``: chunks)."""
    h, w = size
    per_pixel = (frames * channels * (4 + 8) + (8 if cells else 0)) if pixels else 0
    check_memory(float(h) * w * per_pixel + 100.0 * (h / spacing + 2) * (w / spacing + 2), size,
                 what="the output" if pixels else "the cells (p_i, q_i) of the whole output",
                 also={"n_frames": frames} if frames > 1 else None)


def padded_flat(image, pads):
    """The input padded by mirroring (only used where samples leave it) as ``(pixels, C)``."""
    top, bottom, left, right = pads
    if any(pads):
        image = np.pad(image, ((top, bottom), (left, right), (0, 0)), mode="symmetric")
    return image.reshape(-1, image.shape[-1]), image.shape[1]


def run_bands(geom, width, pads, need_cells, compose, progress, desc):
    """Loop over bands: weights once per band, then ``compose(band, parts)``."""
    cells = np.zeros((geom.rows.n_out, geom.cols.n_out), np.intp) if need_cells else None
    bands = geom.bands()
    with Progress(progress, len(bands), desc) as bar:
        for band in bands:
            parts, cell_blocks = geom.band_weights(band, width, pads, need_cells)
            compose(band, parts)
            if need_cells:
                idx, block_cells = geom.to_output(band, cell_blocks[..., None])
                cells[idx] = block_cells[..., 0]
            bar.advance({"band": band.start})
    return cells


# --------------------------------------------------------------------------
# Public functions


def voronoi_weights(size, *, grid_spacing=64, sharpness=6, tileable=False, neighbors=4, rng=None):
    """The largest normalised patch weight ``w_i(x) / sqrt(sum_j w_j(x)^2)`` (eqs. 1-2), and the cell map.

    Draws the patch shapes of Figure 2: deep inside a cell the largest
    normalised weight is close to 1; on the join between two cells both
    weights are about ``1/sqrt(2)``. Larger ``f`` makes the joins narrower.
    The weights are those :func:`patchwork` uses: ``w_i phi_i`` over the
    ``m x m`` block, smoothly tapered at its edge (module notes).

    Parameters
    ----------
    size : int or (int, int)
        Output size ``(height, width)``.
    grid_spacing : int
        Spacing of the jittered grid of points ``p_i`` (paper: 64).
    sharpness : float
        ``f`` in eq. 1 (paper: 6; Figure 2 shows 2, 6 and 20).
    tileable : bool
        Wrap the grid and the distance around the borders.
    neighbors : int
        Block size ``m``: each pixel sums over the cells of ``m x m`` grid points.
    rng : None, int or numpy.random.Generator
        Seed for the jittered grid (the same seed gives the same ``p_i`` as
        :func:`patchwork` with the same size and options).

    Returns
    -------
    largest : numpy.ndarray
        ``(H, W)`` float64, the largest normalised weight at each pixel.
    cells : numpy.ndarray
        ``(H, W)`` int, index ``i`` of the cell with the largest weight.

    Examples
    --------
    >>> largest, cells = voronoi_weights(32, grid_spacing=8, rng=0)
    >>> largest.shape, int(cells.max()) + 1
    ((32, 32), 16)
    >>> bool(largest.min() > 0.5) and bool(largest.max() <= 1.0)  # >= 1/sqrt(3) where 3 cells meet
    True
    """
    H, W = as_size(size)
    f = check_sharpness(sharpness)
    s = check_positive_int(grid_spacing, "grid_spacing")
    m = check_neighbors(neighbors)
    check_output_memory((H, W), 1, s, cells=True)
    geom = Geometry((H, W), (H, W), s, f, m, check_bool(tileable, "tileable"), as_rng(rng), choose_q=False)
    largest = np.zeros((H, W), np.float64)
    cells = np.zeros((H, W), np.intp)
    for band in geom.bands():
        parts, cell_blocks = geom.band_weights(band, need_cells=True)
        weights = [w for _, w, *_ in parts]
        norm = np.sqrt(sum(w * w for w in weights))
        top = np.max(np.stack(weights), 0) / norm
        idx, block = geom.to_output(band, np.stack([top.astype(np.float64), cell_blocks], -1))
        largest[idx] = block[..., 0]
        cells[idx] = block[..., 1].astype(np.intp)
    return largest, cells


def patchwork(
    exemplar,
    size,
    *,
    grid_spacing="auto",
    sharpness=6,
    tileable=False,
    neighbors=4,
    rng=None,
    return_info=False,
    progress=False,
    chunks=None,
):
    """Synthesise a texture from random Voronoi patches with invisible joins (Harrison 2002, Section 3).

    Examples
    --------
    >>> import texsynth
    >>> metal = texsynth.data.load("metal")
    >>> out, info = texsynth.patchwork(metal, 96, grid_spacing=32, rng=0, return_info=True)
    >>> out.shape, info.grid_shape, info.cells.shape
    ((96, 96), (3, 3), (96, 96))
    >>> bool(abs(out.mean() - metal.mean()) < 0.05)
    True

    Gives every point of a jittered grid over the output a random patch of
    the exemplar and blends the patches with weights that fall with the
    distance to their point (eq. 1), normalised so that the blend keeps the
    exemplar's contrast (eq. 2) [1]_.

    Parameters
    ----------
    exemplar : array_like
        Input texture ``I``: ``(H, W)`` grey or ``(H, W, C)``; uint8, uint16,
        bool or float, converted to float in [0, 1] (docs/conventions.md).
    size : int or (int, int)
        Output size ``(height, width)``; any size.
    grid_spacing : int or "auto"
        Spacing of the jittered grid of patch centres, about the size of a
        patch (paper: 64 pixels, Figure 4; the points ``p_i``). Must not
        exceed the exemplar.
        ``"auto"`` (default): the paper's 64, or less where the exemplar is
        too small for whole cells: the largest spacing whose cells, with the
        region "in or near" them where they still weigh (about 4 spacings
        across at ``sharpness=6``), fit inside the exemplar, so every
        ``q_i`` keeps its patch inside the input as the paper requires (a
        128-pixel exemplar: 31). A spacing whose cells reach beyond the
        exemplar warns: their far parts copy the mirrored exemplar, which
        shows as mirror-symmetric motifs.
    sharpness : float
        Sharpness of the patch borders, > 0 (paper: 6; Figure 2 shows 2, 6
        and 20). It is ``f`` in eq. 1.
    tileable : bool
        Make the output tile seamlessly: the jittered grid wraps around and the
        distance ``d`` is toroidal. The grid spacing is then adjusted to
        ``height / round(height / grid_spacing)`` (and likewise for width).
    neighbors : int
        Each pixel sums eq. 2 over the cells of the ``m x m`` nearest grid
        points (``m = neighbors``, default 4), with the weights tapered
        smoothly to 0 at the edge of that block (see Notes and the module
        notes for the weight this omits).
    rng : None, int or numpy.random.Generator
        Random source for ``p_i`` and ``q_i``; an int seed reproduces the
        output bit for bit.
    return_info : bool
        Also return a :class:`PatchworkInfo` with ``p_i``, ``q_i`` and the
        cell map.
    progress : bool or callable
        Report progress per band of rows (True: tqdm bar; callable receives
        ``(step, total, info)``).
    chunks : None, int or (int, int)
        Return a lazy ``dask.array`` rendered block by block (blocks of
        ``chunks`` rows and columns, an int meaning square), for outputs
        larger than memory: the points ``p_i`` and ``q_i`` are drawn once for
        the whole output (about 100 bytes per cell), each block blends the
        cells that reach it. Write it with :func:`texsynth.io.save_chunked`.
        Every block equals the same pixels of the in-memory result bit for
        bit. Not with ``return_info`` or ``progress``. Needs Dask
        (the ``dask`` extra: ``pip install '.[dask]'`` in a checkout).

    Returns
    -------
    image : numpy.ndarray or dask.array.Array
        ``(height, width)`` or ``(height, width, C)``, the exemplar's channel
        layout; float32 for float32 input, float64 otherwise; lazy with
        ``chunks``.
    info : PatchworkInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError
        If ``grid_spacing`` is larger than the exemplar, ``sharpness <= 0``,
        or ``neighbors`` is outside 2..8.

    Notes
    -----

    Each cell ``i`` weighs its patch by (eq. 1)

    .. math:: w_i(x) = d(x, p_i)^{-f}

    and the output is (eq. 2)

    .. math:: O(x) = \\frac{\\sum_i (I(x - p_i + q_i) - a)\\, w_i(x)}
              {\\sqrt{\\sum_i w_i(x)^2}} + a

    with ``a`` the mean colour of the input. For uncorrelated patches the
    divisor keeps the standard deviation of every pixel equal to the input's,
    so joins are neither duller nor brighter than the patches (Figure 1c).
    Values are clipped to [0, 1] afterwards (``info.clipped`` is the
    fraction; typically well below 1%). The weights are computed relative to
    the nearest point (``(d_min / d_i)^f``), which leaves eq. 2 unchanged and
    cannot overflow for large ``f``.

    Departure from the paper: the sums run over the ``m x m`` block of cells
    around ``x`` only (the paper allows omitting small terms), and rather
    than being cut off, each ``w_i(x)`` is multiplied by a window
    ``phi_i(x)`` that is 1 except over the outer half grid spacing of the
    region where cell ``i`` is summed and falls there, as a raised cosine,
    to exactly 0 where the cell stops being summed. The plain cut left faint
    straight seams every ``grid_spacing`` pixels at ``f = 2``, which the
    window removes (``docs/methods/patchwork.md``); at larger ``f`` the
    window changes the output very little.
    When the block covers every cell with room to spare, ``phi_i = 1`` and
    eq. 2 is exact. The window does not change how ``q_i`` is drawn for
    ``m >= 4``; with ``m = 2`` or 3 at ``f >= 6`` it can widen a cell's
    "near" region by a few pixels, and a few ``q_i`` (under 1%, up to 8% at
    ``f = 20``, ``m = 2``) are drawn from a slightly narrower range to keep
    it inside the input.

    The points ``p_i`` lie on pixel corners; ``q_i`` is drawn uniformly
    among the positions that keep the cell "in or near" the input: the region
    where its normalised weight ``w_i / sqrt(sum_j w_j^2)`` exceeds 0.01
    (measured per cell on a coarse sample of the output). The far tails of a
    cell may leave the input; there the exemplar is mirrored, changing the
    pixel by less than 0.01 per such cell (``info.exact_sources`` tells
    whether it happened).

    The method fails, as the paper says, on tiling patterns (bricks, weaves)
    and on textures with large objects or cracks: random patches break them.

    References
    ----------
    .. [1] P. Harrison, "Patchwork texture synthesis", Technical report,
       Monash University, 2002. (No DOI; see also P. Harrison, "A
       non-hierarchical procedure for re-synthesis of complex textures",
       WSCG 2001.)
    """
    start = time.perf_counter()
    image = as_image(exemplar, "exemplar")
    ex, grey = with_channels(image)
    H, W = as_size(size)
    f = check_sharpness(sharpness)
    m = check_neighbors(neighbors)
    s = check_grid_spacing(grid_spacing, ex.shape[:2], f, m)
    if chunks is not None and (return_info or progress):
        raise ValueError("return_info and progress are not available with chunks=; pass them as False")
    check_output_memory((H, W), ex.shape[-1], s, cells=return_info, pixels=chunks is None)
    geom = Geometry((H, W), ex.shape[:2], s, f, m, check_bool(tileable, "tileable"), as_rng(rng))
    warn_if_cells_leave(geom, s, ex.shape[:2], f, m)

    C = ex.shape[-1]
    src = ex.astype(np.float32)
    a = src.reshape(-1, C).mean(0, dtype=np.float64).astype(np.float32)  # average colour a (eq. 2)
    pads = geom.pad()
    table, width = padded_flat(src - a, pads)

    def sample(n, ids, flat):
        return table.take(flat, axis=0)

    if chunks is not None:
        from ..core.chunked import chunked_image

        def window(rows, cols):  # the pixels rows x cols, tile by tile, as compose() below computes them
            out = np.empty((rows.stop - rows.start, cols.stop - cols.start, C), np.float32)
            for band, cband in geom.tiles(rows, cols):
                r, c, values = geom.to_output(band, blend(geom.band_weights(band, width, pads, cband=cband)[0],
                                                           sample, C), cband)
                # r and c are runs of rows and columns: the part inside the block, by slices
                r0, r1 = max(r[0], rows.start), min(r[-1] + 1, rows.stop)
                c0, c1 = max(c[0], cols.start), min(c[-1] + 1, cols.stop)
                out[r0 - rows.start : r1 - rows.start, c0 - cols.start : c1 - cols.start] = (
                    values[r0 - r[0] : r1 - r[0], c0 - c[0] : c1 - c[0]] + a)
            return finish_output(out, image.dtype, grey)[0]

        # blending works in float32 on m*m weights of a tile's pixels; the block itself and its result
        return chunked_image((H, W), None if grey else C, image.dtype, chunks, window,
                             bytes_per_pixel=C * (4 + 2 * image.dtype.itemsize))
    out = np.empty((H, W, C), np.float32)
    sources = []  # return_info: the source-coordinate map, band by band (bookkeeping beside the blend)

    def compose(band, parts):
        if return_info:
            c, w = band_sources(parts, pads, width, ex.shape[:2])
            idx, rows = geom.to_output(band, c)
            sources.append((idx, rows, geom.to_output(band, w)[1]))
        blended = blend(parts, sample, C)
        idx, rows = geom.to_output(band, blended)
        out[idx] = rows + a  # eq. 2: ... + a

    cells = run_bands(geom, width, pads, return_info, compose, progress, "patchwork")
    result, clipped = finish_output(out, image.dtype, grey)
    if return_info:
        from ..core.coordinates import compact_slots

        k = max(w.shape[-1] for _, _, w in sources)
        coordinates, weights = np.zeros((H, W, k, 2), np.int64), np.zeros((H, W, k), np.float32)
        for idx, c, w in sources:
            coordinates[idx, :, : w.shape[-1]], weights[idx, :, : w.shape[-1]] = c, w
        coordinates, weights = compact_slots(coordinates, weights)
        return result, patchwork_info(geom, cells, clipped, start, coordinates=coordinates, weights=weights)
    return result
