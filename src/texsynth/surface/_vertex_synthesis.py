"""Texture synthesis on surfaces by colouring mesh vertices (Turk 2001; Wei & Levoy 2001).

Turk [1]_ and Wei & Levoy [2]_ carry multi-resolution neighbourhood
matching (Wei & Levoy 2000) from the pixel grid to a surface, in the same
three ingredients followed here:

1. **A mesh hierarchy**: the surface retiled (Turk 1992,
   :func:`~texsynth.surface.retile`) into meshes of evenly spaced vertices,
   each level with a quarter of the vertices of the next finer one, so the
   vertex spacing doubles per level like the pixel spacing of the
   exemplar's Gaussian pyramid (:func:`texsynth.core.pyramid.gaussian_pyramid`).
   The finest spacing is the ``pixel_size`` of the texture: the length on
   the surface of one exemplar pixel.
2. **An orientation**: a tangent field (:func:`~texsynth.surface.tangent_field`)
   says where the exemplar's x axis runs at every vertex.
3. **Surface neighbourhoods**: around a vertex ``p`` with normal ``n`` and
   field vector ``t``, a square grid of ``w x w`` points ``p + h (j t - i
   (n x t))`` (``h`` the level's spacing) is laid in the tangent plane (the
   *flattening* of the neighbourhood along the field), and the colours of the
   already-synthesised vertices are *resampled* at those grid points
   (the colour of the nearest vertex, skipping vertices that face the other
   way: the query holds exemplar colours, like the exemplar's own
   neighbourhoods, never blends of them); below the coarsest level a
   ``w' x w'`` grid at twice the spacing reads the parent level's colours.
   The vector is compared with the exemplar's multi-level neighbourhoods
   (:func:`texsynth.core.neighborhood.multilevel_vectors`) under a Gaussian
   fall-off of sigma half the neighbourhood's side, through the shared
   search layer (:mod:`texsynth.core.search`), and the vertex takes the
   colour of the best match's centre pixel.

Order: by default (``order="independent"``) *parallel passes* (the
order-independent variant of Wei & Levoy 2002 and Lefebvre & Hoppe 2005 [3]_)
rather than the papers' one vertex at a time: every vertex of a level is
matched at once from the colours of the previous pass, ``passes`` times per
level, so the inner loop is a few sparse products and one batched search per
pass, and neighbourhoods are full squares. ``order="sweep"`` (the paper
preset's) is Turk's order: the vertices are sorted by a *sweep distance*
(:func:`_sweep_distance`) so that visiting them in order scans the surface
as a scanline scans an image, row after row along the field, and each is
matched on its own, its query holding at this level only the vertices
already visited (the causal half of Wei & Levoy's neighbourhoods) and the
whole parent neighbourhood: a loop over the vertices, as the papers' order
is sequential by nature. It is not the default: once a sequential sweep
copies the inside of one stone it can go on copying it over the surface
(measured in ``docs/methods/vertex_synthesis.md``).

Search: ``candidates="k-coherent"`` (default) compares each vertex with
the k-coherent candidates (Ashikhmin 2001, Tong et al. 2002;
:class:`~texsynth.core.search.KCoherence`): for its 8 nearest vertices ``r``
at flattened offset ``d`` (in the vertex's frame, rounded to pixels), the
exemplar position ``s(r) - d`` that continues ``r``'s copy, plus the
position the parent level predicts for the vertex (its nearest parent
vertex's source, moved by the offset and doubled) and its own current
source, each with its ``k - 1`` most similar positions. The coarsest level
starts from random exemplar positions and is searched globally
(:class:`~texsynth.core.search.PatchIndex`), as is every level with
``candidates="all"``. Copies so continue in pieces over the surface, which
keeps structured textures' elements whole; with a random field (isotropic
textures) neighbouring copies do not line up and ``candidates="all"`` is
the better choice.

What could not be checked: the papers were not at hand. Wei & Levoy
resample by flattening the mesh around the vertex and interpolating on it,
Turk by walking over the surface; the tangent-plane grid with a 3-D
nearest-vertex resampling, the parallel passes with coherent candidates, the
Gaussian fall-off and the defaults (9 x 9 and 5 x 5 neighbourhoods, 3
levels, 2 passes of 4 subpasses, ``k=2``) are this implementation's choices.
``preset="paper"`` keeps Turk's sweep order, one pass per level, the
papers' global search (``candidates="all"``) and the 5 x 5 / 3 x 3
neighbourhoods of Wei & Levoy 2000's multi-resolution examples (the surface
papers' own sizes could not be checked) under a fall-off of sigma a quarter
of the side. How Turk computes the sweep distance could not be checked
either: his abstract says only that the vertices are "sorted in such a way
that visiting the points in order will follow the vector field and will
sweep across the surface from one end to the other"; the least-squares
potential along the rows' direction is this implementation's reading. The
sweep's queries weigh each grid point by whether its vertex is visited,
differently for every vertex, so its global search is the search layer's
masked exact search (:class:`~texsynth.core.search.MaskedIndex`) rather
than Wei & Levoy 2000's TSVQ, which cannot weigh queries one by one
(``method="tsvq"`` serves the paper preset with ``order="independent"``,
where the grid points off an open surface hold the exemplar's mean
neighbourhood). Both presets read each grid point from the nearest vertex:
a Gaussian-weighted mean of the 4 nearest (the first version's reading of
the papers' interpolation) made soft queries that favoured the smooth
insides of bricks and stones, and in the sweep order grew them into streaks
along the sweep (``docs/methods/vertex_synthesis.md``).

References
----------
.. [1] G. Turk, "Texture synthesis on surfaces", SIGGRAPH 2001, pp. 347-354.
   :doi:`10.1145/383259.383297`
.. [2] L.-Y. Wei and M. Levoy, "Texture synthesis over arbitrary manifold
   surfaces", SIGGRAPH 2001, pp. 355-360. :doi:`10.1145/383259.383298`
.. [3] S. Lefebvre and H. Hoppe, "Parallel controllable texture synthesis",
   SIGGRAPH 2005, pp. 777-786. :doi:`10.1145/1073204.1073261`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np
import scipy.sparse
import scipy.sparse.csgraph
import scipy.sparse.linalg

from ..core._progress import Progress
from ..core._validate import as_image, as_rng, check_group, check_memory, check_positive_int, with_channels
from ..core.neighborhood import extract, gaussian_falloff, multilevel_vectors, patch_shape
from ..core.pyramid import gaussian_pyramid
from ..core.search import (KCoherence, MaskedIndex, PatchIndex, Search, check_method, is_auto, nearest_candidates,
                           point_tree, refuse_augment)
from ._field import check_field, field_vectors
from ._meshio import as_mesh
from ._retile import lattice_spacing, mesh_hierarchy, resolve_count

__all__ = ["synthesize_surface", "SurfaceSchedule", "SurfaceSynthesisInfo", "CANDIDATES", "ORDERS", "PRESETS"]

#: How a vertex's candidates are found.
CANDIDATES = ("k-coherent", "all")
#: How a level's vertices are visited: all at once per pass, or one at a time along Turk's sweep.
ORDERS = ("independent", "sweep")
#: Named defaults: what ``"auto"`` means under ``"default"`` and ``"paper"`` (see :func:`synthesize_surface`).
#: ``falloff`` (the Gaussian weights' sigma as a fraction of the neighbourhood's side) is not an option, only the
#: presets' choice (see the module notes).
PRESETS = {
    "default": dict(neighborhood_size=9, parent_size=5, levels=3, order="independent", passes=2,
                    candidates="k-coherent", k=2, method="auto", falloff=0.5),
    "paper": dict(neighborhood_size=5, parent_size=3, levels=3, order="sweep", passes=1, candidates="all", k=1,
                  method="tsvq", falloff=0.25),
}

_RESAMPLE_NEIGHBORS = 4    # nearest vertices of a grid point, of which the first facing its way gives the colour
_COHERENT_NEIGHBORS = 8    # vertices whose copies are continued
SUBPASSES = 4              # groups of vertices matched in turn within a pass
_FACING = 0.2              # a vertex whose normal is below this cosine to the centre's does not count
_SWEEP_BYTES = 4096        # the sweep distance's sparse solve per vertex (measured 2.1-3.0 kB, 50,000 to 10^6 vertices)


@dataclass
class SurfaceSynthesisInfo:
    """Extra results of :func:`synthesize_surface`.

    Attributes
    ----------
    levels : list of Mesh
        The mesh hierarchy, finest first, each coloured by its level's result.
    field : numpy.ndarray
        ``(N, 3)`` the tangent vector used at each output vertex.
    sources : numpy.ndarray of int
        ``(N, 2)`` the exemplar pixel ``(row, col)`` each output vertex was
        copied from (the source-coordinate map of ``docs/conventions.md``).
    energy : list of float
        Per level, coarsest first: the mean weighted squared distance of the
        vertices' neighbourhoods to their matches at the last pass.
    pixel_size : float
        The length on the surface of one exemplar pixel (the finest spacing).
    candidates, method : str
        The search used (``method``: the backend of the global searches or
        of the k-coherence sets).
    order : str
        How each level's vertices were visited (``"independent"`` or ``"sweep"``).
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"hierarchy"``, ``"field"`` and each ``"level l"``.
    """

    levels: list = dataclass_field(default_factory=list)
    field: np.ndarray | None = None
    sources: np.ndarray | None = None
    energy: list = dataclass_field(default_factory=list)
    pixel_size: float = 0.0
    candidates: str = ""
    method: str = ""
    order: str = ""
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


@dataclass(frozen=True)
class SurfaceSchedule:
    """The levels of a surface synthesis and how each is visited (Turk 2001; Wei & Levoy 2001).

    Examples
    --------
    >>> import texsynth
    >>> texsynth.SurfaceSchedule(levels=2, order="sweep")
    SurfaceSchedule(neighborhood_size='auto', parent_size='auto', levels=2, order='sweep', passes='auto')

    An option group of :func:`~texsynth.synthesize_surface`
    (``schedule=SurfaceSchedule(...)``); on the command line its fields are
    flags (``--levels``, ``--order``, ...). ``"auto"``: the value of the
    function's ``preset`` (:data:`PRESETS`).

    Parameters
    ----------
    neighborhood_size : int, (int, int) or "auto"
        Neighbourhood at each level, in exemplar pixels. ``"auto"``: 9 (on a
        brick photograph with bricks 20 x 45 pixels, 5 x 5 lost the bricks'
        outlines over 3 levels and 9 x 9 kept them), 5 with ``preset="paper"``.
    parent_size : int, (int, int) or "auto"
        Neighbourhood at the parent level. ``"auto"``: 5 (3 with
        ``preset="paper"``).
    levels : int or "auto"
        Levels of the mesh hierarchy and exemplar pyramid. ``"auto"``: 3.
    order : {"independent", "sweep", "auto"}
        How a level's vertices are visited: all at once from the previous
        pass's colours, ``passes`` times (``"independent"``, the default's),
        or one at a time in Turk's sweep order with causal neighbourhoods
        (``"sweep"``, ``preset="paper"``'s; a second pass sees every vertex).
        docs/methods/vertex_synthesis.md compares the two.
    passes : int or "auto"
        Matching passes per level. ``"auto"``: 2 (1 with ``preset="paper"``).

    """

    neighborhood_size: object = "auto"
    parent_size: object = "auto"
    levels: object = "auto"
    order: str = "auto"
    passes: object = "auto"


def grid_offsets(size):
    """(row, col) offsets of a ``size`` grid about its centre (the convention of ``extract``)."""
    h, w = size
    rows, cols = np.mgrid[-(h // 2):h - h // 2, -(w // 2):w - w // 2]
    return np.stack([rows.ravel(), cols.ravel()], axis=1)


class SurfaceFrame:
    """A level's points with their normals, field and bitangents (``b = n x t``) and a kd-tree."""

    def __init__(self, mesh, tangents, spacing):
        self.mesh = mesh
        self.points = mesh.vertices
        self.normals = mesh.vertex_normals
        self.t = tangents
        self.b = np.cross(self.normals, tangents)
        self.spacing = spacing
        self.tree = point_tree(self.points)

    def flatten(self, centers, others):
        """(row, col) of points ``others`` (M, J, 3) in the frames of ``centers`` (M,), in spacings."""
        d = others - self.points[centers, None, :]
        return np.stack([-np.einsum("mjk,mk->mj", d, self.b[centers]),
                         np.einsum("mjk,mk->mj", d, self.t[centers])], axis=-1) / self.spacing


def resample_grid(frame, source, offsets, step):
    """Which of ``source``'s vertices gives its colour to each grid point of every vertex of ``frame``.

    Grid point ``j`` of vertex ``p`` is ``p + step (col_j t - row_j b)``; its value is that of the nearest
    source vertex facing the same way as ``p`` (among its :data:`_RESAMPLE_NEIGHBORS` nearest): an exemplar
    colour, as the papers copy colours and never blend them. Returns the vertex ``(N, J)`` and whether the
    point found one ``(N, J)`` (a point off an open surface's edge may not).
    """
    n, j = len(frame.points), len(offsets)
    grid = (frame.points[:, None, :] + step * (offsets[None, :, 1, None] * frame.t[:, None, :]
                                               - offsets[None, :, 0, None] * frame.b[:, None, :]))
    _, near = source.tree.query(grid.reshape(-1, 3), k=_RESAMPLE_NEIGHBORS)
    facing = np.einsum("pkd,pd->pk", source.normals[near], np.repeat(frame.normals, j, axis=0)) > _FACING
    first = np.argmax(facing, axis=1)
    rows = np.arange(n * j)
    return near[rows, first].reshape(n, j), facing[rows, first].reshape(n, j)


def resampling_matrix(vertex, valid, count):
    """The sparse ``(N * J, count)`` map from vertex values to the grid points of :func:`resample_grid`."""
    rows = np.flatnonzero(valid.ravel())
    return scipy.sparse.csr_matrix((np.ones(rows.shape[0]), (rows, vertex.ravel()[rows])),
                                   shape=(valid.size, count))


class ExemplarLevel:
    """One exemplar pyramid level: its candidate centres, their neighbourhood vectors and weights.

    The weights are Gaussian fall-offs of sigma ``falloff`` times each neighbourhood's larger side.
    """

    def __init__(self, image, parent, size, parent_size, falloff):
        h, w = size
        rows = np.arange(h // 2, image.shape[0] - (h - 1 - h // 2))
        cols = np.arange(w // 2, image.shape[1] - (w - 1 - w // 2))
        self.image = image
        self.shape = (len(rows), len(cols))
        r, c = np.meshgrid(rows, cols, indexing="ij")
        self.centers = np.stack([r.ravel(), c.ravel()], axis=1)
        channels = image.shape[2]
        here = np.repeat(gaussian_falloff(size, falloff * max(size)).ravel(), channels)
        if parent is None:
            self.vectors = extract(image, self.centers, size, mode="valid").reshape(len(self.centers), -1)
            self.weights = here
        else:
            self.vectors = multilevel_vectors(image, parent, self.centers, size, parent_size, mode="reflect")
            above = gaussian_falloff(parent_size, falloff * max(parent_size))
            self.weights = np.concatenate([here, np.repeat(above.ravel(), channels)])
        self.colors = image[self.centers[:, 0], self.centers[:, 1]]

    def cell(self, positions, rng):
        """Grid cells of exemplar pixels ``(M, 2)``; a pixel outside the candidate region gets a random cell
        (Ashikhmin's rule: a copy that runs off the exemplar ends there, rather than smearing its edge)."""
        r = positions[:, 0] - self.centers[0, 0]
        c = positions[:, 1] - self.centers[0, 1]
        cells = r * self.shape[1] + c
        outside = (r < 0) | (r >= self.shape[0]) | (c < 0) | (c >= self.shape[1])
        cells[outside] = rng.integers(0, len(self.centers), int(outside.sum()))
        return cells


def _check_choice(value, choices, name):
    if not isinstance(value, str) or value not in choices:
        raise ValueError(f"{name} must be one of {', '.join(map(repr, choices))}, got {value!r}")
    return value


def synthesize_surface(
    mesh,
    exemplar,
    *,
    n_vertices=None,
    pixel_size=None,
    field="smooth",
    symmetry=1,
    schedule=SurfaceSchedule(),
    search=Search(candidates="auto"),
    preset="default",
    rng=None,
    progress=False,
    return_info=False,
):
    """Synthesise a texture over a surface by colouring its vertices (Turk 2001; Wei & Levoy 2001).

    Examples
    --------
    >>> import texsynth
    >>> ball, bread = texsynth.surface.sphere(3), texsynth.data.load("bread")[:48, :48]
    >>> out = texsynth.synthesize_surface(ball, bread, n_vertices=600, schedule=texsynth.SurfaceSchedule(levels=2), rng=0)
    >>> out.colors.shape[1], bool(0 <= out.colors.min() and out.colors.max() <= 1)
    (3, True)

    Multi-resolution neighbourhood matching carried from the pixel grid to
    a surface: the mesh is retiled into a hierarchy of evenly spaced
    vertices, a tangent field orients the texture, and every vertex takes
    the colour of the exemplar pixel whose neighbourhood best matches its
    own, resampled in its tangent plane (Turk [1]_; Wei & Levoy [2]_).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`); closed or open.
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    n_vertices : int, optional
        Retile the surface to about this many vertices (the output mesh).
    pixel_size : float, optional
        Instead of ``n_vertices``: the length on the surface of one exemplar
        pixel (the vertex spacing), which sets the density. With neither,
        the mesh's own vertices are coloured (and its area per vertex sets
        the pixel size); retiling is better for uneven meshes.
    field : {"smooth", "random"}, array_like (N, 3) or callable
        Orientation of the texture's x axis (:func:`~texsynth.surface.tangent_field`):
        relaxed (default), random (isotropic textures; use with
        ``candidates="all"``), a vector per input vertex, or a callable of
        positions ``(P, 3) -> (P, 3)``.
    symmetry : {1, 2, 4}
        Rotational symmetry of the texture, used by the relaxed field.
    schedule : SurfaceSchedule
        The ``neighborhood_size`` and ``parent_size``, the ``levels``, and
        the ``order`` and number of ``passes`` in which each level's vertices
        are matched (:class:`SurfaceSchedule`; ``"auto"``: the preset's).
    search : texsynth.core.search.Search
        ``candidates``: the search below the coarsest level, ``"k-coherent"``
        or ``"all"`` (module notes); ``k``: the size of the k-coherence sets;
        ``method``: the backend of the global searches and of the
        k-coherence sets (the sweep's global search is always exact: module
        notes). ``"auto"``: the preset's (``"k-coherent"``, 2 and the search
        layer's choice; ``"all"``, 1 and ``"tsvq"`` with ``preset="paper"``).
    preset : {"default", "paper"}
        What the options left at ``"auto"`` mean (:data:`PRESETS`):
        ``"default"`` as above (with a fall-off of sigma half the
        neighbourhood's side); ``"paper"``: Turk's sweep order, global
        search, one pass per level, 5 x 5 and 3 x 3 neighbourhoods, fall-off
        of sigma a quarter of the side (module notes).
    rng : None, int or numpy.random.Generator
        Seeds the retiling, the field and the initial colours. Same seed,
        same result.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return a :class:`SurfaceSynthesisInfo`.

    Returns
    -------
    Mesh
        The (retiled) surface with per-vertex colours of the exemplar's
        channels.
    info : SurfaceSynthesisInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid mesh, exemplar, field (wrong length, NaN), option
        (or option group of the wrong type),
        a neighbourhood larger than the exemplar's coarsest level, a density
        (``n_vertices`` or ``pixel_size``) needing more memory than is available,
        or too few vertices for ``levels``.

    References
    ----------
    .. [1] G. Turk, "Texture synthesis on surfaces", SIGGRAPH 2001, pp. 347-354.
       :doi:`10.1145/383259.383297`
    .. [2] L.-Y. Wei and M. Levoy, "Texture synthesis over arbitrary manifold
       surfaces", SIGGRAPH 2001, pp. 355-360. :doi:`10.1145/383259.383298`
    """
    start = time.perf_counter()
    mesh = as_mesh(mesh)
    if not isinstance(preset, str) or preset not in PRESETS:
        raise ValueError(f"preset must be one of {', '.join(map(repr, PRESETS))}, got {preset!r}")
    schedule = check_group(schedule, SurfaceSchedule, "schedule")
    search = check_group(search, Search, "search")
    refuse_augment(search.augment, "synthesize_surface", "the tangent field already orients the exemplar on the "
                   "surface")
    chosen = dict(PRESETS[preset])
    for name, value in dict(neighborhood_size=schedule.neighborhood_size, parent_size=schedule.parent_size,
                            levels=schedule.levels, order=schedule.order, passes=schedule.passes,
                            candidates=search.candidates, k=search.k, method=search.method).items():
        if not is_auto(value):
            chosen[name] = value
    size = patch_shape(chosen["neighborhood_size"], "neighborhood_size")
    psize = patch_shape(chosen["parent_size"], "parent_size")
    levels = check_positive_int(chosen["levels"], "levels")
    order = _check_choice(chosen["order"], ORDERS, "order")
    passes = check_positive_int(chosen["passes"], "passes")
    candidates = _check_choice(chosen["candidates"], CANDIDATES, "candidates")
    k = check_positive_int(chosen["k"], "k")
    method = check_method(chosen["method"])
    field = check_field(field, len(mesh.vertices), symmetry)
    rng = as_rng(rng)
    image = with_channels(as_image(exemplar, "exemplar"))[0]  # a grey exemplar gives 1-channel colours
    pyramid = gaussian_pyramid(image, levels)
    coarsest = pyramid[-1].shape[:2]
    need = (max(size[0], psize[0]), max(size[1], psize[1]))
    if coarsest[0] < need[0] or coarsest[1] < need[1]:
        raise ValueError(f"the exemplar's coarsest level (levels={levels}) is {coarsest[0]}x{coarsest[1]} pixels, "
                         f"smaller than the {need[0]}x{need[1]} neighbourhood; pass fewer levels, a smaller "
                         "neighborhood_size or a larger exemplar")
    if n_vertices is None and pixel_size is None:
        n = len(mesh.vertices)
        density = "n_vertices"
    else:
        n = resolve_count(mesh, n_vertices, pixel_size, "pixel_size")
        density = "n_vertices" if pixel_size is None else "pixel_size"
    j_total = size[0] * size[1] + psize[0] * psize[1]
    per_vertex = j_total * (_RESAMPLE_NEIGHBORS * 24 + 8 * image.shape[2]) + (_SWEEP_BYTES if order == "sweep" else 0)
    check_memory(float(n) * per_vertex, n if density == "n_vertices" else pixel_size, density,
                 "the surface neighbourhoods")
    info = SurfaceSynthesisInfo(candidates=candidates, method=method, order=order)

    t0 = time.perf_counter()
    hierarchy = mesh_hierarchy(mesh, n, levels, finest=mesh if n_vertices is None and pixel_size is None else None,
                               rng=rng)
    info.stage_seconds["hierarchy"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    frames, spacing = level_frames(mesh, hierarchy, field, symmetry, rng)
    info.stage_seconds["field"] = time.perf_counter() - t0
    info.pixel_size = spacing

    offsets, parent_offsets = grid_offsets(size), grid_offsets(psize)
    colors, sources, parent_centers = None, None, None
    with Progress(progress, levels * passes, "surface") as bar:
        for level in range(levels - 1, -1, -1):
            t0 = time.perf_counter()
            frame = frames[level]
            parent = frames[level + 1] if level + 1 < levels else None
            ex = ExemplarLevel(pyramid[level], None if parent is None else pyramid[level + 1], size, psize,
                               chosen["falloff"])
            channels = image.shape[2]
            vertex, valid = resample_grid(frame, frame, offsets, frame.spacing)
            weights = ex.weights
            fixed_part = None
            if parent is not None:
                up, pvalid = resample_grid(frame, parent, parent_offsets, parent.spacing)
                fixed_part = (resampling_matrix(up, pvalid, len(parent.points)) @ colors).reshape(len(frame.points),
                                                                                                  -1)
                valid = np.concatenate([valid, pvalid], axis=1)
            query_weights = None
            if not valid.all() or order == "sweep":  # grid points off an open surface's edge do not count
                query_weights = np.repeat(valid, channels, axis=1) * weights
            if parent is None:
                predicted = seed_sources(frame, ex, rng)
            else:
                predicted = predict_sources(frame, parent, parent_centers, ex, rng)
            sources = predicted
            if candidates == "k-coherent":
                searcher = CoherentSearch(frame, ex, k, method, predicted, rng)
            elif order == "sweep":
                searcher = _Causal(ex)
            else:
                searcher = GlobalSearch(ex, method, len(frame.points), rng)
            if order == "sweep":
                sources, d2 = _sweep_level(ex, vertex, fixed_part, query_weights, sources, searcher, passes,
                                           _sweep_distance(frame, symmetry), rng, bar, level)
            else:
                here = resampling_matrix(vertex, valid[:, :len(offsets)], len(frame.points))
                sources, d2 = match_level(frame, ex, here, fixed_part, query_weights, sources, searcher, passes,
                                          SUBPASSES, rng, bar, level)
            info.method = searcher.method
            colors = ex.colors[sources]
            parent_centers = ex.centers[sources]
            info.energy.append(float(np.mean(d2)))
            info.stage_seconds[f"level {level}"] = time.perf_counter() - t0
            info.levels.insert(0, hierarchy[level].with_colors(np.clip(colors, 0, 1)))
    out = info.levels[0]
    info.field = frames[0].t
    info.sources = ex.centers[sources]
    info.seconds = time.perf_counter() - start
    return (out, info) if return_info else out


@dataclass(frozen=True)
class GuidedSchedule:
    """The resolved options of a guided vertex synthesis (:func:`guided_options`, :func:`guided_levels`)."""

    size: tuple
    parent_size: tuple
    levels: int
    passes: int
    k: int
    method: str
    falloff: float


def guided_options(schedule, search, function, why):
    """A :class:`GuidedSchedule` from a method's ``schedule`` and ``search`` (``"auto"``: the default preset's).

    For the methods that synthesise guided vertex colours on :func:`guided_levels` (progressively-variant
    and feature-aligned textures): k-coherent candidates below the coarsest level and the independent
    order only; ``function`` names the method in the errors and ``why`` says why it refuses augmentation.
    """
    schedule = check_group(schedule, SurfaceSchedule, "schedule")
    search = check_group(search, Search, "search")
    refuse_augment(search.augment, function, why)
    if not (is_auto(search.candidates) or search.candidates == "k-coherent"):
        raise ValueError(f"{function} searches k-coherent candidates below the coarsest level; pass "
                         f"search=Search(candidates='k-coherent'), got candidates={search.candidates!r}")
    if not (is_auto(schedule.order) or schedule.order == "independent"):
        raise ValueError(f"{function} matches in the independent order only; pass "
                         f"schedule=SurfaceSchedule(order='independent'), got order={schedule.order!r}")
    chosen = dict(PRESETS["default"])
    for name, value in dict(neighborhood_size=schedule.neighborhood_size, parent_size=schedule.parent_size,
                            levels=schedule.levels, passes=schedule.passes, k=search.k, method=search.method).items():
        if not is_auto(value):
            chosen[name] = value
    return GuidedSchedule(patch_shape(chosen["neighborhood_size"], "neighborhood_size"),
                          patch_shape(chosen["parent_size"], "parent_size"),
                          check_positive_int(chosen["levels"], "levels"), check_positive_int(chosen["passes"], "passes"),
                          check_positive_int(chosen["k"], "k"), check_method(chosen["method"]), chosen["falloff"])


def guided_levels(frames, pyramid, guides, schedule, rng, bar, stage_seconds, label="level"):
    """A multi-level vertex synthesis whose last channels are given per vertex (a guide).

    ``pyramid`` holds the exemplar's levels, finest first, each ``(h, w, C)``; ``guides[l]`` ``(N_l, G)``
    stands for the last ``G`` channels in every query at level ``l`` (:func:`match_level`'s ``guide``). The
    rest is synthesised as :func:`synthesize_surface` does in the independent order: a global search at the
    coarsest level, k-coherent candidates below it (``schedule``: a :class:`GuidedSchedule`). Each level's
    time goes into ``stage_seconds["{label} {level}"]``.

    Returns
    -------
    values : list of numpy.ndarray
        Per level, finest first, ``(N_l, C)`` the synthesised values.
    sources : numpy.ndarray of int
        ``(N, 2)`` the finest level's exemplar pixels.
    energies : list of float
        Per level, coarsest first, the mean squared distance of the last pass.
    """
    levels = len(frames)
    offsets, parent_offsets = grid_offsets(schedule.size), grid_offsets(schedule.parent_size)
    channels = pyramid[0].shape[2]
    values, centers, energies = [None] * levels, None, []
    for level in range(levels - 1, -1, -1):
        t0 = time.perf_counter()
        frame = frames[level]
        parent = frames[level + 1] if level + 1 < levels else None
        n = len(frame.points)
        ex = ExemplarLevel(pyramid[level], None if parent is None else pyramid[level + 1], schedule.size,
                           schedule.parent_size, schedule.falloff)
        vertex, valid = resample_grid(frame, frame, offsets, frame.spacing)
        fixed_part = None
        if parent is None:
            predicted = seed_sources(frame, ex, rng)
            searcher = GlobalSearch(ex, schedule.method, n, rng)
        else:
            up, pvalid = resample_grid(frame, parent, parent_offsets, parent.spacing)
            above = np.concatenate([values[level + 1][:, :channels - guides[level + 1].shape[1]],
                                    guides[level + 1]], axis=1)
            fixed_part = (resampling_matrix(up, pvalid, len(parent.points)) @ above).reshape(n, -1)
            valid = np.concatenate([valid, pvalid], axis=1)
            predicted = predict_sources(frame, parent, centers, ex, rng)
            searcher = CoherentSearch(frame, ex, schedule.k, schedule.method, predicted, rng)
        query_weights = None if valid.all() else np.repeat(valid, channels, axis=1) * ex.weights
        here = resampling_matrix(vertex, valid[:, :len(offsets)], n)
        sources, d2 = match_level(frame, ex, here, fixed_part, query_weights, predicted, searcher, schedule.passes,
                                  SUBPASSES, rng, bar, level, guide=guides[level])
        values[level], centers = ex.colors[sources], ex.centers[sources]
        energies.append(float(np.mean(d2)))
        stage_seconds[f"{label} {level}"] = time.perf_counter() - t0
    return values, centers, energies


def level_frames(mesh, hierarchy, field, symmetry, rng):
    """The :class:`SurfaceFrame` of every level of a mesh hierarchy (finest first), and the finest spacing.

    One field for every level: made on the finest (from ``field``, checked by
    :func:`~texsynth.surface._field.check_field` against ``mesh``'s vertices), carried to the coarser ones by
    the nearest finest vertex (per-level fields would turn the parent's structure against the child's
    neighbourhoods). Level ``l``'s spacing is ``2**l`` times the finest, the lattice spacing of the surface.
    """
    spacing = lattice_spacing(float(mesh.face_areas.sum()), len(hierarchy[0].vertices))
    for level, m in enumerate(hierarchy):
        lost = int(np.count_nonzero(~(np.linalg.norm(m.vertex_normals, axis=1) > 0)))
        if lost:
            raise ValueError(f"mesh: {lost} of the {len(m.vertices)} vertices retiled at level {level} lie on no "
                             f"face (the mesh has parts smaller than the vertex spacing {spacing * 2 ** level:.3g}, "
                             "such as many small separate pieces); pass more n_vertices or fewer levels, or remove "
                             "the small pieces")
    tangents = field_vectors(hierarchy[0].vertices, hierarchy[0].vertex_normals, field, symmetry=symmetry, rng=rng,
                             vertices=mesh.vertices)
    frames = [SurfaceFrame(m, tangents if level == 0 else field_vectors(m.vertices, m.vertex_normals, tangents,
                                                                        vertices=hierarchy[0].vertices),
                           spacing * 2 ** level)
              for level, m in enumerate(hierarchy)]
    return frames, spacing


def predict_sources(frame, parent, parent_centers, ex, rng):
    """The exemplar cell the parent level predicts for each vertex: its nearest parent vertex's copy, continued.

    ``parent_centers`` (N_parent, 2) are the parent level's source pixels; a vertex at offset ``d`` (parent
    pixels, in the parent vertex's frame) continues that copy at ``2 (s + d)`` in this level's pixels.
    """
    _, near = parent.tree.query(frame.points)
    d = parent.flatten(near, frame.points[:, None, :])[:, 0]
    return ex.cell(np.rint(2 * (parent_centers[near] + d)).astype(np.int64), rng)


def seed_sources(frame, ex, rng):
    """Coarsest-level start: random copies of the exemplar, each continued from a seed vertex to its region.

    Seeds lie about half the exemplar level's smaller side apart; every vertex continues the copy of its
    nearest seed (the same continuation as :func:`predict_sources`, at this level's scale), so the level starts from
    coherent pieces with random seams, which the passes then repair (instead of per-vertex noise, which
    parallel matching turns into structure slowly). A copy that runs past the candidate region wraps around
    it: the seeds' pieces are as wide as the region, so with Ashikhmin's random restart (:meth:`ExemplarLevel.cell`)
    20-30 % of the coarsest level's vertices (a flat patch, bricks, seeds 0-2) started as per-vertex noise,
    which the passes never repaired.
    """
    n = len(frame.points)
    apart = max(2.0, 0.5 * min(ex.shape))
    seeds = rng.choice(n, size=int(np.clip(round(n / apart ** 2), 1, n)), replace=False)
    _, near = point_tree(frame.points[seeds]).query(frame.points)
    d = frame.flatten(seeds[near], frame.points[:, None, :])[:, 0]
    start = ex.centers[rng.integers(0, len(ex.centers), len(seeds))]
    wrapped = (np.rint(start[near] + d).astype(np.int64) - ex.centers[0]) % ex.shape + ex.centers[0]
    return ex.cell(wrapped, rng)


def _combed_rows(frame, symmetry):
    """The direction the exemplar's rows go down, ``-b``, at every vertex, made to agree between neighbours.

    A field for a texture with 2- or 4-fold symmetry may turn by a half or a quarter turn from one vertex to
    the next (the texture looks the same). Each vertex takes the turn of its ``-b`` nearest its predecessor's on
    a breadth-first tree of the mesh, one tree depth at a time (each depth's vertices at once).
    """
    down = -frame.b
    if symmetry == 1:
        return down
    turns = np.stack([down, -down, frame.t, -frame.t][:symmetry], axis=1)   # (N, symmetry, 3)
    i, j = frame.mesh.edges.T
    n = len(frame.points)
    graph = scipy.sparse.csr_matrix((np.ones(len(i)), (i, j)), shape=(n, n))
    _, label = scipy.sparse.csgraph.connected_components(graph, directed=False)
    roots = np.unique(label, return_index=True)[1]
    depth, pred = scipy.sparse.csgraph.shortest_path(graph, directed=False, unweighted=True, indices=roots,
                                                     return_predecessors=True)
    depth, pred = depth[label, np.arange(n)], pred[label, np.arange(n)]
    combed = down.copy()
    for d in range(1, int(depth.max()) + 1):
        v = np.flatnonzero(depth == d)
        best = np.argmax(np.einsum("vkd,vd->vk", turns[v], combed[pred[v]]), axis=1)
        combed[v] = turns[v, best]
    return combed


def _sweep_distance(frame, symmetry):
    """Turk's sweep distance of a level's vertices: visited in its increasing order, they scan the surface.

    Sorting the vertices by it is Turk's replacement for the scanline order of an image. An image is scanned
    row after row, down its columns; here the rows run along the field ``t`` and go down along ``-b = -(n x
    t)``, so the distance is the potential ``s`` whose differences along the level's edges best agree, in the
    least-squares sense, with the edges' lengths along ``-b`` (in vertex spacings): ``s_j - s_i ~ (p_j - p_i)
    . (-b_i - b_j) / 2``, with the field's symmetric turns undone between neighbours (:func:`_combed_rows`;
    an edge whose two directions still differ by more than 60 degrees, across a singularity or where the
    combing of a symmetric field closes on itself, is left out). Its gradient is the part of the ``-b``
    field that has one: for a field along the latitudes it runs from pole to pole; where the field only
    circles or is random, the distance is nearly constant and the order nearly arbitrary.
    """
    down = _combed_rows(frame, symmetry)
    i, j = frame.mesh.edges.T
    keep = np.einsum("ij,ij->i", down[i], down[j]) > 0.5
    i, j = i[keep], j[keep]
    along = np.einsum("ij,ij->i", frame.points[j] - frame.points[i], down[i] + down[j]) / (2 * frame.spacing)
    e = len(i)
    incidence = scipy.sparse.csr_matrix((np.r_[np.ones(e), -np.ones(e)], (np.r_[np.arange(e), np.arange(e)],
                                                                         np.r_[j, i])), shape=(e, len(frame.points)))
    # the normal equations, with a tiny pull towards 0 to fix the constant of every connected piece
    system = (incidence.T @ incidence + 1e-9 * scipy.sparse.identity(len(frame.points))).tocsc()
    return scipy.sparse.linalg.spsolve(system, incidence.T @ along)


def _sweep_level(ex, vertex, fixed_part, query_weights, sources, search, passes, sweep, rng, bar, level):
    """Turk's order: the vertices of a level matched one at a time, by increasing sweep distance.

    Each vertex's query holds, at this level, only the grid points whose vertices are already visited (the
    surface's causal neighbourhood, as the half-square of a scanline; the others weigh 0), and the whole parent
    neighbourhood; its match is taken at once, so the next vertices see it. A second pass (``passes=2``) sees
    every vertex. ``vertex`` is :func:`resample_grid`'s for this level; ``query_weights`` ``(N, D)`` the
    fall-off with the grid points off the surface set to 0.
    """
    n, j = vertex.shape
    channels = ex.colors.shape[1]
    order = np.argsort(sweep, kind="stable")
    sources = sources.copy()
    colors = ex.colors[sources]
    d2 = np.zeros(n)
    done = np.zeros(n, dtype=bool)
    for _ in range(passes):
        for v in order:
            weights = query_weights[v].copy()
            # the visited grid points only (the centre reads the vertex itself, not visited yet)
            weights[: j * channels] *= np.repeat(done[vertex[v]], channels)
            done[v] = True
            if not weights.any():  # nothing visited around it yet (the coarsest level's first vertices)
                continue           # it keeps its start, as Wei & Levoy's first pixels keep their noise
            vector = colors[vertex[v]].ravel()
            if fixed_part is not None:
                vector = np.concatenate([vector, fixed_part[v]])
            found, dist = search(np.array([v]), vector[None], weights[None], sources, rng)
            sources[v], d2[v] = found[0], dist[0]
            colors[v] = ex.colors[found[0]]
        bar.advance({"level": level})
    return sources, d2


def match_level(frame, ex, here, fixed_part, query_weights, sources, search, passes, subpasses, rng, bar, level, *,
                guide=None):
    """``passes`` parallel passes over a level, each in ``subpasses`` random groups of vertices.

    Every vertex of a group is matched at once from the current colours; the groups take turns, so a vertex
    sees its neighbours' updates of the same pass (the subpasses of Lefebvre & Hoppe 2005, which keep parallel
    matching from oscillating). Returns the sources and each vertex's last squared distance.

    ``guide`` ``(N, G)``, optional: per-vertex values that stand for the last ``G`` channels of the exemplar's
    colours in every query (channels that are given, not synthesised: a target the match must follow, as the
    transition function and the synthesised texton mask of :mod:`texsynth.surface._progressive_surface`).
    """
    n = len(frame.points)
    j = here.shape[0] // n
    groups = np.array_split(rng.permutation(n), min(subpasses, n))
    rows = [here[(g[:, None] * j + np.arange(j)).ravel()] for g in groups]
    sources = sources.copy()
    d2 = np.zeros(n)
    for _ in range(passes):
        for g, resample in zip(groups, rows):
            values = ex.colors[sources]
            if guide is not None:
                values = np.concatenate([values[:, :values.shape[1] - guide.shape[1]], guide], axis=1)
            vectors = (resample @ values).reshape(len(g), -1)
            if fixed_part is not None:
                vectors = np.concatenate([vectors, fixed_part[g]], axis=1)
            weights = ex.weights if query_weights is None else query_weights[g]
            sources[g], d2[g] = search(g, vectors, weights, sources, rng)
        bar.advance({"level": level})
    return sources, d2


class GlobalSearch:
    """Every exemplar neighbourhood is a candidate (:class:`~texsynth.core.search.PatchIndex`)."""

    def __init__(self, ex, method, queries, rng):
        self.ex = ex
        self.index = PatchIndex(ex.vectors, weights=ex.weights, method=method, queries=queries, rng=rng)
        self.method = self.index.method
        self.mean = ex.vectors.mean(axis=0)

    def __call__(self, group, vectors, weights, sources, rng):
        if weights.ndim == 2:  # grid points off an open surface: the mean vector there (a neutral value)
            vectors = np.where(weights > 0, vectors, self.mean)
        idx, d2 = self.index.query(vectors, k=1)
        return idx[:, 0], d2[:, 0]


class _Causal:
    """Every exemplar neighbourhood a candidate of one query at a time, over the grid points it knows.

    The sweep's queries count a grid point only if its vertex is visited, which differs from vertex to
    vertex: the masked exact search of the search layer (:class:`~texsynth.core.search.MaskedIndex`, one
    product with the exemplar's stacked vectors per query).
    """

    method = "exact"

    def __init__(self, ex):
        self.index = MaskedIndex(ex.vectors, weights=ex.weights)

    def __call__(self, group, vectors, weights, sources, rng):
        idx, d2, _, _ = self.index.near_best(vectors, weights > 0, 0.0, np.zeros(len(group)))
        return idx, d2


class CoherentSearch:
    """k-coherent candidates of every vertex of a level (:class:`~texsynth.core.search.KCoherence`)."""

    def __init__(self, frame, ex, k, method, predicted, rng):
        self.ex = ex
        self.kc = KCoherence(ex.vectors if k > 1 else None, ex.shape, k, weights=ex.weights, method=method, rng=rng)
        self.method = self.kc.method or "exact"
        _, self.near = frame.tree.query(frame.points, k=min(_COHERENT_NEIGHBORS + 1, len(frame.points)))
        # (N, J, 2) flattened offsets of the nearest vertices, in pixels; column 0 is the vertex itself
        self.offsets = np.rint(frame.flatten(np.arange(len(frame.points)), frame.points[self.near])).astype(np.int64)
        self.predicted = predicted

    def __call__(self, group, vectors, weights, sources, rng):
        cand = self.kc.candidates(sources[self.near[group]], self.offsets[group], rng=rng)
        cand = np.concatenate([cand, self.kc.sets[self.predicted[group]]], axis=1)
        choice, d2 = nearest_candidates(vectors, cand, vectors=self.ex.vectors, weights=weights)
        return cand[np.arange(len(cand)), choice], d2
