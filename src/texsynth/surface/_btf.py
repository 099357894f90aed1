"""Synthesis of bidirectional texture functions on arbitrary surfaces (Tong et al. 2002).

A bidirectional texture function (BTF) sample is a stack of images of one
patch of surface under many light (and view) directions: the shading,
self-shadowing and occlusion of its mesostructure (stones, bumps, weave).
Tong et al. [1]_ cover a mesh with it in three steps, followed here:

1. **3-D textons** (Leung & Malik [2]_): the Leung-Malik filter-bank
   responses of all images, concatenated per pixel, clustered by k-means;
   every sample pixel is labelled with its texton, and neighbourhoods are
   compared through the textons' dot-product table
   (:func:`texsynth.core.btf.btf_textons`; here through the table's
   classical-scaling embedding, :func:`texsynth.core.btf.texton_image`).
2. **A surface texton map**: k-coherent vertex synthesis over the retiled
   mesh hierarchy, each vertex getting the sample pixel whose texton
   neighbourhood matches its own. This is
   :func:`~texsynth.synthesize_surface` (Turk 2001; Wei & Levoy 2001; with
   Tong et al.'s k-coherent candidates,
   :class:`texsynth.core.search.KCoherence`) run on the texton image, whose
   ``info.sources`` are the sample positions.
3. **Rendering**: for a light (and view) direction, each vertex expresses
   it in its local frame (the tangent field ``t``, ``b = n x t``, the normal
   ``n``: the sample's x, y and z axes) and looks the BTF up at its sample
   position under that local direction (:func:`render_btf_surface`,
   through :func:`texsynth.core.btf.sample_btf`).

What could not be checked: the paper was not at hand; this module follows
its published description (abstract and talk slides). The texton count (64)
and ``k`` (2) are this implementation's; the texton coordinates keep the 4
leading axes of the exact embedding (the vertex synthesis takes at most 4
channels; ``info.texton_share`` reports how much of the distances they
keep); Tong et al.'s own mesh hierarchy, neighbourhood resampling and
direction interpolation could not be compared.

References
----------
.. [1] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
   "Synthesis of bidirectional texture functions on arbitrary surfaces",
   SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
.. [2] T. Leung and J. Malik, "Representing and recognizing the visual
   appearance of materials using three-dimensional textons", IJCV 43(1),
   2001, pp. 29-44. :doi:`10.1023/A:1011126920638`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np

from ..core._validate import as_array, as_rng, check_memory, check_positive_int
from ..core.btf import BTF, Textons, as_btf, sample_btf, texton_image
from ..core.search import Search
from ._mesh import Mesh
from ._meshio import as_mesh
from ._vertex_synthesis import SurfaceSchedule, synthesize_surface

__all__ = ["synthesize_btf_surface", "render_btf_surface", "BTFSurface", "BTFSurfaceInfo"]

_BYTES_PER_VERTEX = 64   # sources, tangents and the rendered colours of one vertex (the synthesis checks its own)


@dataclass(frozen=True, eq=False)
class BTFSurface:
    """A surface covered by a BTF (:func:`synthesize_btf_surface`): where each vertex reads the sample.

    Attributes
    ----------
    mesh : Mesh
        The retiled surface, coloured by its texton coordinates (a preview).
    sources : numpy.ndarray of int64
        ``(N, 2)`` the sample pixel ``(row, col)`` of each vertex.
    tangents : numpy.ndarray
        ``(N, 3)`` unit tangents along which the sample's x axis runs
        (orthogonal to the vertex normals).
    btf : texsynth.core.btf.BTF
        The sample it reads.
    """

    mesh: Mesh
    sources: np.ndarray
    tangents: np.ndarray
    btf: BTF

    def __repr__(self):
        return f"BTFSurface({len(self.sources)} vertices, {self.btf!r})"


@dataclass
class BTFSurfaceInfo:
    """Extra results of :func:`synthesize_btf_surface`.

    Attributes
    ----------
    textons : texsynth.core.btf.Textons
        The sample's textons (labels and dot-product table).
    texton_image : numpy.ndarray
        ``(h, w, 4)`` the sample as texton coordinates: the exemplar of the
        vertex synthesis.
    texton_share : float
        The share of the textons' squared distances the 4 coordinates keep.
    synthesis : SurfaceSynthesisInfo
        The info of :func:`~texsynth.synthesize_surface`.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"textons"`` and ``"synthesis"``.
    """

    textons: Textons | None = None
    texton_image: np.ndarray | None = None
    texton_share: float = 1.0
    synthesis: object = None
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


def synthesize_btf_surface(
    mesh,
    btf,
    *,
    n_vertices=None,
    pixel_size=None,
    field="smooth",
    symmetry=1,
    textons="auto",
    n_textons=64,
    schedule=SurfaceSchedule(),
    search=Search(candidates="k-coherent", k=2),
    rng=None,
    progress=False,
    return_info=False,
):
    """Cover a surface with a BTF sample: a surface texton map of sample positions (Tong et al. 2002).

    Examples
    --------
    >>> import texsynth
    >>> from texsynth.surface import render_btf_surface, synthesize_btf_surface
    >>> sample = texsynth.data.btf("stones", 32, n_lights=8)
    >>> s = synthesize_btf_surface(texsynth.surface.sphere(3), sample, n_vertices=500, n_textons=8,
    ...                            schedule=texsynth.SurfaceSchedule(levels=2, neighborhood_size=5), rng=0)
    >>> lit = render_btf_surface(s, (0.3, 0.2, 1.0))
    >>> s.sources.shape == (len(lit.vertices), 2), lit.colors.shape[1]
    (True, 1)

    Steps 1 and 2 of the module notes: the sample's textons as an image of
    texton coordinates, synthesised over the retiled mesh hierarchy by
    :func:`~texsynth.synthesize_surface`, whose per-vertex sources become
    the sample positions. :func:`render_btf_surface` renders the result for
    any light and view (step 3).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    btf : texsynth.core.btf.BTF
        The sample (e.g. :func:`texsynth.data.btf`).
    n_vertices, pixel_size, field, symmetry, schedule
        As in :func:`~texsynth.synthesize_surface`: the density of the
        retiled surface (``n_vertices``, or ``pixel_size``: the length of
        one sample pixel), the tangent field along which the sample's x axis
        runs, its symmetry, and the levels and passes of the synthesis.
    textons : Textons or "auto"
        The sample's textons, if made before
        (:func:`texsynth.core.btf.btf_textons`); ``"auto"``: made here.
    n_textons : int
        With ``textons="auto"``: how many (default 64).
    search : Search
        The vertex synthesis's search (default ``candidates="k-coherent"``,
        ``k=2``: Tong et al.'s k-coherent search).
    rng : None, int or numpy.random.Generator
        Seeds k-means, the retiling, the field and the synthesis.
    progress : bool or callable
        True shows a tqdm bar; a callable receives ``(step, total, info)``.
    return_info : bool
        Also return a :class:`BTFSurfaceInfo`.

    Returns
    -------
    BTFSurface
        The retiled mesh with each vertex's sample position and tangent.
    info : BTFSurfaceInfo
        Only with ``return_info=True``.

    Raises
    ------
    TypeError, ValueError
        For a ``btf`` that is not a BTF, bad textons, or any error of
        :func:`~texsynth.synthesize_surface` (a density needing more memory
        than is available is refused before anything is allocated).

    References
    ----------
    .. [1] X. Tong, J. Zhang, L. Liu, X. Wang, B. Guo and H.-Y. Shum,
       "Synthesis of bidirectional texture functions on arbitrary surfaces",
       SIGGRAPH 2002, pp. 665-672. :doi:`10.1145/566654.566634`
    """
    start = time.perf_counter()
    btf = as_btf(btf)
    mesh = as_mesh(mesh)
    check_positive_int(n_textons, "n_textons", minimum=2)
    if n_vertices is not None:
        check_memory(_BYTES_PER_VERTEX * check_positive_int(n_vertices, "n_vertices"), n_vertices, "n_vertices",
                     "the surface's sample positions")
    rng = as_rng(rng)
    textons, image, share = texton_image(btf, textons, n_textons, rng=rng)
    stages = {"textons": time.perf_counter() - start}
    preview, synthesis = synthesize_surface(mesh, image, n_vertices=n_vertices, pixel_size=pixel_size, field=field,
                                            symmetry=symmetry, schedule=schedule, search=search, rng=rng,
                                            progress=progress, return_info=True)
    stages["synthesis"] = time.perf_counter() - start - stages["textons"]
    normals = preview.vertex_normals
    tangents = synthesis.field - np.einsum("nk,nk->n", synthesis.field, normals)[:, None] * normals
    tangents /= np.maximum(np.linalg.norm(tangents, axis=1, keepdims=True), 1e-12)
    surface = BTFSurface(preview, synthesis.sources.astype(np.int64), tangents, btf)
    if not return_info:
        return surface
    return surface, BTFSurfaceInfo(textons, image, share, synthesis, time.perf_counter() - start, stages)


def render_btf_surface(surface, light, *, view=None):
    """The surface under a light (and view) direction: each vertex reads the BTF in its own frame.

    Examples
    --------
    See :func:`synthesize_btf_surface`.

    A direction ``d`` given in the mesh's coordinates becomes, at a vertex
    with tangent ``t`` and normal ``n``, ``(d.t, d.b, d.n)`` with
    ``b = n x t``: the sample's frame (x along its columns, y up its rows,
    z out of it). The vertex takes the BTF's value at its sample position
    under that local direction (:func:`texsynth.core.btf.sample_btf`: the
    nearest measured directions, blended; 0 where the light is behind the
    surface).

    Parameters
    ----------
    surface : BTFSurface
        A result of :func:`synthesize_btf_surface`.
    light : array_like
        ``(3,)`` direction towards the light, in the mesh's coordinates.
    view : array_like, optional
        ``(3,)`` direction towards the viewer (a distant camera), in the
        mesh's coordinates; None: every vertex seen along its normal.

    Returns
    -------
    Mesh
        The surface with one grey colour per vertex (``colors`` ``(N, 1)``),
        for :func:`~texsynth.render_mesh` (with ``ambient=1`` to show the
        BTF's own shading alone).
    """
    if not isinstance(surface, BTFSurface):
        raise TypeError(f"surface must be a BTFSurface (the result of synthesize_btf_surface), got "
                        f"{type(surface).__name__}")
    mesh, t = surface.mesh, surface.tangents
    n = mesh.vertex_normals
    frame = np.stack([t, np.cross(n, t), n], axis=1)                 # (N, 3 axes, 3 coordinates)
    lights = frame @ _direction(light, "light")
    views = None if view is None else frame @ _direction(view, "view")
    values = sample_btf(surface.btf, surface.sources, lights, views)
    return mesh.with_colors(np.clip(values, 0.0, 1.0)[:, None])


def _direction(value, name):
    d = as_array(value, name).astype(np.float64)
    if d.shape != (3,) or not np.linalg.norm(d) > 0:
        raise ValueError(f"{name} must be one direction (x, y, z) of nonzero length, got {value!r}")
    return d / np.linalg.norm(d)
