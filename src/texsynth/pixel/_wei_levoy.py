"""Wei-Levoy pixel synthesis, Wei's multi-source texture mixtures and solid textures.

One engine implements the three functions of this module, because Wei's
multi-source algorithm [2]_ *is* Wei-Levoy synthesis [1]_ with several sources:

:func:`synthesize_pixels`
    Wei & Levoy 2000: multi-resolution pixel synthesis. The output pyramid
    starts as noise drawn from the exemplar's pixels; levels are synthesised
    coarse to fine; each pixel becomes the exemplar pixel whose causal
    (L-shaped) neighbourhood at this level, joined to the full neighbourhood
    of its parent one level coarser, is nearest. Toroidal output (seamless
    when tiled with ``tileable=True``).
    ``order="independent"`` gives the order-independent variant (Wei & Levoy
    2002 [3]_): non-causal neighbourhoods, every pixel of a level updated at
    once from the previous pass, which vectorizes.
:func:`mix_textures`
    Wei 2002, eq. 1: every source ``i`` has a weight image ``w_i`` and its own
    neighbourhood ``N_i``; each output pixel ``p`` minimises

    .. math:: E(p, \\{p_i\\}) = \\sum_i w_i \\left(\\|p - p_i\\|^2
              + \\|N_i(p) - N_i(p_i)\\|^2\\right)                  \\quad (1)

    by alternation: fix ``p``, choose each ``p_i``; fix the ``p_i``, set ``p``
    to their weighted average; stop when ``E`` stops falling.
:func:`synthesize_solid`
    Wei 2002, second specialisation: the sources are 2-D views of a solid
    along the volume axes; the neighbourhood of a voxel for the view along
    axis ``a`` lies in the plane perpendicular to ``a``.

References
----------
.. [1] L.-Y. Wei and M. Levoy, "Fast texture synthesis using tree-structured
   vector quantization", SIGGRAPH 2000, pp. 479-488.
   :doi:`10.1145/344779.345009`
.. [2] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
   Sketches & Applications. :doi:`10.1145/965400.965507`
.. [3] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
   Stanford University Technical Report TR-2002-01, 2002.
"""

from __future__ import annotations

import contextlib
import math
import numbers
import time
from concurrent.futures import ThreadPoolExecutor
import dataclasses
from dataclasses import dataclass, field

import numpy as np

from ..core import search
from ..core._progress import Progress
from ..core._validate import MAX_ITERATIONS, one_blas_thread
from ..core._validate import (as_image, as_rng, as_size, check_bool, check_memory, check_positive_int, max_threads,
                              restore_channels, with_channels)
from ..core.neighborhood import causal_mask, extract, multilevel_vectors, patch_shape
from ..core.pyramid import gaussian_pyramid
from ..core.search import (CANDIDATES, KCoherence, PatchIndex, SequentialExact, candidate_sq_distances,
                           check_candidates, nearest_candidates, neighbor_sources)

__all__ = [
    "synthesize_pixels",
    "mix_textures",
    "synthesize_solid",
    "PixelSynthesisInfo",
    "ORDERS",
    "SHAPES",
    "CANDIDATES",
]

#: Visiting orders: Wei & Levoy 2000 (scanline) and 2002 (order-independent).
ORDERS = ("scanline", "independent")
#: Neighbourhood footprints inside the ``(h, w)`` box: the whole box, or the inscribed disc (ellipse).
SHAPES = ("square", "disc")

# Relative tolerance of "E stops falling" (eq. 1 alternation).
_STOP_TOLERANCE = 1e-9
# Working precision of solid synthesis (the output keeps the views' dtype).
_SOLID_DTYPE = np.float32
# Volume slices whose neighbourhoods are gathered at once (bounds memory).
_SLICE_CHUNK = 8


