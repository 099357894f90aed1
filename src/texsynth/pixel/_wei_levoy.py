"""Wei-Levoy pixel synthesis (Wei & Levoy 2000), and the engine Wei's multi-source synthesis builds on.

:func:`synthesize_pixels`
    Wei & Levoy 2000 [1]_: multi-resolution pixel synthesis. The output
    pyramid starts as noise drawn from the exemplar's pixels; levels are
    synthesised coarse to fine; each pixel becomes the exemplar pixel whose
    causal (L-shaped) neighbourhood at this level, joined to the full
    neighbourhood of its parent one level coarser, is nearest (Sec. 3.2,
    Table 1). Toroidal output (seamless when tiled with ``tileable=True``).
    ``order="independent"`` gives the order-independent variant (Wei & Levoy
    2002 [2]_): non-causal neighbourhoods, every pixel of a level updated at
    once from the previous pass, which vectorizes. ``candidates="k-coherent"``
    compares only the candidates the neighbours' copies suggest (Ashikhmin
    2001 [3]_, Tong et al. 2002 [4]_; :mod:`texsynth.pixel._kcoherent`).
    The options: :class:`Neighborhood` (sizes, footprint, levels) and
    :class:`~texsynth.core.search.Search` (backend, candidates, k).

The engine below is written for one source or several, because Wei's
multi-source synthesis (:mod:`texsynth.pixel._wei_2002`:
:func:`~texsynth.mix_textures`, :func:`~texsynth.synthesize_solid`) *is* this
algorithm with several exemplars, each with its own neighbourhood and weight
image, and with volume outputs: :func:`synthesize_levels` runs the levels,
the visiting orders and the searches, and a :class:`Mixture` passed in by that
module minimises Wei's eq. 1 where a pixel has several sources. With one
source eq. 1 is minimised by the nearest neighbourhood, which is Wei & Levoy
2000; that is all this module does on its own.

References
----------
.. [1] L.-Y. Wei and M. Levoy, "Fast texture synthesis using tree-structured
   vector quantization", SIGGRAPH 2000, pp. 479-488.
   :doi:`10.1145/344779.345009`
.. [2] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
   Stanford University Technical Report TR-2002-01, 2002.
.. [3] M. Ashikhmin, "Synthesizing natural textures", ACM Symposium on
   Interactive 3D Graphics 2001, pp. 217-226. :doi:`10.1145/364338.364405`
.. [4] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
   "Synthesis of bidirectional texture functions on arbitrary surfaces",
   SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
"""

from __future__ import annotations

import contextlib
import numbers
import time
import dataclasses
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from ..core._parallel import parallel_for
from ..core._progress import Progress
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_choice, check_group, max_threads,
                              one_blas_thread, restore_channels, with_channels)
from ..core.neighborhood import (SHAPES, causal_mask, causal_parts, extract, footprint, multilevel_vectors, patch_shape,
                                 plane_vectors)
from ..core.pyramid import gaussian_pyramid
from ..core.search import CANDIDATES, PatchIndex, Search, SequentialExact, SubsetExact, is_auto, lowest_cost, resolve
from ._augment import augmented_source, to_exemplar
from ._kcoherent import coherent_level
from ._options import (check_candidate_options, check_fits, check_levels, check_order_method,
                       check_output_levels, check_output_memory, default_parent_size, search_options)

__all__ = [
    "synthesize_pixels",
    "Neighborhood",
    "PixelSynthesisInfo",
    "SHAPES",
    "CANDIDATES",
]


@dataclass
class PixelSynthesisInfo:
    """Extra results of :func:`synthesize_pixels`, :func:`~texsynth.mix_textures`, :func:`~texsynth.synthesize_solid`.

    Attributes
    ----------
    energy : numpy.ndarray
        Per level, coarsest first: the mean over output pixels of eq. 1,
        ``sum_i a_i (||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2)`` with the
        weights normalised to sum to 1 at each pixel, at the last update.
    stage : numpy.ndarray of int
        The stage of each energy value in synthesis order: stage ``k`` is
        the ``k``-th level synthesised, coarsest first.
    iterations : numpy.ndarray
        Per level: mean number of eq. 1 alternation steps per pixel update.
    level_shapes : list of tuple
        Output shape of each level, coarsest first.
    order, method : str
        Visiting order and search backend actually used (with
        ``candidates="k-coherent"``: the backend that found the k-coherence
        sets).
    candidates : str
        ``"all"`` or ``"k-coherent"``.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time per level, ``{"level 2": ..., "level 1": ..., "level 0": ...}``.
    coordinates : numpy.ndarray or None
        The source-coordinate map of ``docs/conventions.md``, which
        :func:`texsynth.apply_coordinates` renders other channels of the
        exemplar(s) through. :func:`synthesize_pixels`: ``(H, W, 2)`` int,
        the exemplar pixel ``(row, col)`` each output pixel was copied from,
        the centre of its nearest neighbourhood at the finest level (with
        ``candidates="k-coherent"``, Ashikhmin's source map ``s(p)``).
        :func:`~texsynth.mix_textures` with several sources: ``(H, W, n, 2)``, the
        ``p_i`` of eq. 1 whose weighted average ``p = sum_i a_i p_i`` each
        output pixel is, in the pixels of source ``source_index[..., k]``. None
        for solids (see :func:`~texsynth.synthesize_solid`).
    weights : numpy.ndarray or None
        None for copies; for a mixture ``(H, W, n)``, the weights ``a_i``
        (normalised to sum 1 at each pixel), largest first; 0 where a
        source does not take part.
    source_index : numpy.ndarray or None
        For a mixture ``(H, W, n)`` int: the source (index into
        ``sources``) of each slot of ``coordinates``; None otherwise.
        ``apply_coordinates`` then takes one image per source for every
        channel.
    """

    energy: np.ndarray = field(default_factory=lambda: np.zeros(0))
    stage: np.ndarray = field(default_factory=lambda: np.zeros(0, int))
    iterations: np.ndarray = field(default_factory=lambda: np.zeros(0))
    level_shapes: list = field(default_factory=list)
    order: str = "scanline"
    method: str = "exact"
    candidates: str = "all"
    seconds: float = 0.0
    stage_seconds: dict = field(default_factory=dict)
    coordinates: np.ndarray | None = None
    weights: np.ndarray | None = None
    source_index: np.ndarray | None = None


