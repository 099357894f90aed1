"""Geometric texture synthesis by example: image analogies for volumes (Bhat, Ingram & Turk 2004).

Given a training pair of volumes, ``a`` (a plain model) and ``a_prime`` (the
same model carrying a geometric texture: grooves, pits, spikes, a dilation),
and a new plain model ``b``, Bhat et al. synthesise ``b_prime`` so that
``a : a_prime :: b : b_prime`` (Hertzmann et al.'s image analogies carried to
voxel grids). User vector fields on ``a`` and ``b`` give the direction of the
texture's anisotropy. This module reads in the paper's order:

- the models as regularly sampled distance volumes (``as_distance_field``:
  occupancy becomes a signed distance), compared clipped to ``+-band``
  voxels (the paper samples voxel densities; a clipped distance is a density
  that saturates away from the surface), the plain models ``a`` and ``b``
  after a Gaussian filter of one voxel;
- only a narrow band around ``b``'s surface is synthesised (``|b| < band``);
  elsewhere ``b_prime`` is ``b``;
- the local frame of a voxel: the field ``t`` made tangent to the surface
  (its part orthogonal to the normal, the normalised gradient of the distance),
  the normal ``n`` and ``n x t``; a neighbourhood is the volume sampled
  (trilinearly) on a ``neighborhood_size^3`` grid of unit spacing in that
  frame, so the texture turns with the field;
- the feature vector of a voxel of ``b`` joins ``b``'s neighbourhood (all of
  it, unfiltered) and ``b_prime``'s (only its already synthesised voxels),
  plus, below the coarsest level, ``b_prime``'s coarser result around it
  (3^3 samples, all known) as image analogies' multi-resolution
  neighbourhood; the matching voxels of the pair give the same vectors from
  ``a`` and ``a_prime`` in ``a``'s frames, and the nearest one (masked
  distances through :class:`texsynth.core.search.MaskedIndex`, the plain
  part weighted 0.1 against 1 for the textured part) gives ``b_prime``'s
  value: ``a_prime`` at the match; optionally (``coherence``) image
  analogies' coherence rule;
- the visiting order along the field: the band's voxels are ordered by a
  sweep coordinate, the shortest-path distance from an upstream seed over the
  band's 26-neighbour graph in which a step along the field costs its length,
  a step against it four times that and a step across it half its length
  (:func:`scipy.sparse.csgraph.dijkstra`);
- coarse to fine (``levels``), the volumes subsampled by 2 per level;
- the result is a distance volume, whose surface :func:`sdf_to_mesh` extracts
  by marching cubes.

Deviation (stated): the paper visits the voxels one by one. Here the voxels
whose sweep coordinates fall in one step of half a voxel (a *wavefront*) are
matched together, each seeing the voxels of earlier wavefronts as synthesised
(a voxel's own wavefront is not yet known to it). Since a step along the field
costs 1 and a step across 0.5, the voxels behind a voxel along the field, and
those beside it towards the seed, lie on earlier wavefronts, as the scanline
order's wavefronts in 2-D. Samples that fall on voxels not yet synthesised are
left out of the distance (masked), as the paper compares only the synthesised
part of ``b_prime``'s neighbourhood.

What could not be checked: the paper's text was not at hand; this follows its
published description (the abstract and summaries). Its neighbourhood sizes,
band width, weights of the unfiltered and filtered parts, how the order is
computed from the field, whether it uses a coherence search (image analogies'
kappa: available here, off by default) and its resolutions and timings are this module's
choices, measured where the docs page says so; no equation numbers are quoted.

References
----------
.. [1] P. Bhat, S. Ingram and G. Turk, "Geometric texture synthesis by
   example", Eurographics Symposium on Geometry Processing 2004, pp. 41-44,
   doi:10.2312/SGP/SGP04/041-044.
.. [2] A. Hertzmann, C. E. Jacobs, N. Oliver, B. Curless and D. H. Salesin,
   "Image analogies", SIGGRAPH 2001, doi:10.1145/383259.383295.
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from scipy import ndimage, sparse
from scipy.sparse import csgraph

from ..core._progress import Progress
from ..core._validate import (as_rng, check_bool, check_choice, check_memory, check_positive_float,
                              check_positive_int)
from ..core.search import MaskedIndex, nearest_candidates
from ._lagae import as_distance_field

__all__ = ["AnalogiesInfo", "geometry_analogies"]

ALIGNMENTS = ("field", "axes")
#: Sweep costs per voxel of step: along the field, against it, across it.
ALONG_COST, AGAINST_COST, ACROSS_COST = 1.0, 4.0, 0.5
#: Sweep coordinates in one wavefront: voxels within this much are matched together.
WAVEFRONT_STEP = 0.5
#: The coarser level's neighbourhood: 3^3 samples.
PARENT_SIZE = 3
#: The unfiltered volumes (a, b) are compared as densities: their clipped distances after a Gaussian filter of
#: this many voxels (hides the voxel facets of an occupancy's distances).
DENSITY_SIGMA = 1.0
#: Weight of the unfiltered part of a neighbourhood against 1 for the filtered part (a_prime, b_prime). Measured
#: on a 32^3 cylinder pair and a 32^3 cylinder with the field around it (grooves must become rings): weight 1
#: gave grooves 85-90 degrees from the field (following the example's curvature instead), 0.3 gave 77, 0.2 and
#: 0.05 gave 4.6 and 3.5 degrees. Lower weights anchor the depth less (see the docs page).
UNFILTERED_WEIGHT = 0.1


@dataclasses.dataclass(frozen=True)
class AnalogiesInfo:
    """What :func:`geometry_analogies` chose (at the finest level).

    Attributes
    ----------
    voxels : numpy.ndarray
        ``(n, 3)`` int, the band's voxels ``(z, y, x)`` of ``b``, in visiting order.
    sources : numpy.ndarray
        ``(n, 3)`` int, the voxel of ``a_prime`` each one copied.
    sweep : numpy.ndarray
        ``(n,)`` float, each voxel's sweep coordinate (non-decreasing).
    wavefronts : tuple of int
        Wavefronts per level, coarsest first.
    n_candidates : tuple of int
        Voxels of ``a``'s band searched per level, coarsest first.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Seconds per stage (``"distance fields"``, then ``"level L"``, coarsest first).
    """

    voxels: np.ndarray
    sources: np.ndarray
    sweep: np.ndarray
    wavefronts: tuple
    n_candidates: tuple
    seconds: float
    stage_seconds: dict


# --------------------------------------------------------------------------
# Vector fields and local frames


def _as_field(field, shape, name):
    """A function of voxel positions ``(P, 3)`` (input voxels, ``(z, y, x)``) giving the field there."""
    if callable(field):
        def at(positions):
            v = np.asarray(field(positions), dtype=np.float64)
            if v.shape != positions.shape or not np.all(np.isfinite(v)):
                raise ValueError(f"{name} must return finite (P, 3) vectors for (P, 3) positions, got shape "
                                 f"{v.shape}")
            return v
        return at
    if isinstance(field, str) or field is None:
        raise TypeError(f"{name} must be a vector (dz, dy, dx), an array of shape {(*shape, 3)} or a callable of "
                        f"positions, got {field!r}")
    v = np.asarray(field, dtype=np.float64)
    if not np.all(np.isfinite(v)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if v.shape == (3,):
        if not np.any(v):
            raise ValueError(f"{name} is the zero vector; pass a direction (dz, dy, dx) such as (1, 0, 0)")
        return lambda positions: np.broadcast_to(v, positions.shape)
    if v.shape == (*shape, 3):
        def at(positions):
            idx = np.clip(np.rint(positions).astype(np.int64), 0, np.array(shape) - 1)
            return v[idx[:, 0], idx[:, 1], idx[:, 2]]
        return at
    raise ValueError(f"{name} must be a vector (dz, dy, dx), an array of shape {(*shape, 3)} (one vector per "
                     f"voxel) or a callable of positions, got shape {v.shape}")


def _normals(sdf, voxels):
    """Unit gradients of a distance volume at voxels (central differences, one-sided at the border)."""
    g = np.empty((len(voxels), 3))
    hi = np.array(sdf.shape) - 1
    for axis in range(3):
        up, down = voxels.copy(), voxels.copy()
        up[:, axis] = np.minimum(up[:, axis] + 1, hi[axis])
        down[:, axis] = np.maximum(down[:, axis] - 1, 0)
        g[:, axis] = (sdf[tuple(up.T)] - sdf[tuple(down.T)]) / np.maximum(up[:, axis] - down[:, axis], 1)
    norm = np.linalg.norm(g, axis=1, keepdims=True)
    return np.where(norm > 1e-9, g / np.maximum(norm, 1e-9), [1.0, 0.0, 0.0])


def _frames(sdf, voxels, field, scale, kind):
    """``(n, 3, 3)`` rows ``t, n x t, n`` per voxel: the field made tangent, the bitangent and the normal."""
    if kind == "axes":  # the reference: the grid's own axes (no frame), as image analogies on a grid
        return np.broadcast_to(np.eye(3), (len(voxels), 3, 3)), np.broadcast_to(np.eye(3)[0], (len(voxels), 3))
    n = _normals(sdf, voxels)
    f = field(voxels * float(scale))
    t = f - np.sum(f * n, axis=1, keepdims=True) * n
    norm = np.linalg.norm(t, axis=1, keepdims=True)
    # where the field is normal to the surface, any tangent: the axis least aligned with the normal
    fallback = np.eye(3)[np.argmin(np.abs(n), axis=1)]
    fallback -= np.sum(fallback * n, axis=1, keepdims=True) * n
    t = np.where(norm > 1e-6, t / np.maximum(norm, 1e-12), fallback / np.linalg.norm(fallback, axis=1, keepdims=True))
    return np.stack([t, np.cross(n, t), n], axis=1), t


def _grid(size):
    h = size // 2
    return np.stack(np.meshgrid(*[np.arange(-h, h + 1.0)] * 3, indexing="ij"), -1).reshape(-1, 3)


def _sample(volumes, centres, frames, offsets):
    """Trilinear samples of each volume at ``centres + offsets @ frames`` (``(n, len(offsets))`` each); the points."""
    points = centres[:, None, :] + np.einsum("jk,nkd->njd", offsets, frames)
    coords = points.reshape(-1, 3).T
    return [ndimage.map_coordinates(v, coords, order=1, mode="nearest").reshape(points.shape[:2]) for v in volumes], \
        points


# --------------------------------------------------------------------------
# The visiting order along the field


_STEPS = np.array([d for d in np.ndindex(3, 3, 3) if d != (1, 1, 1)]) - 1


def _sweep(voxels, tangents, shape):
    """Each band voxel's sweep coordinate: shortest paths from an upstream seed per connected part of the band."""
    n = len(voxels)
    lookup = np.full(shape, -1, np.int64)
    lookup[tuple(voxels.T)] = np.arange(n)
    rows, cols, costs = [], [], []
    for d in _STEPS:
        nb = voxels + d
        ok = np.all((nb >= 0) & (nb < shape), axis=1)
        j = np.full(n, -1)
        j[ok] = lookup[tuple(nb[ok].T)]
        i = np.flatnonzero(j >= 0)
        j = j[i]
        along = ((tangents[i] + tangents[j]) / 2) @ d
        across = np.sqrt(np.maximum(d @ d - along ** 2, 0.0))
        cost = np.where(along > 0, ALONG_COST * along, -AGAINST_COST * along) + ACROSS_COST * across
        rows.append(i)
        cols.append(j)
        costs.append(np.maximum(cost, 1e-6))
    graph = sparse.csr_matrix((np.concatenate(costs), (np.concatenate(rows), np.concatenate(cols))), shape=(n, n))
    n_parts, part = csgraph.connected_components(graph, directed=False)
    upstream = np.sum(voxels * tangents, axis=1)  # the seed: the voxel furthest back along its own field
    seeds = [int(np.flatnonzero(part == k)[np.argmin(upstream[part == k])]) for k in range(n_parts)]
    return csgraph.dijkstra(graph, directed=True, indices=seeds, min_only=True)