@dataclass
class PixelSynthesisInfo:
    """Extra results of :func:`synthesize_pixels`, :func:`mix_textures` and :func:`synthesize_solid`.

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
        :func:`mix_textures` with several sources: ``(H, W, n, 2)``, the
        ``p_i`` of eq. 1 whose weighted average ``p = sum_i a_i p_i`` each
        output pixel is, in the pixels of source ``source_index[..., k]``. None
        for solids (see :func:`synthesize_solid`).
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
# validation
# --------------------------------------------------------------------------- #
def check_choice(value, allowed, name):
    if not isinstance(value, str) or value not in allowed:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, allowed))}, got {value!r}")
    return value


def default_parent_size(size):
    """Parent neighbourhood: about half the size, odd (5x5 -> 3x3, 9x9 -> 5x5), as in [1]_ Fig. 5."""
    return tuple(max(1, (s // 2) | 1) for s in size)


def _is_int(v):
    return isinstance(v, numbers.Integral) and not isinstance(v, bool)


def _is_pair(v):
    return isinstance(v, (tuple, list, np.ndarray)) and len(v) == 2 and all(_is_int(x) for x in v)


def _per_source(value, n, name):
    """Neighbourhood sizes: one setting for every source, or a list with one per source.

    ``None`` or an int is the same for every source. A list (or a tuple whose
    entries are not all integers, or whose length is the number of sources
    other than two) holds one entry per source, each an int or an ``(h, w)``
    pair. A tuple or array of two integers is one ``(h, w)`` rectangle for
    every source, except with exactly two sources, where ``(5, 9)`` could
    also mean 5x5 and 9x9: that raises, naming both spellings.
    """
    if value is None or _is_int(value):
        return [value] * n
    if isinstance(value, str) or not hasattr(value, "__len__"):
        raise TypeError(f"{name} must be an int, an (h, w) pair or a list with one per source, got {value!r}")
    if not isinstance(value, list) and _is_pair(value):
        h, w = (int(v) for v in value)
        if n == 2:
            raise ValueError(
                f"{name}=({h}, {w}) is ambiguous with two sources: pass a list with one entry per source, "
                f"[{h}, {w}] for {h}x{h} and {w}x{w}, or [({h}, {w}), ({h}, {w})] for one {h}x{w} rectangle for both"
            )
        return [(h, w)] * n
    values = list(value)
    if len(values) != n:
        one = "source" if n == 1 else "sources"
        raise ValueError(
            f"{name} holds {len(values)} entries but there {'is' if n == 1 else 'are'} {n} {one}; pass a list "
            f"with one entry per source (an int or an (h, w) pair each, e.g. {[5] * n!r}) or a single int"
        )
    for i, v in enumerate(values):
        if not (v is None or _is_int(v) or _is_pair(v)):
            raise TypeError(f"{name}[{i}] must be an int or an (h, w) pair of ints, got {v!r}")
    return [v if v is None or _is_int(v) else tuple(int(x) for x in v) for v in values]


def _per_source_shape(value, n, name):
    """Neighbourhood footprints: one name for every source, or a list with one per source."""
    values = [value] * n if isinstance(value, str) else value
    if not isinstance(values, (list, tuple)):
        raise TypeError(
            f"{name} must be one of {', '.join(map(repr, SHAPES))} or a list with one per source, got {value!r}"
        )
    values = list(values)
    if len(values) != n:
        raise ValueError(
            f"{name} holds {len(values)} entries but there are {n} sources; pass one shape "
            f"({' or '.join(map(repr, SHAPES))}) per source or a single one"
        )
    per_source = n > 1 and not isinstance(value, str)
    return [check_choice(v, SHAPES, f"{name}[{i}]" if per_source else name) for i, v in enumerate(values)]


def footprint(size, shape):
    """Pixels of an (h, w) neighbourhood box its footprint keeps.

    ``"square"``: the whole box (Wei & Levoy 2000). ``"disc"``: the ellipse
    inscribed in the box, ``(dy / (h/2))^2 + (dx / (w/2))^2 <= 1`` (a disc
    when h == w; 3x3 keeps all 9 pixels, 5x5 drops the 4 corners, 21 left).
    """
    h, w = size
    if shape == "square":
        return np.ones((h, w), bool)
    dy = (np.arange(h) - h // 2) / (h / 2)
    dx = (np.arange(w) - w // 2) / (w / 2)
    return dy[:, None] ** 2 + dx[None, :] ** 2 <= 1.0


def check_levels(levels):
    return check_positive_int(levels, "levels")


def check_fits(image, size, name, size_name):
    h, w = image.shape[:2]
    if size[0] > h or size[1] > w:
        raise ValueError(
            f"{size_name} {size} is larger than {name} ({h}x{w}); pass a smaller {size_name} or a larger {name}"
        )


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

    @property
    def parent_mask(self):
        """Parent-level footprint, or None for the whole box (the fast shared-layer path)."""
        return None if self.shape == "square" else footprint(self.parent_size, self.shape)


def neighborhood_masks(size, shape="square"):
    """Parts of the neighbourhood inside its footprint: the causal rows above (fixed when a
    scanline starts), the causal pixels left of the centre, and the full non-causal one."""
    h, w = size
    foot = footprint(size, shape)
    above = np.zeros((h, w), bool)
    above[: h // 2] = True
    # every footprint keeps the whole centre row, so ``left`` is always the w//2 pixels
    # left of the centre (the scanline engine reads them as one slice of the row)
    left = causal_mask(size) & ~above & foot
    full = foot.copy()
    full[h // 2, w // 2] = False  # eq. 1 keeps p itself out of N_i(p)
    return above & foot, left, full


def _vectors(image, parent, centers, size, parent_size, mask, mode, parent_mask=None):
    """This level's masked neighbourhood joined to the parent's (Wei & Levoy 2000, Sec. 3.2).

    The parent's neighbourhood is the whole box, or the pixels of ``parent_mask``.
    """
    if parent is None:
        return extract(image, centers, size, mode=mode)[:, mask].reshape(len(centers), -1)
    if parent_mask is None:
        return multilevel_vectors(image, parent, centers, size, parent_size, mode=mode, mask=mask)
    centers = np.asarray(centers)
    here = extract(image, centers, size, mode=mode)[:, mask].reshape(len(centers), -1)
    coarse = extract(parent, centers // 2, parent_size, mode=mode)[:, parent_mask].reshape(len(centers), -1)
    return np.concatenate([here, coarse], axis=1)


def candidate_pixels(source, level, levels):
    """Exemplar pixels whose neighbourhoods (and parents') lie inside the exemplar."""
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


def exemplar_vectors(source, level, levels, centers, mask):
    parent = source.pyramid[level + 1] if level + 1 < levels else None
    return _vectors(
        source.pyramid[level], parent, centers, source.size, source.parent_size, mask, "valid", source.parent_mask
    )


def _output_vectors(out, parent, source, mask):
    """Neighbourhood vectors of every output pixel (or voxel) for one source, toroidal.

    For a volume, the neighbourhood of the view along ``axis`` lies in the
    plane perpendicular to it: the slices along ``axis`` are stacked as
    channels so that the 2-D shared layer extracts every plane at once.
    """
    size, psize = source.size, source.parent_size
    if source.axis is None:
        h, w = out.shape[:2]
        centers = np.argwhere(np.ones((h, w), bool))
        return _vectors(out, parent, centers, size, psize, mask, "wrap", source.parent_mask)
    vol = np.moveaxis(out, source.axis, 2)  # (P0, P1, S, C): plane axes first
    p0, p1, s, c = vol.shape
    pvol = None
    if parent is not None:  # parent voxel of (i, j, k) is (i//2, j//2, k//2)
        pvol = np.repeat(np.moveaxis(parent, source.axis, 2), 2, axis=2)[:, :, :s]
    centers = np.argwhere(np.ones((p0, p1), bool))
    n_here = int(mask.sum())
    result = None
    for s0 in range(0, s, _SLICE_CHUNK):
        chunk = slice(s0, min(s, s0 + _SLICE_CHUNK))
        ns = chunk.stop - chunk.start
        img = vol[:, :, chunk].reshape(p0, p1, ns * c)
        pim = None if pvol is None else pvol[:, :, chunk].reshape(pvol.shape[0], pvol.shape[1], ns * c)
        v = _vectors(img, pim, centers, size, psize, mask, "wrap", source.parent_mask)
        parts = [v[:, : n_here * ns * c].reshape(p0 * p1, n_here, ns, c)]
        if pim is not None:
            parts.append(v[:, n_here * ns * c :].reshape(p0 * p1, -1, ns, c))
        # (P0*P1, ns, n, C) -> one row per voxel, vector = [here..., parent...]
        v = np.concatenate([np.swapaxes(q, 1, 2).reshape(p0 * p1, ns, -1) for q in parts], axis=2)
        if result is None:
            result = np.empty((p0, p1, s, v.shape[-1]), dtype=out.dtype)
        result[:, :, chunk] = v.reshape(p0, p1, ns, -1)
    return np.moveaxis(result, 2, source.axis).reshape(-1, result.shape[-1])


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
        pixels = src.pyramid[level].reshape(-1, channels)
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


def check_output_levels(sources, shape, out_pyr, levels):
    """The toroidal output's coarsest level must hold every neighbourhood (this level's and the parent's)."""
    coarse = out_pyr[-1].shape[:-1]
    for src in sources:
        plane = tuple(n for a, n in enumerate(coarse) if a != src.axis) if src.axis is not None else coarse
        need = src.size if levels == 1 else tuple(max(a, b) for a, b in zip(src.size, src.parent_size))
        if plane[0] < need[0] or plane[1] < need[1]:
            raise ValueError(
                f"the output size {tuple(shape)} is only {plane[0]}x{plane[1]} at the coarsest of levels={levels}, "
                f"smaller than the neighborhood {need[0]}x{need[1]} of {src.name}; pass a larger size, "
                f"fewer levels or a smaller neighborhood"
            )


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


def _check_memory(sources, shape, channels, dtype, order):
    """Refuse an output whose arrays cannot fit: its pyramid, and in independent order every pixel's
    neighbourhood vector for every source at once (scanline order holds one row of them)."""
    n = float(math.prod(shape))  # Python ints: numpy's int64 product of a huge size wraps negative
    item = np.dtype(dtype).itemsize
    need = 3 * n * channels * item  # noise, the output pyramid, one pass's new values
    if order != "scanline":
        for src in sources:
            dim = (src.size[0] * src.size[1] + src.parent_size[0] * src.parent_size[1]) * channels
            need += 2 * n * (dim + channels) * item  # the query vectors and a temporary of the search
    check_memory(need, tuple(shape))


def _synthesize(sources, shape, channels, dtype, *, levels, order, method, iterations, passes, rng, progress, desc,
                candidates="all", k=1, tileable=False):
    """Multi-resolution synthesis minimising eq. 1 at every pixel, coarse to fine."""
    _check_memory(sources, shape, channels, dtype, order)
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
        used = search.resolve(method, n, _set_dim(sources[0], channels, levels), profile=profile, queries=n)
    else:
        used = search.resolve(method, max(len(t) for t in tables[0]), None, profile=profile,
                              queries=int(np.prod(out_pyr[0].shape[:-1])))
    info = PixelSynthesisInfo(order=order, method=used, candidates=candidates)
    # Index builds (PCA subsample, k-means) draw from their own streams, so the
    # synthesis stream does not depend on the search backend or on `iterations`.
    run = _Run(levels, order, used, profile, iterations, passes, int(rng.integers(2**62)), candidates, k, tileable)
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
                energy, iters, cells = _coherent_level(lv, run, bar, parent_cells)
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
        above, left, _ = neighborhood_masks(src.size, src.shape)
        fixed = exemplar_vectors(src, lv.level, run.levels, cen, above)
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
            q = _vectors(lv.out, lv.parent, line_centers, src.size, src.parent_size, t.above, "wrap", src.parent_mask)
            if exact:
                t.exact.start(q)
            else:
                t.q = q
        for j in range(start):
            e, n_iter = _solve_wrapped(row, r, j, wraps, active, run.iterations, picked)
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
                e, n_iter = _solve_pixel(row, j, r, active, run.iterations, exact,
                                         None if picked is None else picked[:, r, j])
                energy += e
                steps += n_iter
        for j in range(stop, width):
            e, n_iter = _solve_wrapped(row, r, j, wraps, active, run.iterations, picked)
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
        d = exact.distances(j, row[cols[j]].ravel())  # ||N(p) - N(p_1)||^2 for every candidate p_1
        k = d.argmin()
        row[j] = pixels[k]
        energy += d[k]
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
    other terms left out, ``||v_S - q_S||^2 = ||v_S||^2 - 2 v.q_S +
    ||q_S||^2``: one product with the candidates per pixel, for a few
    percent of the pixels. (This rule is texsynth's; Wei & Levoy's papers
    were not at hand to say how they treat the wrap.) One search per source
    of :func:`mix_textures`; eq. 1 then alternates over these distances as
    over the causal ones (:func:`_solve_wrapped`).
    """

    def __init__(self, lv, run, table):
        src = table.src
        self.lv, self.table, self.src = lv, table, src
        _, _, self.full = neighborhood_masks(src.size, src.shape)
        self.vectors = exemplar_vectors(src, lv.level, run.levels, lv.centers[table.i], self.full)
        self.squares = self.vectors**2
        self.by_pixel = SequentialExact(table.pixels)  # eq. 1's ||p - p_i||^2 term
        self.channels = lv.out.shape[-1]
        self.parent_dims = self.vectors.shape[1] - int(self.full.sum()) * self.channels
        h, w = src.size
        self.offsets = np.mgrid[-(h // 2):h - h // 2, -(w // 2):w - w // 2]  # (2, h, w) window offsets
        # the coarsest level compares its causal window's noise as Wei & Levoy do; finer levels have the parent
        self.always = causal_mask(src.size) & self.full if lv.parent is None else np.zeros_like(self.full)
        self.kept = {}  # window pixels compared -> (selected dimensions, ||v_S||^2 of every candidate)

    def unwrapped(self, r):
        """The columns ``[start, stop)`` of row ``r`` whose causal window does not wrap (none in the first and
        last rows)."""
        (h, w), (height, width) = self.src.size, self.lv.out.shape[:2]
        if r < h // 2 or r + h // 2 >= height:
            return width, width
        return w // 2, width - w // 2

    def distances(self, r, j):
        """``||N(p) - N(p_i)||^2`` over the window pixels synthesised before ``(r, j)``, to every candidate."""
        height, width = self.lv.out.shape[:2]
        rows = (r + self.offsets[0]) % height
        cols = (j + self.offsets[1]) % width
        known = ((rows * width + cols < r * width + j) & self.full) | self.always  # visited before (r, j)
        key = known.tobytes()
        if key not in self.kept:
            sel = np.concatenate([np.repeat(known[self.full], self.channels), np.ones(self.parent_dims, bool)])
            self.kept[key] = (sel, self.squares @ sel)
        sel, norms = self.kept[key]
        src = self.src
        q = _vectors(self.lv.out, self.lv.parent, np.array([[r, j]]), src.size, src.parent_size, self.full, "wrap",
                     src.parent_mask)[0] * sel
        return norms - 2 * (self.vectors @ q) + q @ q

    def nearest_with(self, distances, p):
        """The candidate minimising ``distances + ||p - p_i||^2`` (one term of eq. 1 with ``p`` fixed)."""
        return self.by_pixel.nearest_with(distances, 0, p)


def _unwrapped(wraps, r):
    """The columns ``[start, stop)`` of row ``r`` where no source's causal window wraps."""
    spans = [w.unwrapped(r) for w in wraps]
    start, stop = max(a for a, _ in spans), min(b for _, b in spans)
    return (start, stop) if start < stop else (stop, stop)


def _solve_wrapped(row, r, j, wraps, active, iterations, picked):
    """Pixel ``(r, j)`` where a window wraps: eq. 1 over the synthesised neighbours; returns (E, iterations).

    One source: its nearest candidate (Wei & Levoy 2000). Several: Wei's
    alternation of :func:`_solve_pixel` over the :class:`_WrapSearch`
    distances.
    """
    if len(wraps) > 1:
        return _solve_pixel(row, j, r, active, iterations, True, None if picked is None else picked[:, r, j],
                            wrapped=wraps)
    d = wraps[0].distances(r, j)
    k = int(d.argmin())
    row[j] = wraps[0].table.pixels[k]
    if picked is not None:
        picked[0, r, j] = k
    return max(float(d[k]), 0.0), 1


def _query_one(index, vector):
    idx, d2 = index.query(vector[None], k=1)
    return idx[0, 0], d2[0, 0]


def _solve_pixel(row, j, r, active, iterations, exact, picks=None, wrapped=None):
    """Eq. 1 at one pixel; writes p into ``row[j]`` (and each source's ``p_i`` into ``picks``, if given),
    returns (E, iterations).

    ``wrapped`` (tileable output, a pixel whose window wraps): each source's
    :class:`_WrapSearch`, whose exact distances replace the causal ones.

    With one source of positive weight, eq. 1 is minimised directly (Wei
    2002: choose the p_i of nearest neighbourhood and set p = p_i, which is
    Wei & Levoy 2000). With several, Wei's alternation starts from the
    current value of p (the initial noise, or the previous pass).
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
            k = x.argmin()
            nd = x[k]
        else:
            k, nd = _query_one(t.index, x)
        row[j] = t.pixels[k]
        if picks is not None:
            picks[t.i] = k
        return nd, 1
    n_iter = 0
    # Wei's alternation needs a starting p; start from each source's own
    # direct solution (its p_i of nearest neighbourhood) and keep the end of
    # lowest E. With one source this is Wei & Levoy 2000 exactly.
    best = None
    for start in range(len(terms)):
        t, _, x = terms[start]
        p = t.pixels[x.argmin()] if exact else t.pixels[_query_one(t.index, x)[0]]
        energy, n, ks = np.inf, 0, None
        for _ in range(iterations):
            # fix p, choose each p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2 (one term of eq. 1)
            chosen = []
            for t, _, x in terms:
                if wrapped is not None:
                    k = wrapped[t.i].nearest_with(x, p)
                    chosen.append((k, x[k]))
                elif exact:  # + ||p - p_i||^2 ranked on the pixel part
                    k = t.exact.nearest_with(x, 2, p)
                    chosen.append((k, x[k]))
                else:
                    k, d = _query_one(t.index_p, np.concatenate([x, p]))
                    chosen.append((k, d - ((t.pixels[k] - p) ** 2).sum()))
            # fix {p_i}, p = weighted average (minimises eq. 1 over p)
            p_new, e_new = _average(terms, chosen)
            n += 1
            if not e_new < energy * (1.0 - _STOP_TOLERANCE):  # E stopped falling
                break
            p, energy, ks = p_new, e_new, [k for k, _ in chosen]
        n_iter += n
        if best is None or energy < best[1]:
            best = (p, energy, ks)
    row[j] = best[0]
    if picks is not None:
        for (t, _, _), k in zip(terms, best[2]):
            picks[t.i] = k
    return best[1], n_iter


def _average(terms, chosen):
    """p = sum_i a_i p_i (sum a_i = 1) and the energy of eq. 1 at that p."""
    picks = [t.pixels[k] for (t, _, _), (k, _) in zip(terms, chosen)]
    p = terms[0][1] * picks[0]
    for (_, a, _), q in zip(terms[1:], picks[1:]):
        p = p + a * q
    energy = 0.0
    for (_, a, _), q, (_, nd) in zip(terms, picks, chosen):
        energy += a * (float(((p - q) ** 2).sum()) + float(nd))
    return p, energy


# --------------------------------------------------------------------------- #
# k-coherent candidates (Ashikhmin 2001, Tong et al. 2002)
# --------------------------------------------------------------------------- #
def _set_dim(source, channels, levels):
    """Dimension of the vectors that decide the k-coherence sets: the whole footprint and the parent's."""
    n = int(footprint(source.size, source.shape).sum())
    if levels > 1:
        n += int(footprint(source.parent_size, source.shape).sum())
    return n * channels


def offsets(mask):
    """(row, col) offsets from the centre of the pixels of a neighbourhood mask."""
    h, w = mask.shape
    return np.argwhere(mask) - [h // 2, w // 2]


def wavefronts(height, width, step):
    """Pixels (flat indices) grouped by wavefront ``j + step * i`` of the scanline order, and the groups' bounds.

    With ``step = w // 2 + 1`` every causal neighbour of pixel ``(i, j)`` (rows
    above within ``w // 2`` columns, pixels to its left) lies on an earlier
    wavefront and every other pixel of its ``(h, w)`` box on a later one.
    """
    t = (np.arange(width)[None, :] + step * np.arange(height)[:, None]).ravel()
    order = np.argsort(t, kind="stable")
    return order, np.searchsorted(t[order], np.arange(t.max() + 2))


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
        above, left, full = neighborhood_masks(src.size, src.shape)
        self.causal = above | left
        grid = tuple(int(v) for v in cen[-1] - cen[0] + 1)
        self.vectors = exemplar_vectors(src, lv.level, run.levels, cen, self.causal)
        self.pixels = src.pyramid[lv.level][cen[:, 0], cen[:, 1]]
        similar = full.copy()
        similar[src.size[0] // 2, src.size[1] // 2] = True  # x's own pixel counts in "similar to x"
        self.sets = KCoherence(exemplar_vectors(src, lv.level, run.levels, cen, similar) if run.k > 1 else None,
                               grid, run.k, method=run.method, profile=run.profile,
                               rng=np.random.default_rng([run.seed, lv.level, 3] + ([i] if i else [])))
        self.draw = np.random.default_rng([run.seed, lv.level] + ([i] if i else []))
        if parent_cells is None:  # Ashikhmin: every pixel starts from a random exemplar position
            self.cells = self.draw.integers(0, len(cen), size=(height, width))
            self.offsets = offsets(self.causal)
        else:
            self.cells = _predicted_cells(parent_cells, cen, (height, width))
            self.offsets = np.concatenate([offsets(self.causal), offsets(similar & ~self.causal)])
        self.flat_cells = self.cells.reshape(-1)

    def candidates(self, lv, centers):
        """The pixels' candidates ``(M, K)`` (cells) and their query vectors."""
        cands = self.sets.candidates(neighbor_sources(self.cells, centers, self.offsets), self.offsets, rng=self.draw)
        src = self.src
        q = _vectors(lv.out, lv.parent, centers, src.size, src.parent_size, self.causal, "wrap", src.parent_mask)
        return cands, q


def _coherent_level(lv, run, bar, parent_cells):
    """One level in scanline order with k-coherent candidates; returns (E, steps per pixel, cells per source).

    Each pixel is compared only with the k-coherence sets of the positions
    its neighbours' sources suggest (``s(p + d) - d``): the causal
    neighbours, as synthesised at this level, and, below the coarsest level,
    every other pixel of the neighbourhood and ``p`` itself as the parent
    level predicts them. The distance is Wei & Levoy's: the causal
    neighbourhood at this level joined to the parent's full one. Pixels on
    one wavefront of the scanline order have no causal neighbour in common
    with each other, so they are chosen together. With several sources each
    keeps its own source map, and eq. 1 alternates over each source's
    candidates (:func:`_coherent_mixture`).
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
            p, e, ks, n = _coherent_mixture(a, nds, colours, run.iterations)
            for (cands, _), c, k in zip(found, srcs, ks):
                c.flat_cells[pix] = cands[np.arange(len(pix)), k]
            flat_out[pix] = p
            energy += float(e.sum())
            steps += float(n.sum())
        if t >= width - 1 and (t - width + 1) % step == 0:  # row (t - width + 1) / step is complete
            bar.advance({"level": lv.level, "row": (t - width + 1) // step})
    return energy / (height * width), steps / (height * width), [c.cells for c in srcs]


def _coherent_mixture(a, nds, colours, iterations):
    """Eq. 1 for ``M`` pixels over each source's own candidates: ``(p, E, picks, steps)``.

    ``a`` ``(S, M)`` the weights (sum 1 per pixel), ``nds[i]`` ``(M, K_i)``
    the neighbourhood distances to source ``i``'s candidates (``inf`` for a
    repeat), ``colours[i]`` ``(M, K_i, C)`` their pixels. As in the full
    search (:func:`_solve_pixel`): from each source's direct solution (its
    nearest neighbourhood), fix ``p`` and choose each ``p_i`` minimising
    ``||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2``, set ``p`` to the weighted
    average, until E stops falling or ``iterations`` steps; keep the start of
    lowest E. A source of weight 0 at a pixel keeps its nearest
    neighbourhood (its map continues from there).
    """
    m = a.shape[1]
    direct = [np.argmin(nd, axis=1) for nd in nds]

    def blend(r, ks):
        """p = sum_i a_i p_i at pixels ``r`` with picks ``ks``, and E there."""
        picked = [col[r, k] for col, k in zip(colours, ks)]
        p = sum(a[i, r, None] * c for i, c in enumerate(picked))
        e = sum(a[i, r] * (((p - c) ** 2).sum(axis=1) + nds[i][r, k]) for i, (c, k) in enumerate(zip(picked, ks)))
        return p, e

    best_p = np.zeros((m, colours[0].shape[-1]))  # every pixel has a source of weight > 0: all are set below
    best_e = np.full(m, np.inf)
    best_k = [k.copy() for k in direct]
    steps = np.zeros(m)
    for start in range(len(nds)):
        sel = np.flatnonzero(a[start] > 0)
        p = colours[start][sel, direct[start][sel]]
        e = np.full(len(sel), np.inf)
        ks = [k[sel].copy() for k in direct]
        todo = np.arange(len(sel))
        for _ in range(iterations):
            r = sel[todo]
            new = [np.where(a[i, r] > 0, np.argmin(nd[r] + ((col[r] - p[todo, None]) ** 2).sum(axis=2), axis=1),
                            direct[i][r]) for i, (nd, col) in enumerate(zip(nds, colours))]
            p_new, e_new = blend(r, new)
            steps[r] += 1
            better = e_new < e[todo] * (1.0 - _STOP_TOLERANCE)  # E still falling
            if not better.any():
                break
            todo, p_new, e_new = todo[better], p_new[better], e_new[better]
            p[todo], e[todo] = p_new, e_new
            for i in range(len(ks)):
                ks[i][todo] = new[i][better]
        win = e < best_e[sel]
        best_p[sel[win]], best_e[sel[win]] = p[win], e[win]
        for i in range(len(ks)):
            best_k[i][sel[win]] = ks[i][win]
    return best_p, best_e, best_k, steps


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
                                       threads, chosen)
        flat[:] = p
        if chosen:
            picked.reshape(len(tabs), -1)[:] = chosen
        bar.advance({"level": lv.level, "parent_only": parent_only})
    return energy.mean(), n_iter.mean()


def _level_table(src, cen, level, run, i, *, direct, several, with_parent):
    """Candidate pixels and the indexes over their neighbourhoods at one level, for one source."""
    _, _, full = neighborhood_masks(src.size, src.shape)
    vec = exemplar_vectors(src, level, run.levels, cen, full)
    pixels = np.ascontiguousarray(src.pyramid[level][cen[:, 0], cen[:, 1]])
    t = _PassTable(src, full, pixels)
    if direct:  # N_i(p) alone: Wei & Levoy 2000, a source's direct solution
        t.index = run.index(vec, level, i, 0)
    if several:  # [N_i(p), p]: one term of eq. 1 with p fixed
        t.index_p = run.index(np.concatenate([vec, pixels], axis=1), level, i, 1)
    if with_parent:  # the parent's neighbourhood alone, per row/column parity of the candidate
        coarse = exemplar_vectors(src, level, run.levels, cen, np.zeros(src.size, bool))
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


def _for_each_source(fn, n, threads):
    """``fn(i)`` for every source ``i``, in up to ``threads`` threads.

    The sources' searches are independent; kd-tree queries run mostly in
    scipy's cKDTree, which releases the GIL, so two views search at once on
    two cores (measured 1.3-2x on 32^3 solids; exact search already uses
    every core inside BLAS and gets single-threaded calls).
    """
    if threads < 2 or n < 2:
        for i in range(n):
            fn(i)
        return
    with ThreadPoolExecutor(min(threads, n)) as pool:
        list(pool.map(fn, range(n)))  # list(): re-raise a worker's exception here


def _solve_all(flat, tabs, a_flat, queries, parent_only, iterations, threads=1, chosen=None):
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

    _for_each_source(direct, len(tabs), threads)
    # One source at a pixel: that is the minimum of eq. 1. (The parent-only
    # first pass stops here everywhere: it is only a starting guess.)
    p, energy = _average_sel(tabs, a_flat, ks, nds, everything)
    final = [k.copy() for k in ks]  # the p_i of each pixel's p (the starts below read ks)
    if chosen is not None:
        chosen.extend(final)
    n_iter = np.ones(n)
    multi = np.flatnonzero(n_on > 1)
    if parent_only or multi.size == 0:
        return p, energy, n_iter
    # Several sources: Wei's alternation from each source's direct solution; keep the lowest E.
    energy[multi] = np.inf
    n_iter[multi] = 0
    # A volume (every voxel has all views) starts once, from the previous pass.
    starts = [(None, None, None)] if from_previous else list(zip(tabs, a_flat, ks))
    for start_tab, start_a, start_k in starts:
        sel = multi if start_tab is None else multi[start_a[multi] > 0]
        cur_p = flat[sel].copy() if start_tab is None else start_tab.pixels[start_k[sel]]
        cur_e = np.full(len(sel), np.inf)
        cur_k = [k[sel] for k in ks]
        cur_nd = [nd[sel] for nd in nds]
        todo = np.arange(len(sel))
        for step in range(iterations):
            # fix p, choose each p_i minimising ||p - p_i||^2 + ||N_i(p) - N_i(p_i)||^2
            new_k = [k.copy() for k in cur_k]
            new_nd = [nd.copy() for nd in cur_nd]
            def choose(i):
                t, a, q = tabs[i], a_flat[i], queries[i]
                m = todo[a[sel[todo]] > 0]
                idx, d2 = t.index_p.query(np.concatenate([q[sel[m]], cur_p[m]], axis=1), k=1)
                new_k[i][m] = idx[:, 0]
                new_nd[i][m] = d2[:, 0] - ((t.pixels[idx[:, 0]] - cur_p[m]) ** 2).sum(1)

            _for_each_source(choose, len(tabs), threads)
            # fix {p_i}, p = weighted average
            p_new, e_new = _average_sel(tabs, a_flat, [k[todo] for k in new_k], [d[todo] for d in new_nd], sel[todo])
            n_iter[sel[todo]] += 1
            better = e_new < cur_e[todo] * (1.0 - _STOP_TOLERANCE)  # E still falling
            if not better.any():
                break
            todo = todo[better]
            # where p did not move, the next step would choose the same p_i and
            # find E unchanged (the stop rule): count that step, skip its search
            moved = np.any(p_new[better] != cur_p[todo], axis=1)
            cur_p[todo], cur_e[todo] = p_new[better], e_new[better]
            for i in range(len(tabs)):
                cur_k[i][todo], cur_nd[i][todo] = new_k[i][todo], new_nd[i][todo]
            if step + 1 < iterations:
                n_iter[sel[todo[~moved]]] += 1
            todo = todo[moved]
            if todo.size == 0:
                break
        win = cur_e < energy[sel]
        p[sel[win]], energy[sel[win]] = cur_p[win], cur_e[win]
        for i in range(len(tabs)):
            final[i][sel[win]] = cur_k[i][win]
    return p, energy, n_iter


def _average_sel(tabs, a_flat, ks, nds, sel):
    """At pixels ``sel``: p = sum_i a_i p_i (sum a_i = 1) and eq. 1 at that p."""
    picks = [t.pixels[k] for t, k in zip(tabs, ks)]
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
def _prepare(images, names, sizes, parent_sizes, axes, levels, size_name, work_dtype=None, shapes=None):
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
        psize = default_parent_size(size) if parent_sizes[i] is None else patch_shape(parent_sizes[i], "parent_size")
        check_fits(img, size, name, size_name)
        check_fits(img, psize, name, size_name.replace("neighborhood", "parent") if parent_sizes[i] is not None else size_name)
        if id(images[i]) not in pyramids:
            pyramids[id(images[i])] = [
                np.asarray(level, dtype=work) for level in gaussian_pyramid(img.astype(work, copy=False), levels)
            ]
        shape = "square" if shapes is None else shapes[i]
        sources.append(Source(pyramids[id(images[i])], size, psize, axis, name, shape=shape))
    return sources, channels, dtype, converted[0][1]


def _check_order_method(order, method, passes, max_iterations=1):
    check_choice(order, ORDERS, "order")
    search.check_method(method)
    check_positive_int(passes, "passes", maximum=MAX_ITERATIONS)
    check_positive_int(max_iterations, "max_iterations", maximum=MAX_ITERATIONS)


def synthesize_pixels(
    exemplar,
    size,
    *,
    neighborhood_size=5,
    neighborhood_shape="square",
    parent_size=None,
    levels=3,
    order="scanline",
    candidates="all",
    k=1,
    method="auto",
    passes=2,
    tileable=False,
    rng=None,
    progress=False,
    return_info=False,
):
    """Wei-Levoy multi-resolution pixel synthesis (scanline or order-independent).

    Parameters
    ----------
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    size : int or (int, int)
        Output ``(height, width)``.
    neighborhood_size : int or (int, int)
        Neighbourhood at each level. Default 5 (5x5, of which the causal
        half is used in scanline order): the paper's multi-resolution
        results use 5x5 neighbourhoods over 3 levels [1]_ (Sec. 3.2, 5).
    neighborhood_shape : {"square", "disc"}
        ``"square"``: the whole box, as in [1]_ (default). ``"disc"``: the
        disc (ellipse) inscribed in it, at this level and the parent level;
        isotropic, about pi/4 of the values (see :func:`mix_textures`).
    parent_size : int or (int, int), optional
        Full neighbourhood at the parent (coarser) level. Default about half
        ``neighborhood_size`` rounded to odd (5 -> 3, 9 -> 5).
    levels : int
        Pyramid levels (default 3, as in [1]_). 1 is single-resolution.
    order : {"scanline", "independent"}
        ``"scanline"``: Wei & Levoy 2000, causal neighbourhoods, sequential.
        ``"independent"``: Wei & Levoy 2002 [2]_, non-causal neighbourhoods,
        every pixel of a level updated at once per pass.
    candidates : {"all", "k-coherent"}
        Which exemplar neighbourhoods a pixel is compared with.
        ``"all"`` (default, Wei & Levoy): every one, so the best match is
        global. ``"k-coherent"``: only the *coherent* candidates, Ashikhmin's
        rule [3]_ with Tong et al.'s k-coherence sets [4]_ (see
        :class:`~texsynth.core.search.KCoherence`): for every already
        synthesised neighbour ``p + d`` of ``p``, the exemplar position that
        continues its copy, ``s(p + d) - d``, and that position's ``k - 1``
        most similar ones; below the coarsest level also the positions the
        parent level's copies predict for the neighbourhood's other pixels.
        The distance is the same as with ``"all"``. Copies then run on in
        pieces, which keeps elements (bricks, tiles) in one piece where the
        global best match breaks them up, and costs a few distances per
        pixel instead of one per exemplar position: the choice for
        structured textures and large outputs. Scanline order only; the
        coarsest level starts from random exemplar positions (Ashikhmin),
        and a continued copy that leaves the exemplar restarts at a random
        position (his rule).
    k : int
        ``candidates="k-coherent"`` only: size of the k-coherence sets.
        1 (default) is Ashikhmin's search: the continuations alone. Larger
        ``k`` adds similar positions (Tong et al. use small ``k``; their
        values could not be checked here), so pieces end where they fit
        rather than only where the copy runs out, at about ``k`` times the
        cost.
    method : {"auto", "exact", "kdtree", "tsvq"}
        Nearest-neighbour search backend (:mod:`texsynth.core.search`). With
        ``candidates="k-coherent"`` it finds the k-coherence sets. In
        scanline order ``"auto"`` is exact search done one scanline at a
        time (the fastest here); ``"kdtree"``/``"tsvq"`` query per pixel.
        In independent order ``"auto"`` is exact for small problems and
        ``"kdtree"`` for large ones (profiles ``"scanline"`` and ``"pixels"``).
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
        ``docs/methods/multisource.md``). In independent order every
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
    source, which :func:`mix_textures` reduces to exactly. Candidate
    neighbourhoods lie wholly inside the exemplar; the output is toroidal.
    The output pyramid starts as a Gaussian pyramid of noise drawn from the
    exemplar's pixels (so its histogram matches the exemplar's).

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

    Examples
    --------
    >>> from texsynth.data import load
    >>> ex = load("bread")[:24, :24]
    >>> out = synthesize_pixels(ex, 20, levels=2, rng=0)
    >>> out.shape == (20, 20, 3), out.dtype
    (True, dtype('float64'))
    >>> bool(np.array_equal(out, synthesize_pixels(ex, 20, levels=2, rng=0)))
    True
    """
    size = as_size(size)
    levels = check_levels(levels)
    _check_order_method(order, method, passes)
    tileable = check_bool(tileable, "tileable")
    k = _check_candidates(candidates, k, order, tileable)
    rng = as_rng(rng)
    sources, channels, dtype, grey = _prepare(
        [exemplar], ["exemplar"], [neighborhood_size], [parent_size], [None], levels, "neighborhood_size",
        shapes=[check_choice(neighborhood_shape, SHAPES, "neighborhood_shape")],
    )
    sources[0].weights = 1.0
    out, info = _synthesize(
        sources, size, channels, dtype, levels=levels, order=order, method=method, iterations=1,
        passes=passes, rng=rng, progress=progress, desc="Wei-Levoy", candidates=candidates, k=k,
        tileable=tileable and order == "scanline",
    )
    out = restore_channels(out, grey)
    return (out, info) if return_info else out


def _check_candidates(candidates, k, order, tileable):
    """``k`` checked, and ``candidates`` with the options it works with; a ValueError naming the fix."""
    check_candidates(candidates)
    k = check_positive_int(k, "k")
    if candidates == "k-coherent" and order != "scanline":
        raise ValueError("candidates='k-coherent' is implemented in order='scanline' only; pass order='scanline' "
                         "or candidates='all'")
    if tileable and candidates == "k-coherent":
        raise ValueError("tileable=True is not implemented with candidates='k-coherent'; pass candidates='all' "
                         "(or order='independent', which tiles)")
    return k


def _check_weights(weights, n, size):
    """Weight images of the output size (a scalar means constant), non-negative, never all zero."""
    if weights is None:
        return [1.0] * n
    if isinstance(weights, np.ndarray) and weights.ndim == 3 and weights.shape[0] == n:
        weights = list(weights)
    if isinstance(weights, numbers.Real) or (isinstance(weights, np.ndarray) and weights.ndim < 3 and n > 1 and weights.ndim != 1):
        raise ValueError(
            f"weights must hold one weight (a number or a {size[0]}x{size[1]} image) per source, "
            f"i.e. a list of {n}, got {np.asarray(weights).shape if hasattr(weights, 'shape') else weights!r}"
        )
    weights = list(weights)
    if len(weights) != n:
        raise ValueError(f"weights holds {len(weights)} entries but there are {n} sources; pass one weight per source")
    result = []
    for i, w in enumerate(weights):
        arr = np.asarray(w)
        if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
            raise TypeError(f"weights[{i}] must be a real number or array, got dtype {arr.dtype}")
        arr = arr.astype(np.float64)
        if arr.ndim != 0 and arr.shape != tuple(size):
            raise ValueError(
                f"weights[{i}] has shape {arr.shape} but the output size is {tuple(size)}; "
                f"pass a number or a weight image of shape {tuple(size)}"
            )
        if not np.all(np.isfinite(arr)):
            raise ValueError(f"weights[{i}] contains NaN or infinite values")
        if arr.size and arr.min() < 0:
            raise ValueError(f"weights[{i}] has negative values (min {arr.min():.4g}); weights must be >= 0")
        result.append(arr)
    total = sum(np.broadcast_to(w, size) for w in result)
    if np.any(total <= 0):
        bad = tuple(int(v) for v in np.argwhere(total <= 0)[0])
        raise ValueError(
            f"weights are all zero at pixel {bad} (and {int(np.sum(total <= 0)) - 1} others); "
            "every output pixel needs a positive weight for at least one source"
        )
    return result


def mix_textures(
    sources,
    size,
    *,
    weights=None,
    neighborhood_sizes=5,
    neighborhood_shapes="square",
    parent_sizes=None,
    levels=3,
    max_iterations=4,
    order="scanline",
    method="auto",
    passes=2,
    candidates="all",
    k=1,
    tileable=False,
    rng=None,
    progress=False,
    return_info=False,
):
    """Texture mixture from several sources (Wei 2002, eq. 1).

    Parameters
    ----------
    sources : sequence of array_like
        Exemplars ``(h_i, w_i[, C])``, all with the same channels (sizes may
        differ).
    size : int or (int, int)
        Output ``(height, width)``.
    weights : sequence, optional
        One weight per source: a number (constant) or a weight image of the
        output size; non-negative, with a positive sum at every pixel.
        Default: equal weighting (a uniform mixture). A ramp
        ``np.linspace(0, 1, width)`` for one source and its complement for
        the other turns one texture into the other from left to right.
    neighborhood_sizes : int or list
        The size of ``N_i``, per source, because sources differ in texon
        size (Wei 2002, Sec. 2). An int ``k`` is a ``k x k`` neighbourhood
        for every source (default 5, as :func:`synthesize_pixels`). A list
        holds one entry per source, each an int or an ``(h, w)`` pair:
        ``[5, 9]`` is 5x5 for ``sources[0]`` and 9x9 for ``sources[1]``,
        ``[(5, 9), 7]`` a 5-row by 9-column box and 7x7. A bare tuple
        ``(h, w)`` is one box for every source; with exactly two sources it
        is ambiguous and raises ``ValueError`` (write ``[5, 9]`` or
        ``[(5, 9), (5, 9)]``).
    neighborhood_shapes : {"square", "disc"} or list of them
        The shape of ``N_i``, one for every source or a list with one per
        source: ``"square"`` is the whole ``(h, w)`` box (Wei & Levoy 2000;
        default), ``"disc"`` the disc (ellipse, for ``h != w``) inscribed in
        it, at this level and at the parent level. In scanline order the
        causal (L-shaped) half of the shape is used. See Notes.
    parent_sizes : None, int or list
        Parent-level neighbourhood, same forms as ``neighborhood_sizes``;
        default about half of each source's size, odd (5 -> 3, 9 -> 5).
    levels : int
        Pyramid levels (default 3).
    max_iterations : int
        Most alternation steps of eq. 1 per pixel (default 4: the paper found
        1 to 4 enough). Stops earlier when E stops falling.
    tileable : bool
        Make the output tile seamlessly, as :func:`synthesize_pixels` does:
        in scanline order a pixel where some source's causal window wraps
        compares, for every source, the wrapped pixels synthesised before it
        (exact search), and eq. 1 alternates over those distances. In
        independent order the output tiles either way; True changes nothing
        there. Weight images should then wrap too (a left-to-right ramp
        meets its other end at the seam).
    candidates : {"all", "k-coherent"}
        ``"all"`` (default, the paper's): each ``p_i`` among all of source
        ``i``'s neighbourhoods. ``"k-coherent"``: among the k-coherent
        candidates of its own source map only, as :func:`synthesize_pixels`
        chooses them (Ashikhmin 2001; Tong et al. 2002): each source keeps
        the map of where its ``p_i`` came from, and eq. 1 alternates over
        the candidates that map's neighbours suggest (their neighbourhood
        distances computed once per pixel). Scanline order only; not with
        ``tileable=True``.
    k : int
        ``candidates="k-coherent"`` only: size of the k-coherence sets, as
        in :func:`synthesize_pixels` (default 1).
    order, method, passes, rng, progress, return_info
        As in :func:`synthesize_pixels`.

    Returns
    -------
    image : numpy.ndarray
        The mixture, ``size`` with the sources' channel layout; toroidal
        (seamless when tiled with ``tileable=True`` or in independent
        order).
    info : PixelSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For weights of the wrong shape, negative weights, all weights zero at
        a pixel, sources with different channel counts, a neighbourhood
        larger than its source, ``neighborhood_sizes`` or
        ``neighborhood_shapes`` of the wrong length or ambiguous (a tuple of
        two ints with two sources), or an invalid option.

    Notes
    -----
    For each output pixel ``p`` the algorithm minimises (Wei 2002, eq. 1)

    .. math:: E(p, \\{p_i\\}) = \\sum_i w_i \\left(\\|p - p_i\\|^2
              + \\|N_i(p) - N_i(p_i)\\|^2\\right)

    First each ``p_i`` minimises its neighbourhood term (``p`` is not known
    yet); then ``p`` is set to the weighted average of the ``p_i``; then,
    with ``p`` fixed, each ``p_i`` minimises its whole term, and so on. Both
    steps never raise E; the loop stops when E stops falling or after
    ``max_iterations`` steps. The weights are normalised to sum 1 at each pixel,
    which does not move the minimum. With one source the first step is
    Wei & Levoy 2000 and later steps keep it, so the result equals
    :func:`synthesize_pixels` bit for bit.

    Neighbourhood shape: Wei gives each source "a neighborhood parameter,
    defining the size and shape of the neighborhood" [1]_ without listing
    shapes; Wei & Levoy 2000 use square boxes (the causal L-shaped half in
    scanline order) [2]_. A box reaches sqrt(2) times farther along its
    diagonals than along its axes, so for isotropic (stochastic) textures
    ``"disc"`` compares the same distance in every direction, with about
    pi/4 of the values (5x5: 21 of 25, 9x9: 69 of 81). A rectangular
    ``(h, w)`` box suits elongated texons (bricks). 3x3 discs keep all 9
    pixels, so they equal 3x3 squares. The shape is this library's option,
    not a setting the paper reports. The neighbourhood term of eq. 1 sums
    over the pixels of ``N_i``, so at equal weights a source with a larger
    neighbourhood counts more (a ramp turns later); divide ``w_i`` by the
    pixel count of ``N_i`` to balance them.

    References
    ----------
    .. [1] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
       Sketches & Applications. :doi:`10.1145/965400.965507`
    .. [2] L.-Y. Wei and M. Levoy, "Fast texture synthesis using
       tree-structured vector quantization", SIGGRAPH 2000.
       :doi:`10.1145/344779.345009`

    Examples
    --------
    >>> from texsynth.data import load
    >>> a, b = load("bread")[:24, :24], load("wood")[:24, :24]
    >>> ramp = np.tile(np.linspace(0, 1, 20), (20, 1))
    >>> out = mix_textures([a, b], 20, weights=[1 - ramp, ramp], levels=2, rng=0)
    >>> out.shape
    (20, 20, 3)
    >>> out = mix_textures([a, b], 20, neighborhood_sizes=[3, (5, 7)], neighborhood_shapes=["square", "disc"],
    ...                    levels=2, rng=0)
    >>> mix_textures([a, b], 20, neighborhood_sizes=(3, 5))  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    ValueError: neighborhood_sizes=(3, 5) is ambiguous with two sources: ... [3, 5] ... or [(3, 5), (3, 5)] ...
    """
    if isinstance(sources, np.ndarray) or not hasattr(sources, "__len__") or len(sources) == 0:
        raise ValueError("sources must be a non-empty list of exemplar images, e.g. [a, b]")
    n = len(sources)
    size = as_size(size)
    levels = check_levels(levels)
    _check_order_method(order, method, passes, max_iterations)
    tileable = check_bool(tileable, "tileable")
    k = _check_candidates(candidates, k, order, tileable)
    rng = as_rng(rng)
    sizes = _per_source(neighborhood_sizes, n, "neighborhood_sizes")
    psizes = _per_source(parent_sizes, n, "parent_sizes")
    shapes = _per_source_shape(neighborhood_shapes, n, "neighborhood_shapes")
    names = [f"sources[{i}]" for i in range(n)]
    srcs, channels, dtype, grey = _prepare(
        sources, names, sizes, psizes, [None] * n, levels, "neighborhood_sizes", shapes=shapes
    )
    _check_memory(srcs, size, channels, dtype, order)  # before the weight images are summed at the output size
    for src, w in zip(srcs, _check_weights(weights, n, size)):
        src.weights = w
    out, info = _synthesize(
        srcs, size, channels, dtype, levels=levels, order=order, method=method, iterations=max_iterations,
        passes=passes, rng=rng, progress=progress, desc="Wei mixture", candidates=candidates, k=k,
        tileable=tileable and order == "scanline",
    )
    out = restore_channels(out, grey)
    return (out, info) if return_info else out


def synthesize_solid(
    views,
    size,
    *,
    axes=None,
    neighborhood_size=5,
    neighborhood_shape="square",
    parent_size=None,
    levels=3,
    max_iterations=2,
    passes=2,
    method="auto",
    rng=None,
    progress=False,
    return_info=False,
):
    """Solid texture from 2-D views along the volume axes (Wei 2002).

    Parameters
    ----------
    views : array_like or sequence of array_like
        One image (used as the view along all three axes) or a list of 1 to 3
        images with the same channels. ``views[k]`` is what the solid looks
        like when cut perpendicular to ``axes[k]``.
    size : int or (int, int, int)
        Output ``(depth, height, width)``.
    axes : sequence of int, optional
        Volume axis of each view: 0 (z: the slice ``volume[d]`` has rows H,
        columns W), 1 (y: ``volume[:, h]`` has rows D, columns W) or 2 (x:
        ``volume[:, :, w]`` has rows D, columns H). Default: ``(0, 1, 2)``
        for one view (repeated) or three views, ``(0, 1)`` for two.
    neighborhood_size, neighborhood_shape, parent_size, levels
        As in :func:`synthesize_pixels` (one setting for every view; each
        view's neighbourhood lies in the plane perpendicular to its axis).
    max_iterations : int
        Most alternation steps of eq. 1 per voxel and pass (default 2).
    passes : int
        Passes per level of the order-independent update (default 2).
    method : {"auto", "exact", "kdtree", "tsvq"}
        Search backend; ``"auto"``: exact for small volumes, kd-tree (4
        re-ranked candidates, profile ``"solid"``) for large ones.
        ``"tsvq"`` is Wei & Levoy's tree-structured vector quantization
        (faster, less exact; see Notes).
    rng, progress, return_info
        As in :func:`synthesize_pixels`.

    Returns
    -------
    volume : numpy.ndarray
        ``(D, H, W)`` or ``(D, H, W, C)`` following the views' layout;
        toroidal along every axis.
    info : PixelSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For views with mismatched channels, more than 3 views, repeated or
        invalid axes, a neighbourhood larger than a view, bad options.

    Notes
    -----
    Every view is one source of eq. 1 (equal weights); the neighbourhood
    ``N_a`` of a voxel for the view along axis ``a`` is the square in the
    plane perpendicular to ``a`` (and its parent one level coarser, in the
    same plane), so each view constrains what the slices across its axis
    look like. Wei synthesised the volume in scanline order; here voxels
    are updated in the order-independent way (Wei & Levoy 2002: non-causal
    neighbourhoods, all voxels per pass), which vectorizes over the volume.
    The output pyramid is a 3-D Gaussian pyramid of noise.

    No source-coordinate map (``info.coordinates`` is None): each voxel is
    the average of one pixel of every view (eq. 1), so a map would be
    ``(D, H, W, 3, 2)`` plus the view of each slot, 48 bytes a voxel (800
    MB for 256^3), and it would render only channels that mean the same in
    every view. A tangent-space normal map is expressed in its view's own
    plane, and the three views' planes differ, so averaging their normals
    gives no normal of the solid; a height map is a height above one
    view's plane, not a property of a voxel. Colour and roughness alone
    would survive, and for them one can synthesise a solid of those
    channels stacked with the colour (``views`` with more channels).

    Speed: a view given once for several axes builds each search index once;
    the alternation of eq. 1 starts from the previous pass's voxel (the
    direct per-view search is skipped); volumes and their neighbourhood
    vectors are float32 inside (the output keeps the views' dtype); kd-tree
    search re-ranks 4 candidates, the views' searches run in threads
    (``docs/methods/multisource.md`` has the times and the quality of each
    backend).

    References
    ----------
    .. [1] L.-Y. Wei, "Texture synthesis from multiple sources", SIGGRAPH 2003
       Sketches & Applications. :doi:`10.1145/965400.965507`
    .. [2] L.-Y. Wei and M. Levoy, "Order-independent texture synthesis",
       Stanford University Technical Report TR-2002-01, 2002.

    Examples
    --------
    >>> from texsynth.data import load
    >>> vol = synthesize_solid(load("bread")[:24, :24], 8, levels=1, passes=1, rng=0)
    >>> vol.shape
    (8, 8, 8, 3)
    """
    size = as_size(size, "size", ndim=3)
    levels = check_levels(levels)
    _check_order_method("independent", method, passes, max_iterations)
    rng = as_rng(rng)
    if isinstance(views, np.ndarray) or not isinstance(views, (list, tuple)):
        views = [views]
    views = list(views)
    if not 1 <= len(views) <= 3:
        raise ValueError(f"views must hold 1 to 3 images (one per axis), got {len(views)}")
    if axes is None:
        axes = (0, 1, 2) if len(views) in (1, 3) else (0, 1)
    if isinstance(axes, (str, bytes)) or not hasattr(axes, "__len__"):
        raise TypeError(f"axes must be a sequence of volume axes (0, 1 or 2), one per view, got {axes!r}")
    axes = tuple(axes)
    if len(views) == 1 and len(axes) > 1:
        views = views * len(axes)
    if len(axes) != len(views) or not all(isinstance(a, numbers.Integral) and 0 <= a <= 2 for a in axes) or len(
        set(axes)
    ) != len(axes):
        raise ValueError(f"axes must name a distinct volume axis (0, 1 or 2) for each of the {len(views)} views, got {axes!r}")
    n = len(views)
    names = [f"views[{i}]" for i in range(n)]
    # float32 work: the volume's neighbourhood vectors are the bulk of the
    # memory traffic (64^3 voxels x 3 views x ~100 values); voxels are averages
    # of exemplar pixels, so 1e-7 rounding is far below any visible change.
    srcs, channels, dtype, grey = _prepare(
        views, names, [neighborhood_size] * n, [parent_size] * n, list(axes), levels, "neighborhood_size",
        work_dtype=_SOLID_DTYPE, shapes=[check_choice(neighborhood_shape, SHAPES, "neighborhood_shape")] * n,
    )
    for src in srcs:
        src.weights = 1.0
    out, info = _synthesize(
        srcs, size, channels, _SOLID_DTYPE, levels=levels, order="independent", method=method,
        iterations=max_iterations, passes=passes, rng=rng, progress=progress, desc="Wei solid",
    )
    out = restore_channels(out.astype(dtype, copy=False), grey)
    return (out, info) if return_info else out