# --------------------------------------------------------------------------- #
# the options
# --------------------------------------------------------------------------- #
@dataclass(frozen=True)
class Neighborhood:
    """The multi-resolution neighbourhood a pixel is matched by (Wei & Levoy 2000, Sec. 3.2).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.Neighborhood(neighborhood_size=7, levels=2)
    Neighborhood(neighborhood_size=7, neighborhood_shape='square', parent_size='auto', levels=2)
    >>> texsynth.Neighborhood(neighborhood_shape="round")
    Traceback (most recent call last):
    ...
    ValueError: neighborhood_shape must be one of 'square', 'disc', got 'round'

    The neighbourhood of an output pixel at one pyramid level, joined to the
    neighbourhood of its parent pixel one level coarser. An option group of
    :func:`synthesize_pixels`, :func:`~texsynth.mix_textures`,
    :func:`~texsynth.synthesize_solid` and
    :func:`~texsynth.synthesize_controlled`
    (``neighborhood=Neighborhood(...)``); on the command line its fields are
    the flags ``--neighborhood-size``, ``--neighborhood-shape``,
    ``--parent-size`` and ``--levels``.

    Parameters
    ----------
    neighborhood_size : int, (int, int) or list
        The neighbourhood at each level: ``k`` (``k x k``) or ``(h, w)``.
        Default 5 (5x5, of which the causal half is used in scanline
        order): the paper's multi-resolution results use 5x5 neighbourhoods
        over 3 levels (Sec. 3.2, 5). With several sources
        (:func:`~texsynth.mix_textures`) also a list with one entry per
        source, because sources differ in texon size (Wei 2002, Sec. 2):
        ``[5, 9]`` is 5x5 for ``sources[0]`` and 9x9 for ``sources[1]``,
        ``[(5, 9), 7]`` a 5-row by 9-column box and 7x7; there a bare tuple
        ``(h, w)`` with exactly two sources is ambiguous and raises
        ``ValueError`` (write ``[5, 9]`` or ``[(5, 9), (5, 9)]``).
    neighborhood_shape : {"square", "disc"} or list of them
        ``"square"``: the whole box, as in Wei & Levoy 2000 (default).
        ``"disc"``: the disc (ellipse, for ``h != w``) inscribed in it, at
        this level and at the parent level: isotropic, about pi/4 of the
        values (:func:`texsynth.core.neighborhood.footprint`). In scanline
        order the causal (L-shaped) half of the shape is used. With several
        sources also a list with one per source.
    parent_size : "auto", int, (int, int) or list
        The full neighbourhood at the parent (coarser) level. ``"auto"``
        (default): about half ``neighborhood_size``, odd (5 -> 3, 9 -> 5),
        as in Wei & Levoy 2000, Fig. 5. With several sources also a list
        with one entry per source (each may be ``"auto"``).
    levels : int
        Pyramid levels (default 3, as in Wei & Levoy 2000). 1 is
        single-resolution.
    """

    neighborhood_size: object = 5
    neighborhood_shape: object = "square"
    parent_size: object = "auto"
    levels: int = 3

    def __post_init__(self):
        check_levels(self.levels)
        per_source = isinstance(self.neighborhood_shape, (list, tuple))
        for i, shape in enumerate(self.neighborhood_shape if per_source else [self.neighborhood_shape]):
            check_choice(shape, f"neighborhood_shape[{i}]" if per_source else "neighborhood_shape", SHAPES)
        # an int is checked here; pairs and lists (one per source) by the function, which knows the sources
        if not isinstance(self.neighborhood_size, (list, tuple, np.ndarray)):
            patch_shape(self.neighborhood_size, "neighborhood_size")
        if not (is_auto(self.parent_size) or isinstance(self.parent_size, (list, tuple, np.ndarray))):
            if not isinstance(self.parent_size, numbers.Integral) or isinstance(self.parent_size, bool):
                raise TypeError(f"parent_size must be 'auto' (about half of neighborhood_size), an int or an "
                                f"(h, w) pair, got {self.parent_size!r}")
            patch_shape(self.parent_size, "parent_size")


# --------------------------------------------------------------------------- #
# validation
# --------------------------------------------------------------------------- #


# --------------------------------------------------------------------------- #
# the sources of eq. 1
# --------------------------------------------------------------------------- #
@dataclass
class Source:
    """One input of eq. 1: exemplar pyramid, neighbourhood N_i, weight images, plane."""

    pyramid: list  # exemplar levels (h, w, C), finest first
    size: tuple  # N_i at each level
    parent_size: tuple  # N_i at the parent level
    axis: int | None  # output axis the view looks along (None: 2-D output)
    name: str
    weights: list = field(default_factory=list)  # normalised weight per output level
    shape: str = "square"  # footprint of N_i at this level and at the parent level
    atlas: object = None  # Search(augment=...): the ExemplarAtlas whose copies' pyramids `pyramid` holds

    @property
    def parent_mask(self):
        """Parent-level footprint, or None for the whole box (the fast shared-layer path)."""
        return None if self.shape == "square" else footprint(self.parent_size, self.shape)

    def vectors(self, level, levels, centers, mask):
        """The exemplar's neighbourhoods at ``centers`` of ``level``: the ``mask`` pixels joined to the parent's."""
        parent = self.pyramid[level + 1] if level + 1 < levels else None
        return multilevel_vectors(self.pyramid[level], parent, centers, self.size, self.parent_size, mode="valid",
                                  mask=mask, parent_mask=self.parent_mask)


