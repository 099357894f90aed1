"""Progressively-variant textures on surfaces (Zhang, Zhou, Velho, Guo & Shum 2003).

Zhang et al. [1]_ describe a progressively-variant texture as the tuple
``(T, M, F, V)``: the texture ``T``, its **texton mask** ``M`` (which pixels
belong to a texture element), a **transition function** ``F`` (how far the
texture has gone from one kind to another) and an **orientation field**
``V``. On a surface the user gives ``F`` per vertex (here ``blend``: 0 shows
``exemplar``, 1 ``exemplar_b``) and ``V`` (a tangent field); the method:

1. **A 2-D progressively-variant sample from two exemplars** by feature-based
   warping and blending of their elements
   (:func:`texsynth.core.textons.progressive_sample`): a strip of a few
   exemplar widths across which ``F`` runs from 0 to 1; at ``F`` every
   element of ``exemplar`` has moved a share ``F`` of the way towards its
   partner element of ``exemplar_b`` (and that one a share ``1 - F`` back),
   and the two are cross-dissolved, so in-between elements appear. The
   sample carries its own ``T``, ``M`` (the warped and blended masks) and
   ``F`` (the column's value).
2. **The texton mask first**: a vertex synthesis on the retiled mesh
   hierarchy along ``V`` (the pieces of
   :func:`~texsynth.surface.synthesize_surface`: multi-resolution surface
   neighbourhoods, global search at the coarsest level, k-coherent
   candidates below) of the sample's ``(M, F)``, in which the ``F`` channel
   of every query is not synthesised but the vertex's own target: the
   distance is ``|M(p) - M(x)|^2 + w_F |F(p) - F_o(x)|^2`` summed over the
   neighbourhood, so each vertex copies the part of the sample whose
   ``F`` matches its own.
3. **Then the texture with the mask in the distance**: the same synthesis
   of ``(T, M, F)``, whose queries hold the synthesised colours, the mask
   of step 2 and the target ``F``: ``|T(p) - T(x)|^2 + w_M |M(p) - M(x)|^2 +
   w_F |F(p) - F_o(x)|^2``, so the colours follow the elements laid out in
   step 2 and the elements are not cut.

What could not be checked: the paper was not at hand; this follows its
published description (abstract; the issue's summary) and the lecture
slides that show its results. Not from the paper (this implementation's
reading): the automatic texton masks (:func:`~texsynth.find_textons`,
Otsu), the features of the warping (the masks' connected components,
matched by nearest centroid: the paper's user-marked features and its
exact warp could not be checked), the sample's width (four exemplar
widths), the weights' defaults (``w_M = 1``, ``w_F = 4``), the global
search at the coarsest level only, and the independent (parallel) order of
:func:`~texsynth.surface.synthesize_surface` in place of the paper's
sequential vertex order. The paper's local size control (a scale field on
the surface) is not implemented.

References
----------
.. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
   progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
   (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np

from ..core._progress import Progress
from ..core._validate import as_array, as_image, as_rng, check_memory, check_positive_float, with_channels
from ..core.pyramid import gaussian_pyramid
from ..core.search import Search, point_tree
from ..core.textons import find_textons, progressive_sample
from ._field import check_field
from ._meshio import as_mesh
from ._retile import mesh_hierarchy, resolve_count
from ._vertex_synthesis import SurfaceSchedule, guided_levels, guided_options, level_frames

__all__ = ["progressive_surface", "ProgressiveSurfaceInfo"]

_SAMPLE_WIDTHS = 4  # the progressively-variant sample is this many exemplar widths wide


@dataclass
class ProgressiveSurfaceInfo:
    """Extra results of :func:`progressive_surface`.

    Attributes
    ----------
    levels : list of Mesh
        The mesh hierarchy, finest first, each coloured by its level's result.
    field : numpy.ndarray
        ``(N, 3)`` the tangent vector ``V`` at each output vertex.
    blend : numpy.ndarray
        ``(N,)`` the transition function ``F`` at each output vertex.
    texton_mask : numpy.ndarray or None
        ``(N,)`` bool, the texton mask synthesised first (step 2; None
        without texton masks).
    sources : numpy.ndarray of int
        ``(N, 2)`` the pixel ``(row, col)`` of :attr:`sample` each output
        vertex copies.
    sample, sample_mask, sample_blend : numpy.ndarray
        The 2-D progressively-variant sample ``(T, M, F)`` of step 1:
        ``(h, w, C)``, ``(h, w)`` bool and ``(h, w)``.
    energy : list of float
        Per synthesis and level, coarsest first (the mask's levels, then the
        texture's): the mean weighted squared distance of the matches.
    pixel_size : float
        The length on the surface of one sample pixel.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"sample"``, ``"hierarchy"``, ``"field"`` and each
        ``"mask level l"`` and ``"texture level l"``.
    """

    levels: list = dataclass_field(default_factory=list)
    field: np.ndarray | None = None
    blend: np.ndarray | None = None
    texton_mask: np.ndarray | None = None
    sources: np.ndarray | None = None
    sample: np.ndarray | None = None
    sample_mask: np.ndarray | None = None
    sample_blend: np.ndarray | None = None
    energy: list = dataclass_field(default_factory=list)
    pixel_size: float = 0.0
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


def _texton_masks(texton_mask, images):
    """The two exemplars' binary texton masks (None: no masks)."""
    if texton_mask is None:
        return None
    if isinstance(texton_mask, str):
        if texton_mask != "auto":
            raise ValueError(f"texton_mask must be 'auto', None or a pair (mask, mask_b), got {texton_mask!r}")
        return [find_textons(img) for img in images]
    if not isinstance(texton_mask, (tuple, list)) or len(texton_mask) != 2:
        raise ValueError("texton_mask must be 'auto', None or a pair (mask, mask_b) of the exemplars' sizes")
    masks = []
    for value, img, name in zip(texton_mask, images, ("texton_mask[0]", "texton_mask[1]")):
        arr = as_array(value, name)
        if arr.shape != img.shape[:2]:
            raise ValueError(f"{name} must have its exemplar's size {img.shape[:2]}, got shape {arr.shape}; pass "
                             "a mask per exemplar or texton_mask='auto'")
        if not np.isfinite(arr.astype(np.float64)).all():
            raise ValueError(f"{name} has NaN or infinite values; pass a mask of 0/1 or bool")
        masks.append(arr.astype(np.float64) > 0.5)
    return masks


def _blend_at(blend, points, tree):
    """``F`` at ``points``: ``blend`` per input vertex (carried by the nearest one) or a callable of positions."""
    if callable(blend):
        values = as_array(blend(points.copy()), "blend(points)").astype(np.float64)
        name = "blend(points)"
        if values.shape != (len(points),):
            raise ValueError(f"blend(points) must return one value per point, shape ({len(points)},), got shape "
                             f"{values.shape}")
    else:
        values, name = blend[tree.query(points)[1]], "blend"
    if not np.isfinite(values).all() or values.min() < 0 or values.max() > 1:
        raise ValueError(f"{name} must lie in [0, 1] (0: exemplar, 1: exemplar_b), got values in "
                         f"[{np.nanmin(values):.4g}, {np.nanmax(values):.4g}]")
    return values


def _check_blend(blend, mesh):
    if callable(blend):
        return blend
    values = as_array(blend, "blend")
    if values.ndim != 1 or len(values) != len(mesh.vertices):
        raise ValueError(f"blend must give one value per mesh vertex, shape ({len(mesh.vertices)},), or be a "
                         f"callable of positions (P, 3) -> (P,); got shape {values.shape}")
    return values.astype(np.float64)


def progressive_surface(
    mesh,
    exemplar,
    exemplar_b,
    blend,
    *,
    texton_mask="auto",
    texton_weight=1.0,
    blend_weight=4.0,
    n_vertices=None,
    field="smooth",
    schedule=SurfaceSchedule(),
    search=Search(candidates="auto"),
    rng=None,
    progress=False,
    return_info=False,
):
    """Synthesise a progressively-variant texture over a surface (Zhang et al. 2003).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> from texsynth.surface import progressive_surface
    >>> ball = texsynth.surface.sphere(3)
    >>> a, b = texsynth.data.load("bread")[:40, :40], texsynth.data.load("brick")[:40, :40]
    >>> out = progressive_surface(ball, a, b, lambda p: (p[:, 2] + 1) / 2, n_vertices=700, rng=0,
    ...                           schedule=texsynth.SurfaceSchedule(levels=2, neighborhood_size=5, parent_size=3))
    >>> out.colors.shape[1]
    3

    The texture changes from ``exemplar`` where ``blend`` is 0 to
    ``exemplar_b`` where it is 1 through in-between elements made by
    feature-based warping and blending; a texton mask is synthesised first
    and the texture then follows it, so elements stay whole [1]_ (module
    notes: the steps, and what could not be checked).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    exemplar, exemplar_b : array_like
        ``(h, w)`` or ``(h, w, C)`` textures with the same channels, shown
        where ``blend`` is 0 and 1; both are cut to their common size.
    blend : array_like (N,) or callable
        The transition function ``F``: a value in [0, 1] per mesh vertex, or
        a callable of positions ``(P, 3) -> (P,)``.
    texton_mask : "auto", (array_like, array_like) or None
        The two exemplars' texton masks (each of its exemplar's size, True
        or > 0.5 on the elements). ``"auto"``: :func:`~texsynth.find_textons`.
        None: no mask (the texture is synthesised with ``F`` alone).
    texton_weight : float
        ``w_M``, the weight of the mask against the colours in the
        texture's distance (default 1, as in
        :func:`~texsynth.synthesize_controlled`).
    blend_weight : float
        ``w_F``, the weight of the transition channel in both syntheses
        (default 4: with 1 the copies strayed from their ``F``; measured in
        ``docs/methods/progressive_surface.md``).
    n_vertices : int, optional
        Retile the surface to about this many vertices; None colours the
        mesh's own vertices.
    field : {"smooth", "random"}, array_like (N, 3) or callable
        The orientation field ``V`` (:func:`~texsynth.surface.tangent_field`).
    schedule : SurfaceSchedule
        Neighbourhood sizes, levels and passes as in
        :func:`~texsynth.synthesize_surface` (its ``"default"`` preset);
        ``order`` must be ``"independent"``.
    search : texsynth.core.search.Search
        ``k`` (default 2) and ``method`` of the k-coherent search below the
        coarsest level (``candidates`` must be ``"auto"`` or
        ``"k-coherent"``).
    rng, progress, return_info
        As in :func:`~texsynth.synthesize_surface`; the info is a
        :class:`ProgressiveSurfaceInfo`.

    Returns
    -------
    Mesh
        The (retiled) surface with per-vertex colours.
    info : ProgressiveSurfaceInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid mesh, exemplar, mask, ``blend`` (wrong length, values
        outside [0, 1]), field or option, exemplars with different channels,
        a neighbourhood larger than the sample's coarsest level, or a density
        needing more memory than is available.

    References
    ----------
    .. [1] J. Zhang, K. Zhou, L. Velho, B. Guo and H.-Y. Shum, "Synthesis of
       progressively-variant textures on arbitrary surfaces", ACM TOG 22(3)
       (SIGGRAPH 2003), pp. 295-302. :doi:`10.1145/882262.882344`
    """
    start = time.perf_counter()
    mesh = as_mesh(mesh)
    opts = guided_options(schedule, search, "progressive_surface", "the tangent field already orients the sample")
    size, psize, levels, passes = opts.size, opts.parent_size, opts.levels, opts.passes
    texton_weight = check_positive_float(texton_weight, "texton_weight", allow_zero=True, maximum=1e6)
    blend_weight = check_positive_float(blend_weight, "blend_weight", allow_zero=True, maximum=1e6)
    field = check_field(field, len(mesh.vertices), 1)
    blend = _check_blend(blend, mesh)
    rng = as_rng(rng)
    images = [with_channels(as_image(exemplar, "exemplar"))[0], with_channels(as_image(exemplar_b, "exemplar_b"))[0]]
    masks = _texton_masks(texton_mask, images)
    n = len(mesh.vertices) if n_vertices is None else resolve_count(mesh, n_vertices, None, "n_vertices")
    channels = images[0].shape[2] + 2
    per_vertex = (size[0] * size[1] + psize[0] * psize[1]) * (4 * 24 + 8 * channels) * 2
    check_memory(float(n) * per_vertex, n, "n_vertices", "the surface neighbourhoods")
    info = ProgressiveSurfaceInfo()

    # step 1: the 2-D progressively-variant sample (T, M, F)
    t0 = time.perf_counter()
    width = _SAMPLE_WIDTHS * min(images[0].shape[1], images[1].shape[1])
    sample_masks = masks if masks is not None else [np.zeros(img.shape[:2], bool) for img in images]
    sample, sample_mask, sample_blend = progressive_sample(images[0], images[1], sample_masks, width=width)
    coarsest = gaussian_pyramid(sample_blend, levels)[-1].shape
    need = (max(size[0], psize[0]), max(size[1], psize[1]))
    if coarsest[0] < need[0] or coarsest[1] < need[1]:
        raise ValueError(f"the exemplars' coarsest level (levels={levels}) is {coarsest[0]} pixels high, smaller "
                         f"than the {need[0]}x{need[1]} neighbourhood; pass fewer levels, a smaller "
                         "neighborhood_size or larger exemplars")
    info.stage_seconds["sample"] = time.perf_counter() - t0

    t0 = time.perf_counter()
    hierarchy = mesh_hierarchy(mesh, n, levels, finest=mesh if n_vertices is None else None, rng=rng)
    info.stage_seconds["hierarchy"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    frames, info.pixel_size = level_frames(mesh, hierarchy, field, 1, rng)
    tree = None if callable(blend) else point_tree(mesh.vertices)
    targets = [_blend_at(blend, m.vertices, tree) for m in hierarchy]
    info.stage_seconds["field"] = time.perf_counter() - t0

    wf = np.sqrt(blend_weight)
    with Progress(progress, levels * passes * (2 if masks is not None else 1), "Zhang et al.") as bar:
        guides = [wf * t[:, None] for t in targets]
        if masks is not None:
            # step 2: the texton mask, with F as the guide
            work = np.stack([sample_mask.astype(np.float64), wf * sample_blend], axis=-1)
            mask_values, _, energies = guided_levels(frames, gaussian_pyramid(work, levels), guides, opts, rng, bar,
                                                     info.stage_seconds, "mask level")
            info.energy.extend(energies)
            wm = np.sqrt(texton_weight)
            guides = [np.concatenate([wm * v[:, :1], g], axis=1) for v, g in zip(mask_values, guides)]
            info.texton_mask = mask_values[0][:, 0] > 0.5
            parts = [sample, wm * sample_mask[..., None], wf * sample_blend[..., None]]
        else:
            parts = [sample, wf * sample_blend[..., None]]
        # step 3: the texture, with the mask and F as guides
        values, sources, energies = guided_levels(frames, gaussian_pyramid(np.concatenate(parts, axis=-1), levels),
                                                  guides, opts, rng, bar, info.stage_seconds, "texture level")
        info.energy.extend(energies)
    color_count = images[0].shape[2]
    for level, m in enumerate(hierarchy):
        info.levels.append(m.with_colors(np.clip(values[level][:, :color_count], 0, 1)))
    out = hierarchy[0].with_colors(np.clip(sample[sources[:, 0], sources[:, 1]], 0, 1))
    info.levels[0] = out
    info.field, info.blend, info.sources = frames[0].t, targets[0], sources
    info.sample, info.sample_mask, info.sample_blend = sample, sample_mask, sample_blend
    info.seconds = time.perf_counter() - start
    return (out, info) if return_info else out