# --------------------------------------------------------------------------
# Image analogies' coherence: continue a neighbour's copy


def _coherent(idx, d2, kappa, queries, masks, voxels, frames_b, source_at, cand, frames_a, cand_at, vectors,
               weights):
    """Replace each nearest match by the best continuation of a synthesised neighbour's source where it is close.

    For a synthesised neighbour ``q = p + d`` that copied candidate ``s``, the continuation is the voxel
    ``s - F_a(s)^T F_b(p) d`` of ``a`` (the step back from ``q`` to ``p`` carried from ``b``'s frame at ``p``
    into ``a``'s frame at ``s``), rounded."""
    hi_b, hi_a = np.array(source_at.shape) - 1, np.array(cand_at.shape) - 1
    pool = np.full((len(voxels), len(_STEPS)), -1, np.int64)
    for j, d in enumerate(_STEPS):
        q = np.clip(voxels + d, 0, hi_b)
        s = source_at[q[:, 0], q[:, 1], q[:, 2]]
        ok = s >= 0
        if not ok.any():
            continue
        local = frames_b[ok] @ d  # the step (u, v, w) in b's frame
        back = cand[s[ok]] - np.einsum("nkd,nk->nd", frames_a[s[ok]], local)
        c = np.clip(np.rint(back).astype(np.int64), 0, hi_a)
        pool[ok, j] = cand_at[c[:, 0], c[:, 1], c[:, 2]]
    has = (pool >= 0).any(axis=1)
    if not has.any():
        return idx
    rows = np.flatnonzero(has)
    sub = pool[rows]
    first = sub[np.arange(len(rows)), np.argmax(sub >= 0, axis=1)]
    sub = np.where(sub >= 0, sub, first[:, None])  # repeats score inf: invalid slots never win
    choice, d_coh = nearest_candidates(queries[rows], sub, vectors=vectors, weights=masks[rows] * weights)
    better = d_coh <= d2[rows] * (1.0 + kappa)
    out = idx.copy()
    out[rows[better]] = sub[better, choice[better]]
    return out