def candidate_pixels(source, level, levels):
    """Exemplar pixels whose neighbourhoods (and parents') lie inside the exemplar (inside one of its copies)."""
    if source.atlas is not None:
        return np.concatenate([candidate_pixels(dataclasses.replace(source, pyramid=p, atlas=None), level, levels) + c
                               for p, c in zip(source.atlas.tiles(source.pyramid), source.atlas.corners(level))])
    ex = source.pyramid[level]
    has_parent = level + 1 < levels
    (nh, nw), (ph, pw) = source.size, source.parent_size
    rows = np.arange(nh // 2, ex.shape[0] - nh + nh // 2 + 1)
    cols = np.arange(nw // 2, ex.shape[1] - nw + nw // 2 + 1)
    if has_parent:
        par = source.pyramid[level + 1]
        rows = rows[(rows // 2 >= ph // 2) & (rows // 2 - ph // 2 + ph <= par.shape[0])]
        cols = cols[(cols // 2 >= pw // 2) & (cols // 2 - pw // 2 + pw <= par.shape[1])]
    if rows.size == 0 or cols.size == 0:
        raise ValueError(
            f"{source.name} is only {ex.shape[0]}x{ex.shape[1]} at pyramid level {level} (of levels={levels}), "
            f"too small for the neighbourhood {source.size} with parent {source.parent_size}; "
            f"pass fewer levels (e.g. levels={max(1, level)}) or a smaller neighbourhood"
        )
    rr, cc = np.meshgrid(rows, cols, indexing="ij")
    return np.stack([rr.ravel(), cc.ravel()], 1)


def _output_vectors(out, parent, source, mask):
    """Neighbourhood vectors of every output pixel (or voxel) for one source, toroidal.

    For a volume, the neighbourhood of the view along ``axis`` lies in the
    plane perpendicular to it.
    """
    size, psize = source.size, source.parent_size
    if source.axis is None:
        h, w = out.shape[:2]
        centers = np.argwhere(np.ones((h, w), bool))
        return multilevel_vectors(out, parent, centers, size, psize, mode="wrap", mask=mask,
                                  parent_mask=source.parent_mask)
    return plane_vectors(out, parent, source.axis, size, psize, mask=mask, parent_mask=source.parent_mask)


def _set_dim(source, channels, levels):
    """Dimension of the vectors that decide the k-coherence sets: the whole footprint and the parent's."""
    n = int(footprint(source.size, source.shape).sum())
    if levels > 1:
        n += int(footprint(source.parent_size, source.shape).sum())
    return n * channels


# --------------------------------------------------------------------------- #
# the engine
# --------------------------------------------------------------------------- #
def _noise(sources, weights, channels, dtype, rng, level=0):
    """Noise drawn from the exemplars' pixels (so its histogram matches), mixed by the weights.

    Two uniform draws per pixel whatever the number of sources (which source,
    which of its pixels), so a source of weight zero leaves the noise as it
    is without that source.
    """
    shape = weights[0].shape
    u, v = rng.random(shape), rng.random(shape)
    pick = np.zeros(shape, np.intp)
    cumulative = np.zeros(shape)
    for w in weights[:-1]:
        cumulative = cumulative + w
        pick += u >= cumulative
    out = np.empty(shape + (channels,), dtype)
    for i, src in enumerate(sources):
        pixels = src.pyramid[level].reshape(-1, channels) if src.atlas is None else src.pyramid[level][
            src.atlas.inside(level)]
        here = pick == i
        out[here] = pixels[np.minimum((v[here] * len(pixels)).astype(np.intp), len(pixels) - 1)]
    return out


def _weight_pyramids(raw, levels, spatial_dims):
    """Per level, weights normalised to sum 1 at each pixel (the scale of eq. 1 does not move its minimum)."""
    pyramids = [gaussian_pyramid(w[..., None], levels, spatial_dims=spatial_dims) for w in raw]
    result = []
    for level in range(levels):
        ws = [np.maximum(p[level][..., 0], 0.0) for p in pyramids]
        total = sum(ws)
        result.append([np.divide(w, total, out=np.full_like(w, 1.0 / len(ws)), where=total > 0) for w in ws])
    return result  # [level][source]


@dataclass(frozen=True)
class Mixture:
    """How a synthesis with several sources minimises Wei's eq. 1 where a pixel has more than one.

    The engine finds each source's candidates and distances; these callables
    combine them (:mod:`texsynth.pixel._wei_2002`: Wei's alternation). Where
    one source has positive weight the engine copies its nearest
    neighbourhood itself.

    Attributes
    ----------
    pixel : callable
        Scanline order, one pixel: ``pixel(weights, pixels, direct, choose,
        iterations) -> (p, E, picks, steps)``; ``weights[i]`` is ``a_i``,
        ``pixels[i]`` source ``i``'s candidate pixels, ``direct(i)`` its
        nearest neighbourhood, ``choose(i, p) -> (k, ||N_i(p) -
        N_i(p_k)||^2)`` its term of eq. 1 minimised with ``p`` fixed.
    candidates : callable
        k-coherent candidates, many pixels: ``candidates(a, sq_distances,
        colours, iterations) -> (p, E, picks, steps)``, ``a`` ``(S, M)``,
        per source ``(M, K_i)`` distances and ``(M, K_i, C)`` pixels.
    everywhere : callable
        Independent order: ``everywhere(previous, pixels, a, picks,
        sq_distances, rows, iterations, choose, for_each, result)`` updates
        ``result = (p, E, steps, picks)`` at ``rows`` from the direct
        ``picks`` (or from ``previous``, the last pass); ``choose(i, rows,
        p)`` searches source ``i``, ``for_each(fn)`` calls ``fn(i)`` per
        source.
    """

    pixel: Callable
    candidates: Callable
    everywhere: Callable


@dataclass(frozen=True)
class _Run:
    """What every level of one synthesis shares."""

    levels: int
    order: str  # "scanline" or "independent"
    method: str  # the search backend, resolved
    profile: str  # its named setting (texsynth.core.search.PROFILES)
    iterations: int  # most alternation steps of eq. 1 per pixel
    passes: int  # order-independent passes per level
    seed: int  # of the index builds (their own streams: the synthesis does not depend on them)
    candidates: str = "all"  # "all" exemplar neighbourhoods, or "k-coherent"
    k: int = 1  # size of the k-coherence sets
    tileable: bool = False  # scanline order: the last rows and columns also match the first ones
    mixture: Mixture | None = None  # eq. 1 where a pixel has several sources (texsynth.pixel._wei_2002)

    def index(self, vectors, *key):
        """A search index over ``vectors``, seeded by ``key`` (level, source, which index)."""
        return PatchIndex(vectors, method=self.method, profile=self.profile,
                          rng=np.random.default_rng([self.seed, *key]))


@dataclass
class _Level:
    """One pyramid level of the output, synthesised in place."""

    level: int
    out: np.ndarray  # (H, W, C) or (D, H, W, C)
    parent: np.ndarray | None  # the level above (None at the coarsest)
    sources: list
    centers: list  # per source: its candidate exemplar pixels at this level
    weights: list  # per source: its normalised weight image at this level


def synthesize_levels(sources, shape, channels, dtype, *, levels, order, method, iterations, passes, rng, progress,
                      desc, candidates="all", k=1, tileable=False, mixture=None):
    """Multi-resolution synthesis of ``sources`` (see :func:`prepare_sources`), coarse to fine: ``(out, info)``.

    Every pixel becomes the nearest neighbourhood's pixel (one source of
    positive weight there), or what ``mixture`` (a :class:`Mixture`) makes
    of the sources' candidates (several); ``iterations`` is passed to it.
    """
    if len(sources) > 1 and mixture is None:
        raise ValueError("several sources need a mixture: how eq. 1 combines them (texsynth.pixel._wei_2002)")
    check_output_memory(sources, shape, channels, dtype, order)
    start = time.perf_counter()
    spatial_dims = len(shape)
    raw = [np.broadcast_to(np.asarray(s.weights, dtype=np.float64), shape) for s in sources]
    weights = _weight_pyramids(raw, levels, spatial_dims)
    noise = _noise(sources, weights[0], channels, dtype, rng)
    # Wei & Levoy 2000, Sec. 3.2: Gaussian pyramids of the exemplar and of the noise output.
    out_pyr = [np.array(level, dtype=dtype) for level in gaussian_pyramid(noise, levels, spatial_dims=spatial_dims, mode="wrap")]
    check_output_levels(sources, shape, out_pyr, levels)
    tables = [[candidate_pixels(s, level, levels) for s in sources] for level in range(levels)]
    # scanline: one step per row; independent: `passes` per level, and one parent-only pass per finer level
    total = sum(out_pyr[lv].shape[0] for lv in range(levels)) if order == "scanline" else levels * passes + levels - 1
    profile = "scanline" if order == "scanline" else "solid" if sources[0].axis is not None else "pixels"
    if candidates == "k-coherent":  # the search finds the k-coherence sets: every exemplar position once
        profile = "default"
        n = max(len(t) for t in tables[0])
        used = resolve(method, n, _set_dim(sources[0], channels, levels), profile=profile, queries=n)
    else:
        used = resolve(method, max(len(t) for t in tables[0]), None, profile=profile,
                              queries=int(np.prod(out_pyr[0].shape[:-1])))
    info = PixelSynthesisInfo(order=order, method=used, candidates=candidates)
    # Index builds (PCA subsample, k-means) draw from their own streams, so the
    # synthesis stream does not depend on the search backend or on `iterations`.
    run = _Run(levels, order, used, profile, iterations, passes, int(rng.integers(2**62)), candidates, k, tileable,
               mixture)
    energies, steps = [], []
    cells = None  # k-coherent: the grid cell each output pixel of the last level came from
    # 2-D output: each source's candidate p_i at every pixel of the finest level (the source-coordinate map)
    picked = np.zeros((len(sources),) + tuple(shape), np.intp) if spatial_dims == 2 else None
    with Progress(progress, total, desc) as bar:
        for level in range(levels - 1, -1, -1):
            t_level = time.perf_counter()
            lv = _Level(level, out_pyr[level], out_pyr[level + 1] if level + 1 < levels else None, sources,
                        tables[level], weights[level])
            if candidates == "k-coherent":
                parent_cells = None if cells is None else [tables[level + 1][i][c] for i, c in enumerate(cells)]
                energy, iters, cells = coherent_level(lv, run, bar, parent_cells)
            elif order == "scanline":
                with one_blas_thread():
                    energy, iters = _scanline_level(lv, run, bar, picked if level == 0 else None)
            else:
                # tree searches make many small BLAS calls, which multi-threaded BLAS
                # slows down on a busy machine (tsvq 64^3 at load 3: 31 s -> 13 s)
                with one_blas_thread() if used != "exact" else contextlib.nullcontext():
                    energy, iters = _independent_level(lv, run, bar, picked if level == 0 else None)
            energies.append(float(energy))
            steps.append(float(iters))
            info.level_shapes.append(lv.out.shape[:-1])
            info.stage_seconds[f"level {level}"] = time.perf_counter() - t_level
    info.energy, info.iterations = np.asarray(energies), np.asarray(steps)
    if cells is not None:
        picked[:] = cells  # k-coherent: each source's p_i at the finest level
    if picked is not None and len(sources) == 1:
        info.coordinates = tables[0][0][picked[0]].astype(np.int64)
    elif picked is not None:  # p = sum_i a_i p_i: source i's p_i with weight a_i, largest first
        coords = np.stack([tables[0][i][picked[i]] for i in range(len(sources))], axis=2).astype(np.int64)
        order = np.argsort(-np.stack(weights[0], axis=2), axis=2, kind="stable")
        info.weights = np.take_along_axis(np.stack(weights[0], axis=2), order, axis=2)
        info.coordinates = np.take_along_axis(coords, order[..., None], axis=2)
        info.source_index = order
    info.stage = np.arange(levels)
    info.seconds = time.perf_counter() - start
    return out_pyr[0], info


# --------------------------------------------------------------------------- #
# scanline order (Wei & Levoy 2000, Table 1)
# --------------------------------------------------------------------------- #
@dataclass
class _LineTable:
    """One source at one level in scanline order: its candidates and how they are searched.

    The causal neighbourhood splits into the rows above (and the parent
    level), fixed once a scanline starts, and the pixels left of the centre,
    which change as the line is written. Exact search keeps the parts apart
    (:class:`~texsynth.core.search.SequentialExact`: one matrix product per
    line, a small dot product per pixel); an approximate index is queried
    pixel by pixel with the joined vector.
    """

    src: Source
    weight: np.ndarray  # a_i at this level
    above: np.ndarray  # mask of the fixed part
    pixels: np.ndarray  # candidate pixel values p_i
    cols: np.ndarray  # per output column, the columns of its left part
    exact: SequentialExact | None = None  # parts: fixed, left, pixel
    index: PatchIndex | None = None  # [fixed, left]
    index_p: PatchIndex | None = None  # [fixed, left, pixel], for eq. 1 with several sources
    q: np.ndarray | None = None  # approximate search: this line's fixed parts
    i: int = 0  # the source's position in the list


def _scanline_level(lv, run, bar, picked=None):
    """Wei & Levoy 2000, Table 1: visit pixels in scanline order, causal neighbourhoods.

    ``picked`` (an ``(n_sources, H, W)`` int array, or None) receives the
    candidate ``p_i`` of every source at each pixel (the one it copies, or
    the ones eq. 1 averages)."""
    height, width, channels = lv.out.shape
    exact = run.method == "exact"
    tabs = []
    for i, (src, cen, a) in enumerate(zip(lv.sources, lv.centers, lv.weights)):
        above, left, _ = causal_parts(src.size, src.shape)
        fixed = src.vectors(lv.level, run.levels, cen, above)
        lefts = extract(src.pyramid[lv.level], cen, src.size, mode="valid")[:, left].reshape(len(cen), -1)
        pixels = np.ascontiguousarray(src.pyramid[lv.level][cen[:, 0], cen[:, 1]])
        nw = src.size[1]
        t = _LineTable(src, a, above, pixels, (np.arange(width)[:, None] - nw // 2 + np.arange(nw // 2)[None, :]) % width,
                       i=i)
        if exact:
            t.exact = SequentialExact(fixed, lefts, pixels)
        else:
            full = np.concatenate([fixed, lefts], axis=1)
            t.index = run.index(full, lv.level, i, 0)
            if len(lv.sources) > 1:
                t.index_p = run.index(np.concatenate([full, pixels], axis=1), lv.level, i, 1)
        tabs.append(t)
    single = len(tabs) == 1
    wraps = [_WrapSearch(lv, run, t) for t in tabs] if run.tileable else None
    energy = 0.0
    steps = 0
    line_centers = np.stack([np.zeros(width, np.intp), np.arange(width)], 1)
    for r in range(height):
        # tileable: the columns [start, stop) where no source's causal window wraps; the others search by
        # _WrapSearch
        start, stop = (0, width) if wraps is None else _unwrapped(wraps, r)
        line_centers[:, 0] = r
        row = lv.out[r]
        active = [t for t in tabs if t.weight[r].any()]
        for t in active:
            src = t.src
            q = multilevel_vectors(lv.out, lv.parent, line_centers, src.size, src.parent_size, mode="wrap",
                                   mask=t.above, parent_mask=src.parent_mask)
            if exact:
                t.exact.start(q)
            else:
                t.q = q
        for j in range(start):
            e, n_iter = _solve_wrapped(row, r, j, wraps, active, run, picked)
            energy += e
            steps += n_iter
        if single and exact:  # Wei & Levoy 2000: p = the exemplar pixel of nearest neighbourhood
            energy += _scanline_single(row, tabs[0], None if picked is None else picked[0, r], start, stop)
            steps += stop - start
        else:
            for j in range(start, stop):
                if single:
                    t = tabs[0]
                    k, d_k = _query_one(t.index, np.concatenate([t.q[j], row[t.cols[j]].ravel()]))
                    row[j] = t.pixels[k]
                    if picked is not None:
                        picked[0, r, j] = k
                    energy += d_k
                    steps += 1
                    continue
                e, n_iter = _solve_pixel(row, j, r, active, run, exact, None if picked is None else picked[:, r, j])
                energy += e
                steps += n_iter
        for j in range(stop, width):
            e, n_iter = _solve_wrapped(row, r, j, wraps, active, run, picked)
            energy += e
            steps += n_iter
        bar.advance({"level": lv.level, "row": r})
    n = height * width
    return energy / n, steps / n


def _scanline_single(row, t, picked=None, start=0, stop=None):
    """Columns ``start`` to ``stop`` of one scanline of single-source exact synthesis: the per-pixel loop kept
    minimal (``picked``: the line's chosen candidates, or None)."""
    exact, pixels, cols = t.exact, t.pixels, t.cols
    energy = 0.0
    for j in range(start, len(row) if stop is None else stop):
        k, d = exact.nearest(j, row[cols[j]].ravel())  # the p_1 of least ||N(p) - N(p_1)||^2
        row[j] = pixels[k]
        energy += d
        if picked is not None:
            picked[j] = k
    return energy


class _WrapSearch:
    """Scanline order, ``tileable=True``: where a causal window wraps, the pixels synthesised before it.

    Wei & Levoy's output is toroidal, but a causal neighbourhood that wraps
    compares the wrong pixels for a seamless tiling: the first rows and
    columns read the not yet synthesised end of the level (noise) above and
    left of them, and the last ones never see the first rows and columns
    they meet across the wrap. Both show as a seam when the output is tiled.
    Here a pixel whose window wraps (the first and last ``h//2`` rows and
    ``w//2`` columns of each level) compares the window pixels synthesised
    before it in scanline order, found toroidally (so the last rows match
    the first rows below them), and the parent's neighbourhood. The
    coarsest level, which has no parent, keeps the noise of its causal
    window too: it is the synthesis's only source of randomness (without
    it the first pixel would have nothing to match). Exact search with the
    other terms left out (:class:`~texsynth.core.search.SubsetExact`): one
    product with the candidates per pixel, for a few percent of the pixels.
    (This rule is texsynth's; Wei & Levoy's papers were not at hand to say
    how they treat the wrap.) One search per source of
    :func:`~texsynth.mix_textures`; eq. 1 then alternates over these
    distances as over the causal ones (:func:`_solve_wrapped`).
    """

    def __init__(self, lv, run, table):
        src = table.src
        self.lv, self.table, self.src = lv, table, src
        _, _, self.full = causal_parts(src.size, src.shape)
        vectors = src.vectors(lv.level, run.levels, lv.centers[table.i], self.full)
        self.search = SubsetExact(vectors)
        self.by_pixel = SequentialExact(table.pixels)  # eq. 1's ||p - p_i||^2 term
        self.channels = lv.out.shape[-1]
        self.parent_dims = vectors.shape[1] - int(self.full.sum()) * self.channels
        h, w = src.size
        self.offsets = np.mgrid[-(h // 2):h - h // 2, -(w // 2):w - w // 2]  # (2, h, w) window offsets
        # the coarsest level compares its causal window's noise as Wei & Levoy do; finer levels have the parent
        self.always = causal_mask(src.size) & self.full if lv.parent is None else np.zeros_like(self.full)
        self.kept = {}  # window pixels compared -> the dimensions of the vectors they are

    def unwrapped(self, r):
        """The columns ``[start, stop)`` of row ``r`` whose causal window does not wrap (none in the first and
        last rows)."""
        (h, w), (height, width) = self.src.size, self.lv.out.shape[:2]
        if r < h // 2 or r + h // 2 >= height:
            return width, width
        return w // 2, width - w // 2

    def _query(self, r, j):
        """The query of ``(r, j)`` and the dimensions it knows: the window pixels synthesised before it."""
        height, width = self.lv.out.shape[:2]
        rows = (r + self.offsets[0]) % height
        cols = (j + self.offsets[1]) % width
        known = ((rows * width + cols < r * width + j) & self.full) | self.always  # visited before (r, j)
        key = known.tobytes()
        if key not in self.kept:
            self.kept[key] = np.concatenate([np.repeat(known[self.full], self.channels),
                                             np.ones(self.parent_dims, bool)])
        src = self.src
        q = multilevel_vectors(self.lv.out, self.lv.parent, np.array([[r, j]]), src.size, src.parent_size, mode="wrap",
                               mask=self.full, parent_mask=src.parent_mask)[0]
        return q, self.kept[key]

    def distances(self, r, j):
        """``||N(p) - N(p_i)||^2`` over the window pixels synthesised before ``(r, j)``, to every candidate."""
        return self.search.sq_distances(*self._query(r, j))

    def nearest(self, r, j):
        """The candidate of least :meth:`distances`: ``(index, squared distance)``."""
        return self.search.nearest(*self._query(r, j))

    def nearest_with(self, distances, p):
        """The candidate minimising ``distances + ||p - p_i||^2`` (one term of eq. 1 with ``p`` fixed)."""
        return self.by_pixel.nearest_with(distances, 0, p)


def _unwrapped(wraps, r):
    """The columns ``[start, stop)`` of row ``r`` where no source's causal window wraps."""
    spans = [w.unwrapped(r) for w in wraps]
    start, stop = max(a for a, _ in spans), min(b for _, b in spans)
    return (start, stop) if start < stop else (stop, stop)


def _solve_wrapped(row, r, j, wraps, active, run, picked):
    """Pixel ``(r, j)`` where a window wraps: eq. 1 over the synthesised neighbours; returns (E, iterations).

    One source: its nearest candidate (Wei & Levoy 2000). Several: eq. 1
    by the run's :class:`Mixture`, as in :func:`_solve_pixel`, over the
    :class:`_WrapSearch` distances.
    """
    if len(wraps) > 1:
        return _solve_pixel(row, j, r, active, run, True, None if picked is None else picked[:, r, j], wrapped=wraps)
    k, d = wraps[0].nearest(r, j)
    row[j] = wraps[0].table.pixels[k]
    if picked is not None:
        picked[0, r, j] = k
    return max(float(d), 0.0), 1


def _query_one(index, vector):
    idx, d2 = index.query(vector[None], k=1)
    return idx[0, 0], d2[0, 0]


def _solve_pixel(row, j, r, active, run, exact, picks=None, wrapped=None):
    """Eq. 1 at one pixel; writes p into ``row[j]`` (and each source's ``p_i`` into ``picks``, if given),
    returns (E, iterations).

    ``wrapped`` (tileable output, a pixel whose window wraps): each source's
    :class:`_WrapSearch`, whose exact distances replace the causal ones.

    With one source of positive weight, eq. 1 is minimised directly (Wei
    2002: choose the p_i of nearest neighbourhood and set p = p_i, which is
    Wei & Levoy 2000). With several, the run's :class:`Mixture` combines
    the sources' searches.
    """
    terms = []  # (table, a_i, neighbourhood distances to all candidates, or the query vector)
    for t in active:
        a = t.weight[r, j]
        if a <= 0:
            continue
        if wrapped is not None:
            terms.append((t, a, wrapped[t.i].distances(r, j)))
            continue
        lv = row[t.cols[j]].ravel()
        if exact:
            terms.append((t, a, t.exact.distances(j, lv)))  # ||N_i(p) - N_i(p_i)||^2, all p_i
        else:
            terms.append((t, a, np.concatenate([t.q[j], lv])))
    if len(terms) == 1:
        t, _, x = terms[0]
        if exact:
            choice, cost = lowest_cost(x[None])
            k, nd = choice[0], cost[0]
        else:
            k, nd = _query_one(t.index, x)
        row[j] = t.pixels[k]
        if picks is not None:
            picks[t.i] = k
        return nd, 1

    def direct(i):
        """Source i's p_i of nearest neighbourhood."""
        t, _, x = terms[i]
        return lowest_cost(x[None])[0][0] if exact else _query_one(t.index, x)[0]

    def choose(i, p):
        """The p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2 (one term of eq. 1, p fixed), and its
        neighbourhood distance."""
        t, _, x = terms[i]
        if wrapped is not None:
            k = wrapped[t.i].nearest_with(x, p)
            return k, x[k]
        if exact:  # + ||p - p_i||^2 ranked on the pixel part
            k = t.exact.nearest_with(x, 2, p)
            return k, x[k]
        k, d = _query_one(t.index_p, np.concatenate([x, p]))
        return k, d - ((t.pixels[k] - p) ** 2).sum()

    p, energy, ks, n_iter = run.mixture.pixel([a for _, a, _ in terms], [t.pixels for t, _, _ in terms], direct,
                                              choose, run.iterations)
    row[j] = p
    if picks is not None:
        for (t, _, _), k in zip(terms, ks):
            picks[t.i] = k
    return energy, n_iter


# --------------------------------------------------------------------------- #
# order-independent (Wei & Levoy 2002)
# --------------------------------------------------------------------------- #
@dataclass
class _PassTable:
    """One source at one level in independent order: its candidates and their indexes."""

    src: Source
    full: np.ndarray  # mask of the non-causal neighbourhood
    pixels: np.ndarray  # candidate pixel values p_i
    index: PatchIndex | None = None  # N_i(p) alone: a source's direct solution
    index_p: PatchIndex | None = None  # [N_i(p), p]: one term of eq. 1 with p fixed
    by_parity: list | None = None  # (candidate subset, index) per row/column parity: the parent alone
    parity: np.ndarray | None = None  # row/column parity of every output pixel


def _independent_level(lv, run, bar, picked=None):
    """Wei & Levoy 2002: non-causal neighbourhoods, all pixels updated at once per pass.

    ``picked`` (an ``(n_sources, H, W)`` int array, or None) receives each
    source's candidate ``p_i`` at every pixel in the last pass.

    Every pass reads the previous pass's output (Jacobi order), so the
    search for all pixels is one batched query per source. A Jacobi update
    of blurred noise settles on flat, self-consistent regions, so each level
    starts from a better guess: the coarsest from noise drawn from the
    coarsest exemplar level (its contrast matches), finer ones from a first
    pass that matches the parent's neighbourhood alone, among the exemplar
    pixels of the same row and column parity, so that the four children of
    one parent pixel become a coherent 2x2 block rather than four copies.
    """
    out, parent = lv.out, lv.parent
    flat = out.reshape(-1, out.shape[-1])
    a_flat = [w.reshape(-1) for w in lv.weights]
    volume = lv.sources[0].axis is not None
    # A voxel of a solid has every view: the alternation of eq. 1 starts from
    # the previous pass, so the sources' direct solutions (the "index" search)
    # are needed only for pixels with a single source of positive weight.
    direct = not volume or bool(np.any(sum((a > 0).astype(int) for a in a_flat) == 1))
    threads = max_threads() if run.method == "kdtree" else 1
    shared = {}  # views given as one image share their tables and indexes (built once)
    tabs = []
    for i, (src, cen) in enumerate(zip(lv.sources, lv.centers)):
        key = (id(src.pyramid[lv.level]), src.size, src.parent_size, src.shape)
        if key not in shared:
            shared[key] = _level_table(src, cen, lv.level, run, i, direct=direct, several=len(lv.sources) > 1,
                                       with_parent=parent is not None)
        t = dataclasses.replace(shared[key], src=src)
        if parent is not None:
            t.parity = _plane_parity(out.shape[:-1], src.axis)
        tabs.append(t)
    if parent is None:
        out[...] = _noise(lv.sources, lv.weights, out.shape[-1], out.dtype, np.random.default_rng([run.seed, lv.level]),
                          lv.level)
    energy = np.zeros(len(flat))
    n_iter = np.zeros(len(flat))
    schedule = ([True] if parent is not None else []) + [False] * run.passes
    for parent_only in schedule:
        queries = []
        for t in tabs:
            mask = np.zeros(t.src.size, bool) if parent_only else t.full
            queries.append(_output_vectors(out, parent, t.src, mask))
        chosen = [] if picked is not None else None
        p, energy, n_iter = _solve_all(flat, tabs, a_flat, queries, parent_only, 1 if parent_only else run.iterations,
                                       threads, chosen, run.mixture)
        flat[:] = p
        if chosen:
            picked.reshape(len(tabs), -1)[:] = chosen
        bar.advance({"level": lv.level, "parent_only": parent_only})
    return energy.mean(), n_iter.mean()


def _level_table(src, cen, level, run, i, *, direct, several, with_parent):
    """Candidate pixels and the indexes over their neighbourhoods at one level, for one source."""
    _, _, full = causal_parts(src.size, src.shape)
    vec = src.vectors(level, run.levels, cen, full)
    pixels = np.ascontiguousarray(src.pyramid[level][cen[:, 0], cen[:, 1]])
    t = _PassTable(src, full, pixels)
    if direct:  # N_i(p) alone: Wei & Levoy 2000, a source's direct solution
        t.index = run.index(vec, level, i, 0)
    if several:  # [N_i(p), p]: one term of eq. 1 with p fixed
        t.index_p = run.index(np.concatenate([vec, pixels], axis=1), level, i, 1)
    if with_parent:  # the parent's neighbourhood alone, per row/column parity of the candidate
        coarse = src.vectors(level, run.levels, cen, np.zeros(src.size, bool))
        t.by_parity = []
        for c in range(4):
            subset = np.flatnonzero((cen[:, 0] % 2) * 2 + cen[:, 1] % 2 == c)
            subset = subset if subset.size else np.arange(len(cen))
            t.by_parity.append((subset, run.index(coarse[subset], level, i, 2, c)))
    return t


def _plane_parity(shape, axis):
    """Row and column parity (0..3) of every output pixel in the plane of a source's neighbourhood."""
    plane = [d for d in range(len(shape)) if d != axis] if axis is not None else [0, 1]
    grids = np.indices(shape)
    return ((grids[plane[0]] % 2) * 2 + grids[plane[1]] % 2).reshape(-1)


def _query(t, parent_only, q, sel):
    """Nearest candidate of each query vector: (indices, squared distances)."""
    if not parent_only:
        idx, d2 = t.index.query(q, k=1)
        return idx[:, 0], d2[:, 0]
    k, d = np.empty(len(q), np.intp), np.empty(len(q))
    parity = t.parity[sel]
    for c, (subset, index) in enumerate(t.by_parity):
        m = parity == c
        if m.any():
            idx, d2 = index.query(q[m], k=1)
            k[m], d[m] = subset[idx[:, 0]], d2[:, 0]
    return k, d


def _solve_all(flat, tabs, a_flat, queries, parent_only, iterations, threads=1, chosen=None, mixture=None):
    """Eq. 1 at every pixel at once (vectorized over pixels), as :func:`_solve_pixel`.

    ``chosen``, a list, receives each source's candidate ``p_i`` per pixel: the ones ``p`` averages."""
    n = len(flat)
    everything = np.arange(n)
    n_on = sum((a > 0).astype(int) for a in a_flat)
    # A volume starts the alternation from the previous pass (below), so it
    # needs the direct solutions only where a single view has weight.
    from_previous = not parent_only and tabs[0].src.axis is not None
    # Each source's direct solution: p_i of nearest neighbourhood (Wei & Levoy 2000).
    ks, nds = [np.zeros(n, np.intp) for _ in tabs], [np.zeros(n) for _ in tabs]

    def direct(i):
        a, q = a_flat[i], queries[i]
        on = np.flatnonzero((a > 0) & (n_on == 1)) if from_previous else np.flatnonzero(a > 0)
        if on.size:
            ks[i][on], nds[i][on] = _query(tabs[i], parent_only, q[on], on)

    # The sources' searches are independent; kd-tree queries run mostly in scipy's cKDTree, which releases the
    # GIL, so two views search at once on two cores (measured 1.3-2x on 32^3 solids; exact search already uses
    # every core inside BLAS and gets single-threaded calls).
    parallel_for(direct, len(tabs), threads)
    # One source at a pixel: that is the minimum of eq. 1. (The parent-only
    # first pass stops here everywhere: it is only a starting guess.)
    pixels = [t.pixels for t in tabs]
    p, energy = average_picks(pixels, a_flat, ks, nds, everything)
    final = [k.copy() for k in ks]  # the p_i of each pixel's p (the starts below read ks)
    if chosen is not None:
        chosen.extend(final)
    n_iter = np.ones(n)
    multi = np.flatnonzero(n_on > 1)
    if parent_only or multi.size == 0:
        return p, energy, n_iter

    def choose(i, rows, p_rows):
        """At ``rows``, source i's p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2, and its neighbourhood
        distance."""
        t = tabs[i]
        idx, d2 = t.index_p.query(np.concatenate([queries[i][rows], p_rows], axis=1), k=1)
        return idx[:, 0], d2[:, 0] - ((t.pixels[idx[:, 0]] - p_rows) ** 2).sum(1)

    mixture.everywhere(flat if from_previous else None, pixels, a_flat, ks, nds, multi, iterations, choose,
                       lambda fn: parallel_for(fn, len(tabs), threads), (p, energy, n_iter, final))
    return p, energy, n_iter


def average_picks(pixels, a_flat, ks, nds, sel):
    """At pixels ``sel``: p = sum_i a_i p_i (sum a_i = 1) and eq. 1 at that p.

    ``pixels[i]`` are source ``i``'s candidate pixels, ``ks[i]`` its picks at
    ``sel`` and ``nds[i]`` their neighbourhood distances; with one source of
    weight 1, ``p`` is its pick and E its distance (Wei & Levoy 2000).
    """
    picks = [c[k] for c, k in zip(pixels, ks)]
    p = np.zeros_like(picks[0])
    for a, q in zip(a_flat, picks):
        p += a[sel, None].astype(p.dtype) * q
    energy = np.zeros(len(sel))
    for a, q, nd in zip(a_flat, picks, nds):
        energy += a[sel] * (((p - q) ** 2).sum(1) + nd)
    return p, energy


# --------------------------------------------------------------------------- #
# public functions
# --------------------------------------------------------------------------- #
def prepare_sources(images, names, sizes, parent_sizes, axes, levels, size_name, work_dtype=None, shapes=None):
    """Convert the sources once and check their channels and neighbourhoods.

    The same image object passed twice (one view for all axes of a solid) gets
    one pyramid, so the engine builds its search indexes once. ``work_dtype``
    forces the working precision (the returned ``dtype`` is the output's).
    """
    converted = [with_channels(as_image(img, name)) for img, name in zip(images, names)]
    channels = converted[0][0].shape[-1]
    for (img, _), name in zip(converted, names):
        if img.shape[-1] != channels:
            raise ValueError(
                f"{name} has {img.shape[-1]} channels but {names[0]} has {channels}; "
                f"pass sources with the same channels (e.g. convert all to RGB or all to grey)"
            )
    dtype = np.float32 if all(img.dtype == np.float32 for img, _ in converted) else np.float64
    work = dtype if work_dtype is None else work_dtype
    sources, pyramids = [], {}
    for i, ((img, _), name, axis) in enumerate(zip(converted, names, axes)):
        size = patch_shape(sizes[i], f"{size_name}[{i}]" if len(images) > 1 else size_name)
        auto = is_auto(parent_sizes[i])
        psize = default_parent_size(size) if auto else patch_shape(parent_sizes[i], "parent_size")
        check_fits(img, size, name, size_name)
        check_fits(img, psize, name, size_name.replace("neighborhood", "parent") if not auto else size_name)
        if id(images[i]) not in pyramids:
            pyramids[id(images[i])] = [
                np.asarray(level, dtype=work) for level in gaussian_pyramid(img.astype(work, copy=False), levels)
            ]
        shape = "square" if shapes is None else shapes[i]
        sources.append(Source(pyramids[id(images[i])], size, psize, axis, name, shape=shape))
    return sources, channels, dtype, converted[0][1]


def synthesize_pixels(
    exemplar,
    size,
    *,
    neighborhood=Neighborhood(),
    order="scanline",
    search=Search(),
    passes=2,
    tileable=False,
    rng=None,
    progress=False,
    return_info=False,
):
    """Wei-Levoy multi-resolution pixel synthesis (scanline or order-independent).

    Examples
    --------
    >>> import texsynth
    >>> bread = texsynth.data.load("bread")[:24, :24]
    >>> out = texsynth.synthesize_pixels(bread, 20, neighborhood=texsynth.Neighborhood(levels=2), rng=0)
    >>> out.shape, out.dtype
    ((20, 20, 3), dtype('float64'))

    Synthesises a pyramid coarse to fine: every output pixel becomes the
    exemplar pixel whose multi-resolution neighbourhood best matches its
    own, in scanline order with causal neighbourhoods [1]_ or in passes
    over every pixel at once [2]_.

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    size : int or (int, int)
        Output ``(height, width)``.
    neighborhood : Neighborhood
        The neighbourhood at each level, its footprint, the parent's and the
        pyramid levels (:class:`Neighborhood`; default 5x5 squares with 3x3
        parents over 3 levels, as in [1]_).
    order : {"scanline", "independent"}
        ``"scanline"``: Wei & Levoy 2000, causal neighbourhoods, sequential.
        ``"independent"``: Wei & Levoy 2002 [2]_, non-causal neighbourhoods,
        every pixel of a level updated at once per pass.
    search : Search
        How a pixel's neighbourhood is matched
        (:class:`~texsynth.core.search.Search`): ``method`` the backend
        (``"auto"``, ``"exact"``, ``"kdtree"``, ``"tsvq"``), ``candidates``
        ``"all"`` (``"auto"``, Wei & Levoy) or ``"k-coherent"`` (Ashikhmin
        [3]_, Tong et al. [4]_), ``k`` the size of the k-coherence sets
        (``"auto"``: 1, Ashikhmin's search), ``augment`` the exemplar's
        flipped or rotated copies, each with its own pyramid, as candidates
        too (with ``candidates="all"``). See Notes.
    passes : int
        ``order="independent"`` only: passes over each level (default 2).
    tileable : bool
        Make the output tile seamlessly. The output is toroidal either way
        (windows wrap), but in scanline order a causal window that wraps
        reads noise above and left of the first rows and columns, and the
        last ones never see the first rows and columns they meet across the
        wrap, so the tiled output shows a seam (seam visibility 1.5-3.5 on
        pebbles, where 1 is no seam). With True, the pixels whose window
        wraps (the first and last ``h//2`` rows and ``w//2`` columns of each
        level) compare the wrapped pixels synthesised before them instead,
        by exact search (0.6-1.7, one outlier 2.7 in ten seeds; see
        ``docs/methods/wei_levoy.md``). In independent order every
        neighbourhood is whole and the output tiles either way (about 1.0);
        True changes nothing there. Not with ``candidates="k-coherent"``.
    rng : None, int or numpy.random.Generator
        Seeds the initial noise. Same seed, same output.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return a :class:`PixelSynthesisInfo`.

    Returns
    -------
    image : numpy.ndarray
        ``size`` with the exemplar's channel layout; toroidal (seamless
        when tiled with ``tileable=True`` or in independent order).
    info : PixelSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid exemplar, size, option, or a neighbourhood larger than
        the exemplar (at its finest or coarsest pyramid level).

    Notes
    -----
    Each output pixel ``p`` becomes the exemplar pixel ``p_1`` minimising
    ``||N(p) - N(p_1)||^2`` over the multi-level neighbourhood ``N`` (this
    level's causal part, the parent's full part): eq. 1 of Wei 2002 with one
    source, which :func:`~texsynth.mix_textures` reduces to exactly. Candidate
    neighbourhoods lie wholly inside the exemplar; the output is toroidal.
    The output pyramid starts as a Gaussian pyramid of noise drawn from the
    exemplar's pixels (so its histogram matches the exemplar's).

    *Search.* ``method``: in scanline order ``"auto"`` is exact search done
    one scanline at a time (the fastest here); ``"kdtree"``/``"tsvq"`` query
    per pixel. In independent order ``"auto"`` is exact for small problems
    and ``"kdtree"`` for large ones (profiles ``"scanline"`` and
    ``"pixels"``). With ``candidates="k-coherent"`` the backend finds the
    k-coherence sets. ``candidates="all"`` compares every exemplar
    neighbourhood, so the best match is global. ``candidates="k-coherent"``
    compares only the *coherent* candidates
    (:class:`~texsynth.core.search.KCoherence`): for every already
    synthesised neighbour ``p + d`` of ``p``, the exemplar position that
    continues its copy, ``s(p + d) - d``, and that position's ``k - 1``
    most similar ones; below the coarsest level also the positions the
    parent level's copies predict for the neighbourhood's other pixels. The
    distance is the same as with ``"all"``. Copies then run on in pieces,
    which keeps elements (bricks, tiles) in one piece where the global best
    match breaks them up, and costs a few distances per pixel instead of one
    per exemplar position: the choice for structured textures and large
    outputs. Scanline order only; the coarsest level starts from random
    exemplar positions (Ashikhmin), and a continued copy that leaves the
    exemplar restarts at a random position (his rule). ``k = 1`` is
    Ashikhmin's search, the continuations alone; a larger ``k`` adds similar
    positions (Tong et al. use small ``k``; their values could not be
    checked here), so pieces end where they fit rather than only where the
    copy runs out, at about ``k`` times the cost.

    The same seed gives the same output, and k-coherent search suits a
    structured exemplar:

    >>> import numpy as np
    >>> bool(np.array_equal(out, texsynth.synthesize_pixels(bread, 20, neighborhood=texsynth.Neighborhood(levels=2),
    ...                                                     rng=0)))
    True
    >>> bricks = texsynth.synthesize_pixels(texsynth.data.load("brick")[:32, :32], 24, rng=0,
    ...                                     neighborhood=texsynth.Neighborhood(levels=2),
    ...                                     search=texsynth.Search(candidates="k-coherent"))

    References
    ----------
    .. [1] L.-Y. Wei and M. Levoy, "Fast texture synthesis using
       tree-structured vector quantization", SIGGRAPH 2000, pp. 479-488.
       :doi:`10.1145/344779.345009`
    .. [2] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
       Stanford University Technical Report TR-2002-01, 2002.
    .. [3] M. Ashikhmin, "Synthesizing natural textures", ACM Symposium on
       Interactive 3D Graphics 2001, pp. 217-226. :doi:`10.1145/364338.364405`
    .. [4] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
    """
    size = as_size(size)
    nb = check_group(neighborhood, Neighborhood, "neighborhood")
    method, candidates, k = search_options(search)
    check_order_method(order, method, passes)
    tileable = check_bool(tileable, "tileable")
    k = check_candidate_options(candidates, k, order, tileable)
    rng = as_rng(rng)
    sources, channels, dtype, grey = prepare_sources(
        [exemplar], ["exemplar"], [nb.neighborhood_size], [nb.parent_size], [None], nb.levels, "neighborhood_size",
        shapes=[check_choice(nb.neighborhood_shape, "neighborhood_shape", SHAPES)],
    )
    sources[0] = augmented_source(sources[0], search.augment, nb.levels, candidates)  # the exemplar's copies too
    sources[0].weights = 1.0
    out, info = synthesize_levels(
        sources, size, channels, dtype, levels=nb.levels, order=order, method=method, iterations=1,
        passes=passes, rng=rng, progress=progress, desc="Wei-Levoy", candidates=candidates, k=k,
        tileable=tileable and order == "scanline",
    )
    info.coordinates = to_exemplar(sources, info.coordinates)
    out = restore_channels(out, grey)
    return (out, info) if return_info else out
