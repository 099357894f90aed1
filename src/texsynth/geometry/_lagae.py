"""Geometry synthesis by example on signed distance fields (Lagae, Dumont & Dutré 2005).

Lagae et al. carry patch-based texture synthesis over to geometry: the example
shape is sampled as a *regularly sampled signed distance field* (a volume whose
voxels hold the distance to the surface, negative inside), the volume is
synthesised like a solid texture, and the surface of the result is extracted
as a mesh. This module reads in that order:

- the example as a distance field: a signed distance volume as given, or a
  boolean occupancy volume converted by two Euclidean distance transforms
  (:func:`scipy.ndimage.distance_transform_edt` of the inside and of the
  outside, half a voxel apart so that the zero level runs between them);
- hierarchical synthesis (``levels``): coarser passes first, on the volumes
  subsampled by 2 per level on the same block grid, each finer pass guided by
  the coarser result under its blocks (one pass by default, see the docs);
- block-based synthesis in 3-D, image quilting carried to volumes: cubic
  blocks of the example are placed on a grid of the output in raster order
  (depth, then rows, then columns), each overlapping its placed neighbours by
  ``overlap`` voxels; every candidate block is scored by its *overlap error*,
  the sum of squared distance-field differences over the voxels the output
  already holds (both fields clipped to ``+-truncation`` voxels, as truncated
  distance fields: the surfaces near the overlap decide, not the distances far
  from them), through :class:`texsynth.core.search.MaskedIndex` (masked
  exact distances), and one is drawn among those within ``error_tolerance``
  of the best (:func:`texsynth.core.search.within_tolerance`);
- the seam between a new block and the output: a 3-D minimum cut through the
  overlap (:func:`texsynth.core.seams.graph_cut` with ``spatial_dims=3``,
  Kwatra et al.'s patch fitting in a volume, on the truncated fields), so the
  new block replaces the old voxels where the two distance fields agree;
- the paper's second output: the example's own separate elements copied
  whole where the matched blocks show them (``copy_elements=True``);
- the surface: the zero level set of the result by marching cubes
  (:func:`sdf_to_mesh`, :func:`skimage.measure.marching_cubes`).

What could not be checked: the paper's text was not at hand; this follows its
published description (the abstract and summaries of it). Its details (the
block size, the overlap, the matching error, the seams, how the hierarchy
guides the finer levels, how elements are assigned to blocks) are this
module's choices, measured where the docs page says so; the paper's equation
numbers are not quoted.

References
----------
.. [1] A. Lagae, O. Dumont and P. Dutré, "Geometry synthesis by example",
   Shape Modeling International 2005 (an earlier version as a report of the
   Department of Computer Science, KU Leuven, 2004). The DOI
   10.1109/SMI.2005.19 is quoted from memory and was not verified here.
.. [2] A. A. Efros and W. T. Freeman, "Image quilting for texture synthesis
   and transfer", SIGGRAPH 2001, doi:10.1145/383259.383296.
.. [3] V. Kwatra, A. Schödl, I. Essa, G. Turk and A. Bobick, "Graphcut
   textures", SIGGRAPH 2003, doi:10.1145/882262.882264.
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import time

import numpy as np
from scipy import ndimage

from ..core._progress import Progress
from ..core._validate import (as_array, as_rng, as_size, check_bool, check_choice, check_memory,
                              check_positive_float, check_positive_int, is_auto)
from ..core.search import MaskedIndex, within_tolerance
from ..core.seams import graph_cut

__all__ = ["GeometryInfo", "synthesize_geometry", "sdf_to_mesh", "as_distance_field"]

#: Voxels: the largest shift of the distance values by which sdf_to_mesh breaks ties (see there)
_TIE_BREAK = 1e-4
#: Blocks never smaller than this many voxels a side by default ...
MIN_AUTO_BLOCK = 8
#: ... nor larger (a third of the example's smallest side in between).
MAX_AUTO_BLOCK = 32
#: Bytes the candidate blocks' overlap vectors may take (float32, stored with their squares
#: by the masked index: three copies); ``candidate_stride="auto"`` is the smallest stride within it.
CANDIDATE_BUDGET = 256 * 2**20
PLACEMENTS = ("overlap", "random")
#: Weight of a coarse voxel of the guide in a finer level's matching error, against 1 per overlap voxel
#: (measured on the docs' pebbles, 72^3, levels=2, rng 0-2: 0.5 gave 2-9 cut elements and 2.3-2.9 local
#: energy, 2 gave 3-7 and 3.0-3.9, 8 gave 9-14 and 3.8-4.7; one level: 2-10 and 2.8-2.9).
GUIDE_WEIGHT = 0.5
#: ``truncation="auto"``: the distance fields are compared clipped to +-2 voxels.
AUTO_TRUNCATION = 2.0


@dataclasses.dataclass(frozen=True)
class GeometryInfo:
    """What :func:`synthesize_geometry` chose.

    Attributes
    ----------
    sources : numpy.ndarray
        ``(n_blocks, 3)`` int, the example corner ``(z, y, x)`` copied into
        each block, in placement (raster) order.
    corners : numpy.ndarray
        ``(n_blocks, 3)`` int, each block's corner in the output (it may reach
        past the output's end: the grid is cropped).
    overlap_errors : numpy.ndarray
        ``(n_blocks,)`` float, the chosen block's overlap error per overlap
        voxel (mean squared distance difference; 0 for the first block).
    cut_costs : numpy.ndarray
        ``(n_blocks,)`` float, the cost of each block's seam (0 without cut).
    element_placements : numpy.ndarray or None
        With ``copy_elements=True``: ``(n, 4)`` int, per copied element its
        label in ``scipy.ndimage.label(example_sdf < 0)`` and the offset
        ``(dz, dy, dx)`` added to its example voxels; else None.
    block, overlap, candidate_stride : int
        The values used (at the finest level).
    truncation : float or None
        The truncation used.
    n_candidates : int
        Candidate blocks in the example.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Seconds per stage (``"distance field"``, then ``"level L"`` for each
        level, coarsest first: its index and blocks; ``"elements"``).
    """

    sources: np.ndarray
    corners: np.ndarray
    overlap_errors: np.ndarray
    cut_costs: np.ndarray
    element_placements: np.ndarray | None
    block: int
    overlap: int
    candidate_stride: int
    truncation: float | None
    n_candidates: int
    seconds: float
    stage_seconds: dict


# --------------------------------------------------------------------------
# The example as a regularly sampled signed distance field


def as_distance_field(volume, name="exemplar"):
    """A ``(D, H, W)`` signed distance volume (float64, negative inside) from an SDF or an occupancy volume.

    Parameters
    ----------
    volume : array_like, shape (D, H, W)
        Real values (a signed distance field, negative inside: taken as it
        is) or bool (occupancy, True inside: converted by two Euclidean
        distance transforms, ``-(d_in - 1/2)`` inside and ``d_out - 1/2``
        outside, so the zero level lies half-way between an inside and an
        outside voxel).
    name : str
        Parameter name used in error messages.

    Returns
    -------
    numpy.ndarray
        float64 ``(D, H, W)``.

    Examples
    --------
    >>> occupancy = np.zeros((5, 5, 5), bool); occupancy[2, 2, 2] = True
    >>> sdf = as_distance_field(occupancy)
    >>> float(sdf[2, 2, 2]), float(sdf[2, 2, 3]), float(sdf[2, 2, 4])
    (-0.5, 0.5, 1.5)
    """
    arr = as_array(volume, name)
    if arr.ndim != 3:
        raise ValueError(f"{name} must be a volume (depth, height, width): a signed distance field or a bool "
                         f"occupancy, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape})")
    if arr.dtype == np.bool_:
        inside = ndimage.distance_transform_edt(arr)
        outside = ndimage.distance_transform_edt(~arr)
        if not arr.any() or arr.all():  # no surface: the transforms measure to nothing
            fill = -1.0 if arr.all() else 1.0
            return np.full(arr.shape, fill * float(max(arr.shape)))
        return np.where(arr, 0.5 - inside, outside - 0.5)
    if not (np.issubdtype(arr.dtype, np.integer) or np.issubdtype(arr.dtype, np.floating)):
        raise TypeError(f"{name} must be a real (signed distance) or bool (occupancy) volume, got dtype {arr.dtype}")
    out = arr.astype(np.float64)
    if not np.all(np.isfinite(out)):
        raise ValueError(f"{name} contains NaN or infinite values; a signed distance field must be finite")
    return out


# --------------------------------------------------------------------------
# Block grid, candidates and the overlap shell


def _auto_block(shape):
    return int(np.clip(min(shape) // 3, MIN_AUTO_BLOCK, MAX_AUTO_BLOCK))


def _shell(block, overlap):
    """The voxels of a block that its already placed neighbours may cover: the three low faces, ``overlap`` thick.

    In raster order every earlier block that overlaps block ``(i, j, k)`` lies before it along some axis and so
    covers only its first ``overlap`` voxels along that axis."""
    z, y, x = np.indices((block,) * 3, sparse=True)
    return (z < overlap) | (y < overlap) | (x < overlap)


def _grid(n, block, step):
    return int(max(1, math.ceil(max(n - block, 0) / step) + 1))


def _positions(shape, block, stride):
    axes = [np.arange(0, s - block + 1, stride) for s in shape]
    return np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 3)


def _auto_stride(shape, block, shell_size):
    for stride in range(1, block + 1):
        n = int(np.prod([len(range(0, s - block + 1, stride)) for s in shape]))
        if 12.0 * n * shell_size <= CANDIDATE_BUDGET:
            return stride
    return block


def _faces(block):
    """The voxels on the six outer faces of a block."""
    f = np.zeros((block,) * 3, bool)
    f[0], f[-1], f[:, 0], f[:, -1], f[:, :, 0], f[:, :, -1] = (True,) * 6
    return f


def _next_to(region):
    """Voxels of ``region`` with a 6-neighbour outside it (inside the block)."""
    out = np.zeros_like(region)
    for axis in range(3):
        for shift in (1, -1):
            rolled = np.roll(~region, shift, axis)
            edge = [slice(None)] * 3
            edge[axis] = 0 if shift == 1 else -1
            rolled[tuple(edge)] = False  # np.roll wraps: nothing lies beyond the block's faces
            out |= region & rolled
    return out


# --------------------------------------------------------------------------
# Synthesis


def synthesize_geometry(exemplar, size, *, block="auto", overlap="auto", error_tolerance=0.1, truncation="auto",
                        candidate_stride="auto", levels=1, placement="overlap", cut=True, copy_elements=False, rng=None,
                        return_info=False, progress=False):
    """Synthesise a signed distance volume like an example's, block by block (Lagae et al. 2005).

    Examples
    --------
    >>> import texsynth.geometry
    >>> z, y, x = np.indices((24, 24, 24))
    >>> example = (z - 12) ** 2 + ((y % 8) - 4) ** 2 + ((x % 8) - 4) ** 2 < 9  # a grid of pebbles
    >>> sdf = texsynth.geometry.synthesize_geometry(example, 32, block=8, overlap=2, rng=0)
    >>> sdf.shape, bool((sdf < 0).any() and (sdf > 0).any())
    ((32, 32, 32), True)
    >>> vertices, faces = texsynth.geometry.sdf_to_mesh(sdf)
    >>> vertices.shape[1], faces.shape[1]
    (3, 3)

    Parameters
    ----------
    exemplar : array_like, shape (D, H, W)
        The example geometry: a signed distance field (real values, negative
        inside, in voxels) or an occupancy volume (bool, True inside),
        converted with :func:`as_distance_field`.
    size : int or (int, int, int)
        The output's ``(depth, height, width)`` in voxels; an int means a cube.
    block : int or "auto"
        Side of the cubic blocks in voxels. ``"auto"``: a third of the
        example's smallest side, between 8 and 32. At most the example's
        smallest side.
    overlap : int or "auto"
        Voxels by which neighbouring blocks overlap, 2 to ``block // 2``.
        ``"auto"``: ``block // 4`` (at least 2).
    error_tolerance : float
        A block is drawn among those whose overlap error is within
        ``(1 + error_tolerance)`` of the best (quilting's 0.1); 0 keeps only
        the best.
    truncation : float, "auto" or None
        The overlap error and the cut compare the distance fields clipped to
        ``[-truncation, truncation]`` voxels, so that the surfaces near the
        overlap decide, not the distances far from any surface (the output
        keeps the unclipped values). ``"auto"``: 2 voxels (measured on the
        docs' pebbles, 72^3 outputs, rng 0-2: 2-10 cut elements against
        25-37 without truncation and 13-24 with 4). None compares the raw distances.
    candidate_stride : int or "auto"
        Step in voxels between the example corners tried as blocks.
        ``"auto"``: 1 if every corner's overlap fits in 256 MiB, else the
        smallest stride that fits.
    levels : int
        Hierarchical synthesis: ``levels - 1`` coarser passes first, on the
        example and output subsampled by 2 per level (distances halved), with
        blocks and overlaps halved on the same grid; each finer pass matches
        its overlap and, over the whole block, the coarser result under it.
        ``block`` and ``overlap`` must divide by ``2^(levels - 1)`` and the
        coarsest overlap be at least 2; the finest level then tries every
        second example corner at least (``candidate_stride`` rounded up to
        even). 1 (the default): one pass.
    placement : {"overlap", "random"}
        ``"overlap"`` chooses each block by its overlap error;
        ``"random"`` draws blocks uniformly (a baseline, as in graph-cut
        textures' random placement).
    cut : bool
        Join each block to the output along a 3-D minimum cut through the
        overlap (True), or paste it over the overlap.
    copy_elements : bool
        The paper's second output: instead of the stitched field, the union of
        the example's own separate elements (connected components of its
        inside that do not touch its border), each copied whole where a
        matched block shows it: an element belongs to the block whose
        central part (the block less half the overlap on each side, a
        partition of the output) holds its centre copied from the source.
        Elements are never cut (except by the output's border); copies from
        neighbouring blocks may touch or overlap. The field is each element's
        own distance field, at most ``block // 2`` voxels far.
    rng : None, int or numpy.random.Generator
        Seeds the first block and every draw among candidates.
    return_info : bool
        Also return a :class:`GeometryInfo`.
    progress : bool or callable
        A progress bar (True) or a callback ``(step, total, info)``, one step
        per block.

    Returns
    -------
    sdf : numpy.ndarray
        float64 ``(depth, height, width)``, the synthesised distance field
        (negative inside); its zero level is the surface
        (:func:`sdf_to_mesh`). Stitched from blocks of the example, it is a
        distance field inside every block and only approximately one across
        the seams. With ``copy_elements=True``, the minimum of the copied
        elements' own fields (their union), at most ``block // 2`` far.
    info : GeometryInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an example that is not a 3-D real or bool volume, a bad size,
        block, overlap or other option, naming the parameter; a ``size`` whose
        volume does not fit in the memory available (before allocating it).

    Notes
    -----
    Memory: the output grid (padded to whole blocks, float64), its filled
    mask, and the candidates' overlap vectors (float32, bounded by
    ``candidate_stride``). Time: one masked search and one graph cut of
    about ``3 block^2 overlap`` voxels per block.
    """
    t_start = time.perf_counter()
    stages = {}
    rng = as_rng(rng)
    size = as_size(size, "size", ndim=3)
    arr = as_array(exemplar, "exemplar")
    if arr.ndim != 3:
        raise ValueError(f"exemplar must be a volume (depth, height, width): a signed distance field or a bool "
                         f"occupancy, got shape {arr.shape}")
    ex_shape = arr.shape
    if min(ex_shape) < 4:
        raise ValueError(f"exemplar must be at least 4 voxels along every axis, got shape {ex_shape}")
    block = min(_auto_block(ex_shape), min(ex_shape)) if is_auto(block) else check_positive_int(block, "block", 4)
    if block > min(ex_shape):
        raise ValueError(f"block must fit in the example (at most {min(ex_shape)} voxels, its smallest side), "
                         f"got {block}")
    if is_auto(overlap):
        overlap = max(2, block // 4)
    else:
        overlap = check_positive_int(overlap, "overlap", 2)
    if overlap > block // 2:
        raise ValueError(f"overlap must be at most block // 2 = {block // 2} voxels, got {overlap}")
    error_tolerance = check_positive_float(error_tolerance, "error_tolerance", allow_zero=True)
    if is_auto(truncation):
        truncation = AUTO_TRUNCATION
    elif truncation is not None:
        truncation = check_positive_float(truncation, "truncation")
    clip = (lambda v: v) if truncation is None else (lambda v: np.clip(v, -truncation, truncation))
    placement = check_choice(placement, "placement", PLACEMENTS)
    cut = check_bool(cut, "cut")
    copy_elements = check_bool(copy_elements, "copy_elements")
    levels = check_positive_int(levels, "levels", 1, 8)
    f = 2 ** (levels - 1)
    if block % f or overlap % f or overlap // f < 2:
        raise ValueError(f"levels={levels} needs block and overlap divisible by {f} and overlap // {f} >= 2 "
                         f"(got block={block}, overlap={overlap}); pass fewer levels or a larger block and overlap")
    return_info = check_bool(return_info, "return_info")
    shell_size = int(_shell(block, overlap).sum()) + ((block // 2) ** 3 if levels > 1 else 0)  # + the guide
    if is_auto(candidate_stride):
        candidate_stride = _auto_stride(ex_shape, block, shell_size)
    else:
        candidate_stride = check_positive_int(candidate_stride, "candidate_stride", 1, block)

    step = block - overlap
    grid = tuple(_grid(s, block, step) for s in size)
    n_blocks = int(np.prod(grid))
    padded = tuple((g - 1) * step + block for g in grid)
    n_candidates = int(np.prod([len(range(0, s - block + 1, candidate_stride)) for s in ex_shape]))
    # the padded output (float64) and its filled mask, the example's field and transforms (3 float64 copies),
    # the candidates' overlap vectors (float32, three copies in the index), one block's graph (~1 kB a voxel)
    out_bytes = 9.0 * np.prod(padded) * (1 + (1 / 8 if levels > 1 else 0)) + 8.0 * np.prod(size)  # + coarse
    work = 24.0 * np.prod(ex_shape) + (12.0 * n_candidates * shell_size if placement == "overlap" else 0)
    check_memory(out_bytes + work + 1024.0 * shell_size, size, "size", "the output volume and the candidate blocks",
                 also={"block": block})

    t0 = time.perf_counter()
    field = as_distance_field(arr, "exemplar")
    stages["distance field"] = time.perf_counter() - t0

    # Hierarchical synthesis: level l works on the example and the output subsampled by 2^l, with blocks and
    # overlaps 2^l times smaller on the same grid; each finer level matches, besides its overlap, the coarser
    # level's result under the whole block (a guide), so the coarse levels decide the layout
    t0 = time.perf_counter()
    coarse = None
    with Progress(progress, n_blocks * levels, "synthesize_geometry") as bar:
        for level in range(levels - 1, -1, -1):
            f = 2 ** level
            level_field = field[::f, ::f, ::f] / f
            level_stride = max(1, candidate_stride // f)
            if level < levels - 1:  # guided: even corners, over whole coarse voxels
                level_stride = 2 * math.ceil(level_stride / 2)
            out, sources, errors, cut_costs = _quilt(
                level_field, grid, block // f, overlap // f, level_stride, error_tolerance, clip, placement, cut,
                rng, bar, guide=None if coarse is None else (field[::2 * f, ::2 * f, ::2 * f] / (2 * f), coarse))
            coarse = out
            stages[f"level {level}"] = time.perf_counter() - t0
            t0 = time.perf_counter()
    corners = np.array(list(np.ndindex(*grid)), np.int64).reshape(-1, 3) * step
    positions_count = len(_positions(ex_shape, block, level_stride))
    placements = None
    if copy_elements:
        t0 = time.perf_counter()
        del out
        sdf, placements = _copy_elements(field, size, sources, corners, grid, block, overlap)
        stages["elements"] = time.perf_counter() - t0
    else:
        sdf = np.ascontiguousarray(out[: size[0], : size[1], : size[2]])
    if not return_info:
        return sdf
    info = GeometryInfo(sources=sources, corners=corners, overlap_errors=errors, cut_costs=cut_costs,
                        element_placements=placements, block=block, overlap=overlap, candidate_stride=level_stride,
                        truncation=truncation, n_candidates=positions_count,
                        seconds=time.perf_counter() - t_start, stage_seconds=stages)
    return sdf, info


def _quilt(field, grid, block, overlap, stride, error_tolerance, clip, placement, cut, rng, bar, guide=None):
    """One level of 3-D quilting on a grid of blocks: the padded output and each block's source, error, cut cost.

    ``guide``: ``(coarse_example, coarse_output)``, fields at half this level's resolution; a candidate at
    example corner ``s`` (even) is then also compared, over its whole block, with the coarse output under
    the block (weight :data:`GUIDE_WEIGHT` per coarse voxel)."""
    step = block - overlap
    padded = tuple((g - 1) * step + block for g in grid)
    shell = _shell(block, overlap)
    positions = _positions(field.shape, block, stride)
    index = None
    if placement == "overlap":
        half = block // 2
        dims = int(shell.sum()) + (half ** 3 if guide is not None else 0)
        windows = np.lib.stride_tricks.sliding_window_view(field, (block,) * 3)
        vectors = np.empty((len(positions), dims), np.float32)
        if guide is not None:
            coarse_windows = np.lib.stride_tricks.sliding_window_view(guide[0], (half,) * 3)
        for start in range(0, len(positions), 1024):
            p = positions[start:start + 1024]
            part = clip(windows[p[:, 0], p[:, 1], p[:, 2]][:, shell])
            if guide is not None:
                q = p // 2
                part = np.concatenate([part, clip(coarse_windows[q[:, 0], q[:, 1], q[:, 2]].reshape(len(p), -1))], 1)
            vectors[start:start + 1024] = part
        weights = None if guide is None else np.r_[np.ones(int(shell.sum())), np.full(half ** 3, GUIDE_WEIGHT)]
        index = MaskedIndex(vectors, weights=weights)
        del vectors
    out = np.zeros(padded)
    filled = np.zeros(padded, bool)
    faces = _faces(block)
    n_blocks = int(np.prod(grid))
    sources = np.zeros((n_blocks, 3), np.int64)
    errors = np.zeros(n_blocks)
    cut_costs = np.zeros(n_blocks)
    for b, (i, j, k) in enumerate(np.ndindex(*grid)):
        corner = np.array((i * step, j * step, k * step))
        region = tuple(slice(c, c + block) for c in corner)
        known = filled[region]
        old = out[region]
        if placement == "random" or (guide is None and not known.any()):
            choice = int(rng.integers(len(positions)))
        else:
            query, mask = old[shell], known[shell]
            if guide is not None:
                under = guide[1][tuple(slice(c // 2, c // 2 + block // 2) for c in corner)]
                query, mask = np.r_[query, under.ravel()], np.r_[mask, np.ones(under.size, bool)]
            d2 = index.sq_distances(clip(query)[None].astype(np.float32), mask[None])[0]
            d2 = np.maximum(d2, 0.0)
            choice = int(rng.choice(within_tolerance(d2, error_tolerance)))
            errors[b] = float(d2[choice]) / max(int(mask.sum()), 1)
        src = positions[choice]
        new = field[tuple(slice(c, c + block) for c in src)]
        if cut and known.any() and not known.all():
            keep_old = known & faces
            take_new = _next_to(known) & ~keep_old
            new_side, cost = graph_cut(clip(old), clip(new), mask=known, old_mask=keep_old, new_mask=take_new,
                                       spatial_dims=3)
            cut_costs[b] = cost
            out[region] = np.where(known & ~new_side, old, new)
        else:
            out[region] = new
        filled[region] = True
        sources[b] = src
        bar.advance({"block": b})
    return out, sources, errors, cut_costs


# --------------------------------------------------------------------------
# The second output: the example's elements copied whole


def _copy_elements(field, size, sources, corners, grid, block, overlap):
    """Union of the example's whole elements copied by the blocks whose central parts hold their centres."""
    labels, n = ndimage.label(field < 0)
    border = np.unique(np.concatenate([labels[[0, -1]].ravel(), labels[:, [0, -1]].ravel(),
                                       labels[:, :, [0, -1]].ravel()]))
    whole = np.setdiff1d(np.arange(1, n + 1), border)
    if whole.size == 0:
        raise ValueError("copy_elements=True needs separate elements in the example (components of its inside that "
                         "do not touch its border); this example has none: pass copy_elements=False")
    boxes = ndimage.find_objects(labels)
    centres = np.rint(np.array(ndimage.center_of_mass(np.ones_like(labels), labels, whole))).astype(np.int64)
    far = float(block // 2)
    out = np.full(size, far)
    step, half = block - overlap, overlap // 2
    grid = np.array(grid)
    placements = []
    for b, (src, corner) in enumerate(zip(sources, corners)):
        inside = np.all((centres >= src) & (centres < src + block), axis=1)
        for e in np.flatnonzero(inside):
            target = centres[e] - src + corner
            owner = np.clip((target - half) // step, 0, grid - 1)  # the block whose central part holds it
            if np.ravel_multi_index(owner, grid) != b or np.any(target >= size):
                continue
            label = whole[e]
            offset = corner - src
            lo = np.array([sl.start for sl in boxes[label - 1]]) - int(far)
            hi = np.array([sl.stop for sl in boxes[label - 1]]) + int(far)
            mask = np.pad(labels[tuple(slice(max(a, 0), b_) for a, b_ in zip(lo, hi))] == label,
                          [(max(-a, 0), max(b_ - s, 0)) for a, b_, s in zip(lo, hi, labels.shape)])
            own = np.minimum(as_distance_field(mask), far)  # the element's own field, alone
            dst_lo, dst_hi = lo + offset, hi + offset
            cl_lo, cl_hi = np.maximum(dst_lo, 0), np.minimum(dst_hi, size)
            if np.any(cl_hi <= cl_lo):
                continue
            region = tuple(slice(a, b_) for a, b_ in zip(cl_lo, cl_hi))
            piece = own[tuple(slice(a - d, b_ - d) for a, b_, d in zip(cl_lo, cl_hi, dst_lo))]
            np.minimum(out[region], piece, out=out[region])
            placements.append((label, *offset))
    return out, np.array(placements, np.int64).reshape(-1, 4)


# --------------------------------------------------------------------------
# The surface: marching cubes


def sdf_to_mesh(sdf, iso_level=0.0, spacing=1.0, *, closed=True):
    """The surface ``sdf == iso_level`` of a distance volume as a triangle mesh, by marching cubes.

    Examples
    --------
    >>> z, y, x = np.indices((12, 12, 12)) - 5.5
    >>> vertices, faces = sdf_to_mesh(np.sqrt(x**2 + y**2 + z**2) - 4)
    >>> vertices.shape[1], faces.shape[1], bool(vertices.min() > 1 and vertices.max() < 10)
    (3, 3, True)

    Parameters
    ----------
    sdf : array_like, shape (D, H, W)
        The distance field (negative inside), e.g. :func:`synthesize_geometry`'s
        output; a bool occupancy volume is converted first.
    iso_level : float
        The iso-value of the surface.
    spacing : float or (float, float, float)
        Voxel size along ``(depth, height, width)``.
    closed : bool
        Cap the surface where it leaves the volume (the volume is padded by one
        voxel of outside), so every mesh is closed (watertight); False leaves it
        open at the volume's faces.

    Returns
    -------
    vertices : numpy.ndarray
        float64 ``(N, 3)`` positions ``(x, y, z)``: ``x`` along the volume's
        width, ``z`` along its depth (texsynth's meshes have z up).
    faces : numpy.ndarray
        int64 ``(M, 3)``, counter-clockwise seen from outside. The pair is a
        mesh for :func:`texsynth.write_mesh`, :func:`texsynth.render_mesh` and
        :func:`texsynth.surface.as_mesh` (zero-area triangles are dropped).

    Raises
    ------
    ValueError
        If the volume has no surface at ``iso_level``, or bad arguments.
    """
    from skimage.measure import marching_cubes

    field = as_distance_field(sdf, "sdf")
    if not isinstance(iso_level, numbers.Real) or isinstance(iso_level, bool) or not math.isfinite(iso_level):
        raise TypeError(f"iso_level must be a finite number, got {iso_level!r}")
    iso_level = float(iso_level)
    spacing = np.broadcast_to(np.asarray(spacing, dtype=np.float64), (3,)).copy() \
        if np.ndim(spacing) in (0, 1) and np.size(spacing) in (1, 3) else None
    if spacing is None or not (np.all(np.isfinite(spacing)) and spacing.min() > 0):
        raise ValueError("spacing must be a positive number or three positive numbers (depth, height, width)")
    closed = check_bool(closed, "closed")
    # values exactly at the iso_level put vertices on voxel corners and make zero-area triangles: nudge them outside
    scale = max(float(np.abs(field - iso_level).max()), 1.0)
    field = np.where(field == iso_level, iso_level + 1e-6 * scale, field)
    # a cube face whose corners tie (an occupancy's +-1/2 in a checkerboard, a clipped field's copies) is
    # ambiguous, and marching cubes may resolve it differently in the two cubes that share it: edges of three or
    # four faces. A fixed, irrational pattern of at most _TIE_BREAK voxels breaks every tie the same way each time
    i, j, k = np.indices(field.shape, sparse=True)
    field = field + _TIE_BREAK * np.modf(i * 0.7548776662466927 + j * 0.5698402909980532 + k * 0.3472963553338607)[0]
    offset = 0.0
    if closed:
        field = np.pad(field, 1, constant_values=iso_level + scale)
        offset = 1.0
    if not (field.min() < iso_level < field.max()):
        raise ValueError(f"sdf has no surface at iso_level={iso_level}: its values lie in "
                         f"[{float(field.min()):.4g}, {float(field.max()):.4g}]")
    verts, tri, _, _ = marching_cubes(field, level=iso_level, gradient_direction="ascent", allow_degenerate=False)
    verts = (verts - offset) * spacing
    vertices = np.ascontiguousarray(verts[:, ::-1], dtype=np.float64)  # (z, y, x) -> (x, y, z)
    faces = tri.astype(np.int64)  # axes reversed: marching cubes' "ascent" winding is counter-clockwise outside
    a, b, c = (vertices[faces[:, n]] for n in range(3))
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1)
    faces = faces[area > 1e-12 * max(float(spacing.max()), 1.0) ** 2]
    used = np.zeros(len(vertices), bool)
    used[faces.ravel()] = True
    remap = np.cumsum(used) - 1
    return vertices[used], remap[faces]