# --------------------------------------------------------------------------
# Synthesis


def geometry_analogies(a, a_prime, b, *, field_a, field_b, neighborhood_size=5, levels=2, band=4.0,
                       error_tolerance=0.0, coherence=0.0, alignment="field", rng=None, return_info=False,
                       progress=False):
    """Give a new shape the geometric texture that ``a_prime`` adds to ``a`` (Bhat, Ingram & Turk 2004).

    Examples
    --------
    >>> from texsynth import data
    >>> from texsynth.geometry import geometry_analogies
    >>> a, a_prime = data.volume("cylinder", 20), data.volume("grooved_cylinder", 20)
    >>> b = data.volume("cylinder", 16)
    >>> b_prime = geometry_analogies(a, a_prime, b, field_a=(1, 0, 0), field_b=(1, 0, 0), levels=1, rng=0)
    >>> b_prime.shape, bool((b_prime < 0).sum() < b.sum())  # grooves remove material
    ((16, 16, 16), True)

    Parameters
    ----------
    a, a_prime : array_like, shape (D, H, W)
        The training pair: the plain model and the same model with the
        texture, signed distance fields (negative inside, in voxels) or
        occupancy volumes (bool, True inside), of one shape.
    b : array_like, shape (D, H, W)
        The new plain model (any shape of volume).
    field_a, field_b : array_like or callable
        The texture's direction on ``a`` and on ``b``, in voxel axes
        ``(dz, dy, dx)``: one vector for the whole volume, an array
        ``(D, H, W, 3)`` of one vector per voxel, or a callable taking
        voxel positions ``(P, 3)`` ``(z, y, x)`` and returning ``(P, 3)``
        vectors. Only its part tangent to the surface is used.
    neighborhood_size : int
        Odd side of the neighbourhood sampled in a voxel's frame, in voxels
        (default 5: 125 samples of each volume).
    levels : int
        Coarse-to-fine levels, the volumes subsampled by 2 per level
        (default 2); the coarsest must keep ``b``'s surface.
    band : float
        Half-width in voxels of the shell around ``b``'s surface that is
        synthesised, and the distance at which the volumes are clipped for
        comparison (default 4: deeper than the texture's relief and the
        neighbourhood's half-width). Halved per coarser level (at least 1.5).
    error_tolerance : float
        Each voxel copies one of the matches within ``(1 + error_tolerance)``
        of the nearest, drawn at random (0: the nearest and its exact ties).
    coherence : float
        Image analogies' coherence parameter kappa: a voxel copies the
        continuation of a synthesised neighbour's source (its source moved by
        the neighbour's offset, carried from ``b``'s frame into ``a``'s)
        when that match's distance is within ``1 + coherence * 2^-level`` of
        the nearest match's (level 0 the finest), so copies stay whole.
        Default 0: only the nearest match (the paper's description names no
        coherence search; on the docs' torus kappa = 1 broke the grooves
        into shorter pieces).
    alignment : {"field", "axes"}
        ``"field"``: neighbourhoods sampled in each voxel's frame and voxels
        visited along the field (the paper). ``"axes"``: the reference that
        ignores the fields: neighbourhoods on the grid's axes and voxels
        swept along the depth axis (image analogies on a voxel grid).
    rng : None, int or numpy.random.Generator
        Seeds the draws among equally good matches.
    return_info : bool
        Also return an :class:`AnalogiesInfo`.
    progress : bool or callable
        A progress bar (True) or a callback ``(step, total, info)``, one step
        per voxel synthesised (advanced a wavefront at a time).

    Returns
    -------
    b_prime : numpy.ndarray
        float64 ``(D, H, W)`` signed distance volume of ``b``'s shape: ``b``'s
        distances outside the band, the copied (clipped) values of
        ``a_prime`` inside it; :func:`sdf_to_mesh` gives its surface.
    info : AnalogiesInfo
        With ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        Volumes that are not 3-D, ``a`` and ``a_prime`` of different shapes,
        a surface-less ``b``, a band of ``a`` too small to match, bad fields
        or options, or a size that does not fit in memory.
    """
    t_start = time.perf_counter()
    stages = {}
    neighborhood_size = check_positive_int(neighborhood_size, "neighborhood_size", 3, 15)
    if neighborhood_size % 2 == 0:
        raise ValueError(f"neighborhood_size must be odd (a centre voxel), got {neighborhood_size}; "
                         f"pass {neighborhood_size + 1}")
    levels = check_positive_int(levels, "levels", 1, 5)
    band = check_positive_float(band, "band", maximum=64.0)
    if band < 1.5:
        raise ValueError(f"band must be at least 1.5 voxels (a shell around the surface), got {band}")
    error_tolerance = check_positive_float(error_tolerance, "error_tolerance", allow_zero=True)
    coherence = check_positive_float(coherence, "coherence", allow_zero=True)
    alignment = check_choice(alignment, "alignment", ALIGNMENTS)
    return_info = check_bool(return_info, "return_info")
    gen = as_rng(rng)

    t0 = time.perf_counter()
    shape_b = np.shape(b)
    if len(shape_b) == 3:  # b's distance, density, result and masks (~8 float64 copies), before converting it
        check_memory(64.0 * np.prod(shape_b, dtype=np.float64), shape_b, "b", "b's distance volumes")
    sdf_a, sdf_ap, sdf_b = (as_distance_field(v, name) for v, name in ((a, "a"), (a_prime, "a_prime"), (b, "b")))
    if sdf_a.shape != sdf_ap.shape:
        raise ValueError(f"a_prime must have a's shape {sdf_a.shape} (the same model with the texture), "
                         f"got {sdf_ap.shape}")
    coarsest = 2 ** (levels - 1)
    if min(sdf_b.shape) // coarsest < 4 or min(sdf_a.shape) // coarsest < 4:
        raise ValueError(f"levels={levels} subsamples the volumes by {coarsest}: a and b need at least "
                         f"{4 * coarsest} voxels a side; pass fewer levels or larger volumes")
    if not (sdf_b.min() < 0 < sdf_b.max()):
        raise ValueError("b has no surface (it is all inside or all outside); pass a shape with a surface")
    field_a = _as_field(field_a, sdf_a.shape, "field_a")
    field_b = _as_field(field_b, sdf_b.shape, "field_b")
    # the candidates' vectors (float32, stacked with their squares and the known block: ~3.5 copies) and the band's
    n_a = int(np.sum(np.abs(sdf_a) < band))
    dims = 2 * neighborhood_size ** 3 + PARENT_SIZE ** 3
    check_memory(14.0 * n_a * dims + 64.0 * sdf_b.size, sdf_b.shape, "b",
                 "the candidate neighbourhoods of a's band and b's volumes")
    stages["distance fields"] = time.perf_counter() - t0

    offsets, parent_offsets = _grid(neighborhood_size), _grid(PARENT_SIZE)
    coarse = None  # (the coarser level's b_prime, a_prime) clipped, in their voxels
    counts, candidates_per_level = [], []
    total = sum(int(np.sum(np.abs(sdf_b[::2 ** lv, ::2 ** lv, ::2 ** lv]) < max(band, 1.5 * 2 ** lv)))
                for lv in range(levels))
    with Progress(progress, total, "geometry_analogies") as bar:
        for level in range(levels - 1, -1, -1):
            t0 = time.perf_counter()
            f = 2 ** level
            vols = [v[::f, ::f, ::f] / f for v in (sdf_a, sdf_ap, sdf_b)]
            result = _level(*vols, field_a, field_b, f, max(band / f, 1.5), offsets, parent_offsets, coarse,
                            error_tolerance, coherence * 2.0 ** -level, alignment, gen, bar)
            coarse = (result[0], np.clip(vols[1], -result[1], result[1]))
            counts.append(result[5])
            candidates_per_level.append(result[6])
            stages[f"level {level}"] = time.perf_counter() - t0
    b_prime_band, _, voxels, sources, sweep = result[:5]
    out = sdf_b.copy()
    out[tuple(voxels.T)] = b_prime_band[tuple(voxels.T)]
    if not return_info:
        return out
    return out, AnalogiesInfo(voxels=voxels, sources=sources, sweep=sweep, wavefronts=tuple(counts),
                              n_candidates=tuple(candidates_per_level), seconds=time.perf_counter() - t_start,
                              stage_seconds=stages)


def _level(sdf_a, sdf_ap, sdf_b, field_a, field_b, scale, band, offsets, parent_offsets, coarse, error_tolerance,
           kappa, kind, gen, bar):
    """One level: b_prime (clipped) over b's band, matched wavefront by wavefront along the sweep."""
    clip = lambda v: np.clip(v, -band, band)  # noqa: E731
    cap, cb = clip(sdf_ap), clip(sdf_b)
    da, db = (ndimage.gaussian_filter(clip(v), DENSITY_SIGMA) for v in (sdf_a, sdf_b))
    # the candidates: a's band, away from the volume's faces by the neighbourhood's reach
    reach = int(np.ceil((len(offsets) ** (1 / 3) // 2) * np.sqrt(3))) + 1
    inner = np.zeros(sdf_a.shape, bool)
    inner[reach:-reach, reach:-reach, reach:-reach] = True
    cand = np.argwhere((np.abs(sdf_a) < band) & inner)
    if len(cand) < 8:
        raise ValueError(f"a has {len(cand)} voxels within {band:.3g} of its surface and "
                         f"{reach} voxels from its faces at subsampling {scale}; pass larger volumes a and a_prime, "
                         "fewer levels or a smaller neighborhood_size")
    voxels = np.argwhere(np.abs(sdf_b) < band)
    if len(voxels) == 0:
        raise ValueError(f"b has no voxel within {band:.3g} of its surface at subsampling {scale}; pass fewer levels")
    k3 = len(offsets)
    frames_a, _ = _frames(sdf_a, cand, field_a, scale, kind)
    frames_b, tangents_b = _frames(sdf_b, voxels, field_b, scale, kind)

    # the candidates' vectors: [a | a_prime coarse (all known) | a_prime (masked like b_prime)]
    parts = []
    for start in range(0, len(cand), 4096):
        sl = slice(start, start + 4096)
        (sa, sap), _ = _sample([da, cap], cand[sl].astype(float), frames_a[sl], offsets)
        pieces = [sa]
        if coarse is not None:
            (sc,), _ = _sample([coarse[1]], cand[sl] / 2.0, frames_a[sl], parent_offsets)
            pieces.append(2.0 * sc)  # in this level's voxels
        parts.append(np.concatenate(pieces + [sap], axis=1).astype(np.float32))
    vectors = np.concatenate(parts)
    known = k3 + (len(parent_offsets) if coarse is not None else 0)
    weights = np.ones(vectors.shape[1], np.float32)
    weights[:k3] = UNFILTERED_WEIGHT
    index = MaskedIndex(vectors, weights=weights, blocks=[np.arange(known)])
    values = cap[tuple(cand.T)]
    cand_at = np.full(sdf_a.shape, -1, np.int64)  # a voxel -> its candidate row (-1: not a candidate)
    cand_at[tuple(cand.T)] = np.arange(len(cand))

    # b's own part and the coarse part of every band voxel are known before the sweep
    fixed = []
    for start in range(0, len(voxels), 4096):
        sl = slice(start, start + 4096)
        (sb,), _ = _sample([db], voxels[sl].astype(float), frames_b[sl], offsets)
        pieces = [sb]
        if coarse is not None:
            (sc,), _ = _sample([coarse[0]], voxels[sl] / 2.0, frames_b[sl], parent_offsets)
            pieces.append(2.0 * sc)
        fixed.append(np.concatenate(pieces, axis=1).astype(np.float32))
    fixed = np.concatenate(fixed)

    # b_prime starts as b (coarsest level) or the coarser result brought up; outside the band it is b, known
    b_prime = cb.copy()
    if coarse is not None:
        up = ndimage.map_coordinates(coarse[0], (voxels / 2.0).T, order=1, mode="nearest")
        b_prime[tuple(voxels.T)] = np.clip(2.0 * up, -band, band)
    done = np.abs(sdf_b) >= band
    source_at = np.full(sdf_b.shape, -1, np.int64)  # b's band voxel -> the candidate row it copied

    sweep = _sweep(voxels, tangents_b, sdf_b.shape)
    order = np.argsort(sweep, kind="stable")
    voxels, frames_b, fixed, sweep = voxels[order], frames_b[order], fixed[order], sweep[order]
    wave = np.floor(sweep / WAVEFRONT_STEP).astype(np.int64)
    bounds = np.flatnonzero(np.r_[True, wave[1:] != wave[:-1], True])
    sources = np.empty(len(voxels), np.int64)
    hi = np.array(sdf_b.shape) - 1
    for w in range(len(bounds) - 1):
        sl = slice(bounds[w], bounds[w + 1])
        (sbp,), points = _sample([b_prime], voxels[sl].astype(float), frames_b[sl], offsets)
        near = np.clip(np.rint(points).astype(np.int64), 0, hi)
        mask = done[near[..., 0], near[..., 1], near[..., 2]]
        queries = np.concatenate([fixed[sl], sbp.astype(np.float32)], axis=1)
        masks = np.concatenate([np.ones((len(sbp), known), bool), mask], axis=1)
        idx, d2, _, _ = index.near_best(queries, masks, error_tolerance, gen.random(len(sbp)))
        if kappa > 0:
            idx = _coherent(idx, d2, kappa, queries, masks, voxels[sl], frames_b[sl], source_at, cand, frames_a,
                            cand_at, vectors, weights)
        target = tuple(voxels[sl].T)
        b_prime[target] = values[idx]
        done[target] = True
        source_at[target] = idx
        sources[sl] = idx
        bar.advance({"level scale": scale, "wavefront": w}, n=len(sbp))
    return b_prime, band, voxels, cand[sources], sweep, len(bounds) - 1, len(cand)
