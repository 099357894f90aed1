"""Mesh quilting: a swatch of separate geometry elements quilted over a surface (Zhou et al. 2006).

Zhou, Huang, Wang, Tong, Desbrun, Guo and Shum cover a base surface with the geometric details of a
*swatch*, a slab of 3-D elements over a plane, inside a thin *shell* above the surface. The swatch is
quilted over the shell patch after patch: each new patch is placed where its elements continue the
ones already there (*geometry matching*), the old and the new elements in the overlap are paired and
each place keeps whole elements of one side only (*element correspondence*), and the elements are
mapped into the shell, following the surface (*local deformation*), and joined into one mesh
(*merging*). This module reads in that order:

- the swatch: a triangle mesh whose connected components are the elements, standing on the plane
  ``z = 0`` of its own coordinates ``(u, v, h)`` (:func:`texsynth.data.swatch` makes some); each
  element is described by its centre ``(u, v)``, the centre of its box in the plane;
- the shell: the surface's points ``S(x) + h n(x)``, ``0 <= h <= thickness``, with ``n`` the
  interpolated (area-weighted) vertex normal at the closest surface point ``S(x)``;
- the patches: discs of radius ``patch_radius`` (swatch units) centred on surface vertices, visited
  in the order in which they grow from a random seed (the next centre is the not yet covered vertex
  nearest the seed along the mesh's edges, Dijkstra), until every vertex lies within
  ``0.7 * patch_radius`` of a centre; each has a tangent frame ``(t1, t2, n)`` whose ``t1`` is the
  projection of a fixed axis (x, or y near the x poles);
- geometry matching: the placed elements near a patch are expressed in its tangent frame; for every
  candidate swatch offset ``o`` (a grid over the swatch, ``candidate_step`` apart, the disc inside
  the swatch) the element-set distance of the overlap is
  ``E(o) = sum_old min(d_old^2, tau^2) + sum_new [d_new < 1.5 s] min(d_new^2, tau^2)``, with ``d_old``
  each placed element's distance to the nearest swatch element centre shifted by ``o``, ``d_new``
  each swatch element of the disc's distance to the nearest placed one, ``s`` the swatch's median
  nearest-neighbour spacing and ``tau = s / 2`` (the pairs are found by
  :func:`texsynth.core.search.point_tree`); one offset is drawn among those within
  ``(1 + error_tolerance)`` of the best (:func:`texsynth.core.search.within_tolerance`, quilting's
  rule); the first patch takes a random offset;
- element correspondence: a new element whose centre, mapped onto the surface, lies nearer a placed
  one's than the swatch's two closest element centres lie to each other takes the same place as that
  one, and the placed one is kept (the cut runs along the placed elements' boundary: the
  old patch keeps the whole overlap it already holds, the new patch adds the elements beyond it);
- local deformation, in two steps: each kept element's centre ``(u, v)`` is mapped to the surface by
  the patch's map (the tangent-plane point ``c + r (cos a t1 + sin a t2)``, ``r`` and ``a`` the polar
  coordinates about the patch centre times ``unit_length``, projected to the surface, its radius corrected
  once so that the chord from the centre to the projection has length ``r``, a chordal approximation
  of the exponential map, and projected again); then every vertex ``(u, v, h)`` of the element is
  mapped on its own by the same construction about the element's centre, in the tangent plane there
  (``t1`` carried over by projection), and lifted by ``h * thickness / swatch height`` along the
  interpolated normal, so the element bends with the surface under it;
- merging: a mapped element whose bounding sphere meets a placed element's is tested for an
  intersection (every edge of each against every triangle of the other, Möller and Trumbore's
  segment-triangle test, and one vertex of each inside the other by its winding number); an element
  that meets one is dropped; the kept elements are joined into one mesh.

What is simplified (the paper's text was not at hand; this follows its published description, the
abstract and summaries of it, and the brief of issue 37): the paper parameterises the shell with a
low-distortion parameterisation of the whole surface and deforms elements to fit it; here each patch
places element centres through its own tangent plane with the chordal correction above, and each
element is bent through the tangent plane at its centre, so placement is only as faithful as the
surface is flat over ``patch_radius * unit_length`` (the radial error of the chordal map is about
``(r / R)^2 / 24`` on a sphere of radius ``R``; in a crease of a bumpy surface the closest-point projection
can fold, and an element whose faces it shrinks is dropped, ``info.n_folded``); the paper's cut
through the overlap and its deformation of matched elements towards each other are replaced by
keeping the placed element of a pair and dropping colliding ones; the paper's matching also compares
the elements' shapes, which here enter only through the element-set distance of their centres; the
paper's rotation of patches by a vector field is a fixed projected axis. The paper's equation
numbers are not quoted, and its timings and defaults could not be compared.

References
----------
.. [1] K. Zhou, X. Huang, X. Wang, Y. Tong, M. Desbrun, B. Guo and H.-Y. Shum, "Mesh quilting for
   geometric texture synthesis", ACM SIGGRAPH 2006, doi:10.1145/1141911.1141921.
.. [2] A. A. Efros and W. T. Freeman, "Image quilting for texture synthesis and transfer",
   SIGGRAPH 2001, doi:10.1145/383259.383296.
.. [3] T. Möller and B. Trumbore, "Fast, minimum storage ray-triangle intersection", Journal of
   Graphics Tools 2(1), 1997 (the DOI 10.1080/10867651.1997.10487468 is quoted from memory).
"""

from __future__ import annotations

import dataclasses
import time

import numpy as np
from scipy import sparse
from scipy.sparse import csgraph

from ..core._progress import Progress
from ..core._validate import as_rng, check_bool, check_choice, check_memory, check_positive_float, is_auto
from ..core.search import lowest_cost, point_tree, within_tolerance
from ..core.triangles import closest_on_triangles

__all__ = ["mesh_quilting", "MeshQuiltingInfo", "QUILT_PLACEMENTS"]

#: ``placement``: matched offsets (the paper) or random ones (the baseline).
QUILT_PLACEMENTS = ("matched", "random")
#: Patch centres cover every vertex within this share of ``patch_radius``.
COVER = 0.7
#: A mapped element with a face shrunk below this share of its swatch area (folded by the local map) is dropped.
MIN_AREA_RATIO = 0.2
#: Surface vertices whose faces are tried when a point is projected to the surface.
NEAREST_VERTICES = 4


@dataclasses.dataclass(frozen=True)
class MeshQuiltingInfo:
    """What :func:`mesh_quilting` chose.

    Attributes
    ----------
    patch_centers : numpy.ndarray
        ``(P, 3)`` the patch centres on the surface, in placement order.
    offsets : numpy.ndarray
        ``(P, 2)`` the swatch point ``(u, v)`` placed at each centre.
    costs : numpy.ndarray
        ``(P,)`` the chosen offset's element-set distance ``E(o)`` (also with ``placement="random"``;
        0 for a patch with no placed element near it).
    element_sources : numpy.ndarray
        ``(E,)`` int, the swatch element of each output element.
    element_patches : numpy.ndarray
        ``(E,)`` int, the patch that placed it.
    element_centers : numpy.ndarray
        ``(E,3)`` each element's centre mapped onto the surface (``h = 0``).
    face_elements : numpy.ndarray
        ``(M,)`` int, the output element of each output face.
    n_duplicates, n_collisions, n_folded : int
        New elements dropped: as the same element as a placed one (correspondence), for meeting a placed
        one (merging), and for a face the local map shrank below :data:`MIN_AREA_RATIO` of its area.
    unit_length, thickness, patch_radius : float
        The values used (``thickness`` in surface units, ``patch_radius`` in swatch units).
    seconds : float
        Total wall time.
    """

    patch_centers: np.ndarray
    offsets: np.ndarray
    costs: np.ndarray
    element_sources: np.ndarray
    element_patches: np.ndarray
    element_centers: np.ndarray
    face_elements: np.ndarray
    n_duplicates: int
    n_collisions: int
    n_folded: int
    unit_length: float
    thickness: float
    patch_radius: float
    seconds: float


# --------------------------------------------------------------------------
# Inputs: the swatch's elements and the surface


def _as_triangles(value, name):
    """``(vertices, faces)`` from a pair or any object with ``vertices`` and ``faces`` (a surface ``Mesh``)."""
    if hasattr(value, "vertices") and hasattr(value, "faces"):
        value = (value.vertices, value.faces)
    if not (isinstance(value, (tuple, list)) and len(value) == 2):
        raise TypeError(f"{name} must be a (vertices, faces) pair or a mesh with .vertices and .faces, "
                        f"got {type(value).__name__}")
    vertices, faces = np.asarray(value[0]), np.asarray(value[1])
    if vertices.ndim != 2 or vertices.shape[1] != 3 or len(vertices) == 0:
        raise ValueError(f"{name}'s vertices must be an (N, 3) array of points, got shape {vertices.shape}")
    if not (np.issubdtype(vertices.dtype, np.floating) or np.issubdtype(vertices.dtype, np.integer)):
        raise TypeError(f"{name}'s vertices must be real numbers, got dtype {vertices.dtype}")
    vertices = vertices.astype(np.float64)
    if not np.all(np.isfinite(vertices)):
        raise ValueError(f"{name}'s vertices contain NaN or infinite values")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0 or not np.issubdtype(faces.dtype, np.integer):
        raise ValueError(f"{name}'s faces must be an (M, 3) integer array of vertex indices, got shape "
                         f"{faces.shape} and dtype {faces.dtype}")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise ValueError(f"{name}'s faces index vertices 0..{len(vertices) - 1}, got indices "
                         f"{int(faces.min())}..{int(faces.max())}")
    return vertices, faces.astype(np.int64)


def _components(n_vertices, faces):
    """Connected component of every vertex (the swatch's elements)."""
    edges = np.concatenate([faces[:, [0, 1]], faces[:, [1, 2]]])
    graph = sparse.coo_matrix((np.ones(len(edges)), (edges[:, 0], edges[:, 1])), shape=(n_vertices,) * 2)
    return csgraph.connected_components(graph, directed=False)[1]


@dataclasses.dataclass(frozen=True)
class _Swatch:
    vertices: list  # per element, (n_i, 3) (u, v, h)
    faces: list  # per element, (m_i, 3) indices into its vertices
    centers: np.ndarray  # (K, 2)
    spacing: float  # median nearest-neighbour distance of the centres
    closest: float  # the smallest distance between two centres
    areas: list  # per element, its faces' areas
    low: np.ndarray  # (2,) the swatch's corner
    high: np.ndarray  # (2,)
    height: float


def _swatch(swatch):
    vertices, faces = _as_triangles(swatch, "swatch")
    if vertices[:, 2].min() < -1e-9 * max(1.0, float(np.abs(vertices).max())):
        raise ValueError(f"swatch's elements must stand on the plane z = 0 (every z >= 0), got z down to "
                         f"{float(vertices[:, 2].min()):.4g}; shift them up")
    edges = np.sort(np.r_[faces[:, [0, 1]], faces[:, [1, 2]], faces[:, [2, 0]]], axis=1)
    if np.any(np.unique(edges, axis=0, return_counts=True)[1] != 2):
        raise ValueError("swatch's elements must be closed meshes (every edge shared by two faces): the intersection "
                         "tests count what lies inside an element; close them (cap their bottoms)")
    label = _components(len(vertices), faces)[faces[:, 0]]
    order = np.argsort(label, kind="stable")
    bounds = np.searchsorted(label[order], np.arange(label.max() + 2))
    els_v, els_f, centers = [], [], []
    for k in range(len(bounds) - 1):  # per element: its own vertices, re-indexed
        f = faces[order[bounds[k]:bounds[k + 1]]]
        if len(f) == 0:
            continue
        used, local = np.unique(f, return_inverse=True)
        v = vertices[used]
        els_v.append(v)
        els_f.append(local.reshape(-1, 3))
        centers.append(0.5 * (v[:, :2].min(0) + v[:, :2].max(0)))
    if len(centers) < 3:
        raise ValueError(f"swatch must hold at least 3 separate elements (connected components), got {len(centers)}")
    centers = np.array(centers)
    nearest = point_tree(centers).query(centers, k=2)[0][:, 1]
    areas = [_areas(v, f) for v, f in zip(els_v, els_f)]
    height = float(vertices[:, 2].max())
    if height <= 0:
        raise ValueError("swatch's elements are flat (every z is 0); they need a height above the plane")
    return _Swatch(els_v, els_f, centers, float(np.median(nearest)), float(nearest.min()), areas,
                   centers.min(0), centers.max(0), height)


def _areas(vertices, faces):
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    return 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1)


@dataclasses.dataclass(frozen=True)
class _Surface:
    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray  # per vertex, area-weighted, unit
    incident: np.ndarray  # (N, max valence) faces of each vertex, -1 padded
    tree: object  # point_tree of the vertices


def _surface(surface):
    vertices, faces = _as_triangles(surface, "surface")
    a, b, c = (vertices[faces[:, i]] for i in range(3))
    cross = np.cross(b - a, c - a)  # |cross| = 2 area: the area-weighted face normal
    if np.any(np.linalg.norm(cross, axis=1) <= 1e-14 * max(1.0, float(np.abs(vertices).max())) ** 2):
        raise ValueError("surface has zero-area faces; remove them (texsynth.surface.as_mesh names them)")
    normals = np.zeros_like(vertices)
    for i in range(3):
        np.add.at(normals, faces[:, i], cross)
    length = np.linalg.norm(normals, axis=1)
    if np.any(length == 0):
        raise ValueError("surface has vertices no face uses; remove them (texsynth.surface.as_mesh names them)")
    owner = faces.ravel()
    order = np.argsort(owner, kind="stable")
    counts = np.bincount(owner, minlength=len(vertices))
    slot = np.arange(len(owner)) - np.repeat(np.cumsum(counts) - counts, counts)
    incident = np.full((len(vertices), int(counts.max())), -1, np.int64)
    incident[owner[order], slot] = order // 3
    return _Surface(vertices, faces, normals / length[:, None], incident, point_tree(vertices))


# --------------------------------------------------------------------------
# The shell: closest points on the surface and the normal there


def _project(surf, points):
    """The closest surface points of ``points`` (the faces around their nearest vertices) and the normals there."""
    k = min(NEAREST_VERTICES, len(surf.vertices))
    near = surf.tree.query(points, k=k)[1].reshape(len(points), k)
    tri = surf.incident[near].reshape(len(points), k * surf.incident.shape[1])  # candidate faces, -1 padded
    corners = surf.vertices[surf.faces[np.maximum(tri, 0)]]  # (P, C, 3, 3)
    closest, bary = closest_on_triangles(points[:, None], corners[..., 0, :], corners[..., 1, :], corners[..., 2, :])
    d2 = np.where(tri >= 0, np.sum((closest - points[:, None]) ** 2, -1), np.inf)
    choice = lowest_cost(d2)[0]  # the nearest candidate face
    rows = np.arange(len(points))
    face = tri[rows, choice]
    normal = np.einsum("pi,pij->pj", bary[rows, choice], surf.normals[surf.faces[face]])
    return closest[rows, choice], normal / np.linalg.norm(normal, axis=1, keepdims=True)


def _frame(normal):
    axis = np.array([1.0, 0.0, 0.0]) if abs(normal[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    t1 = axis - normal * (axis @ normal)
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(normal, t1)


def _to_shell(surf, center, t1, t2, uv, h):
    """Tangent-plane coordinates ``uv`` (surface units) about ``center`` (frames ``t1``, ``t2``: one, or one per
    point) and heights ``h`` -> points in the shell, their feet on the surface and the normals there."""
    r = np.hypot(uv[:, 0], uv[:, 1])
    plane = center + uv[:, :1] * t1 + uv[:, 1:] * t2
    foot, _ = _project(surf, plane)
    chord = np.linalg.norm(foot - center, axis=-1)
    stretch = np.where(chord > 1e-12 * (1 + r), r / np.maximum(chord, 1e-300), 1.0)  # chord length = r
    foot, normal = _project(surf, center + stretch[:, None] * (plane - center))
    return foot + h[:, None] * normal, foot, normal


def _deform(surf, sw, take, feet, up, t1, unit_length, h_scale):
    """Local deformation: the vertices of swatch elements ``take`` about their centres' ``feet`` (normals ``up``)
    on the surface, each through the tangent plane at its element's foot (``t1`` carried over by projection),
    and the elements' vertex counts."""
    e1 = t1 - up * (up @ t1)[:, None]
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    sizes = np.array([len(sw.vertices[e]) for e in take])
    uv = np.concatenate([sw.vertices[e][:, :2] - sw.centers[e] for e in take]) * unit_length
    h = np.concatenate([sw.vertices[e][:, 2] for e in take]) * h_scale
    per = np.repeat(np.arange(len(take)), sizes)
    return _to_shell(surf, feet[per], e1[per], np.cross(up, e1)[per], uv, h)[0], sizes


# --------------------------------------------------------------------------
# Patches: centres grown from a seed


def _patch_centers(surf, radius, rng):
    """Vertex indices of the patch centres, in the order they grow from a random seed vertex."""
    f = surf.faces
    edges = np.concatenate([f[:, [0, 1]], f[:, [1, 2]], f[:, [2, 0]]])
    length = np.linalg.norm(surf.vertices[edges[:, 0]] - surf.vertices[edges[:, 1]], axis=1)
    n = len(surf.vertices)
    graph = sparse.coo_matrix((length, (edges[:, 0], edges[:, 1])), shape=(n, n)).tocsr()
    seed = int(rng.integers(n))
    distance = csgraph.dijkstra(graph, directed=False, indices=seed)
    distance[~np.isfinite(distance)] = np.inf  # other components: reached after this one, by index
    order = np.lexsort((np.arange(n), distance))
    covered = np.zeros(n, bool)
    centers = []
    for v in order:  # sequential by nature: each centre covers a disc, the next is the first vertex left
        if covered[v]:
            continue
        centers.append(int(v))
        covered[surf.tree.query_ball_point(surf.vertices[v], COVER * radius)] = True
    return np.array(centers, np.int64)


# --------------------------------------------------------------------------
# Geometry matching: the element-set distance of the overlap for every candidate offset


def _match(sw, old_uv, offsets, radius):
    """``E(o)`` for every candidate offset (rows of ``offsets``), old elements at ``old_uv`` (swatch units)."""
    tau2 = (0.5 * sw.spacing) ** 2
    tree = point_tree(sw.centers)
    d_old = tree.query((old_uv[None] + offsets[:, None]).reshape(-1, 2))[0].reshape(len(offsets), -1)
    cost = np.minimum(d_old ** 2, tau2).sum(1)
    shifted = sw.centers[None] - offsets[:, None]  # (K, N, 2): the swatch's centres about the patch centre
    inside = np.hypot(shifted[..., 0], shifted[..., 1]) < radius
    d_new = point_tree(old_uv).query(shifted[inside])[0]
    per = np.where(d_new < 1.5 * sw.spacing, np.minimum(d_new ** 2, tau2), 0.0)
    cost += np.bincount(np.nonzero(inside)[0], weights=per, minlength=len(offsets))
    return cost


# --------------------------------------------------------------------------
# Merging: does a new element meet a placed one?


def _segments_cross(starts, ends, tri):
    """Whether any segment crosses any triangle (Möller-Trumbore), segments ``(S, 3)`` x triangles ``(T, 3, 3)``."""
    a, e1, e2 = tri[:, 0], tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0]
    d = (ends - starts)[:, None]
    pvec = np.cross(d, e2[None])
    det = np.einsum("sti,ti->st", pvec, e1)
    ok = np.abs(det) > 1e-14
    inv = 1.0 / np.where(ok, det, 1.0)
    tvec = starts[:, None] - a[None]
    u = np.einsum("sti,sti->st", tvec, pvec) * inv
    qvec = np.cross(tvec, e1[None])
    v = np.einsum("sti,sti->st", d, qvec) * inv
    t = np.einsum("ti,sti->st", e2, qvec) * inv
    return bool(np.any(ok & (u >= 0) & (v >= 0) & (u + v <= 1) & (t >= 0) & (t <= 1)))


def _winding(point, tri):
    """Generalised winding number of a closed triangle set about a point (van Oosterom and Strackee's solid angle)."""
    r = tri - point
    n = np.linalg.norm(r, axis=2)
    numer = np.einsum("ti,ti->t", r[:, 0], np.cross(r[:, 1], r[:, 2]))
    denom = (n[:, 0] * n[:, 1] * n[:, 2] + np.einsum("ti,ti->t", r[:, 0], r[:, 1]) * n[:, 2]
             + np.einsum("ti,ti->t", r[:, 1], r[:, 2]) * n[:, 0] + np.einsum("ti,ti->t", r[:, 2], r[:, 0]) * n[:, 1])
    return float(np.arctan2(numer, denom).sum() / (2 * np.pi))


def _meets(v_new, f_new, v_old, f_old):
    """Whether two closed elements intersect: an edge of one crosses a face of the other, or one holds the other."""
    tri_new, tri_old = v_new[f_new], v_old[f_old]
    edges_new = np.unique(np.sort(f_new[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), 1), axis=0)
    edges_old = np.unique(np.sort(f_old[:, [0, 1, 1, 2, 2, 0]].reshape(-1, 2), 1), axis=0)
    return (_segments_cross(v_new[edges_new[:, 0]], v_new[edges_new[:, 1]], tri_old)
            or _segments_cross(v_old[edges_old[:, 0]], v_old[edges_old[:, 1]], tri_new)
            or abs(_winding(v_new[0], tri_old)) > 0.5 or abs(_winding(v_old[0], tri_new)) > 0.5)


# --------------------------------------------------------------------------
# Mesh quilting


def mesh_quilting(swatch, surface, *, unit_length=1.0, thickness="auto", patch_radius="auto", candidate_step="auto",
                  error_tolerance=0.1, placement="matched", rng=None, return_info=False, progress=False):
    """Quilt a swatch of separate elements over a surface, inside a thin shell (Zhou et al. 2006).

    Examples
    --------
    >>> from texsynth.data import swatch
    >>> from texsynth.geometry import mesh_quilting
    >>> x, y = np.meshgrid(np.linspace(0, 6, 13), np.linspace(0, 6, 13))
    >>> plane = np.c_[x.ravel(), y.ravel(), np.zeros(x.size)]
    >>> q = np.arange(169).reshape(13, 13)[:-1, :-1].ravel()
    >>> faces = np.r_[np.c_[q, q + 1, q + 14], np.c_[q, q + 14, q + 13]]
    >>> vertices, out_faces, info = mesh_quilting(swatch("rivets", 8.0), (plane, faces), unit_length=0.5, rng=0,
    ...                                           return_info=True)
    >>> len(info.element_sources) > 10, bool(vertices[:, 2].min() >= 0 and vertices[:, 2].max() <= info.thickness)
    (True, True)

    Parameters
    ----------
    swatch : (vertices, faces) or mesh
        The swatch: a triangle mesh whose connected components are the elements (closed, at least 3),
        in its own coordinates ``(u, v, h)``, standing on ``h = 0`` (every ``h >= 0``);
        :func:`texsynth.data.swatch` makes some. A ``texsynth.surface.Mesh`` is taken too.
    surface : (vertices, faces) or mesh
        The base surface, a triangle mesh (``texsynth.surface.sphere``, ``bumpy``, ``torus``, a
        plane, or a ``Mesh``); its normals point to the side the shell grows on (outwards for the
        counter-clockwise faces of a closed mesh).
    unit_length : float
        Surface length of one swatch unit (the swatch's elements are ``unit_length`` times their swatch size).
        About ``sqrt(n_swatch * area / (n * swatch_area))`` gives ``n`` elements over a surface of
        ``area`` from ``n_swatch`` elements over ``swatch_area``.
    thickness : float or "auto"
        The shell's thickness in surface units: the swatch's heights are scaled so its highest point
        reaches it. ``"auto"``: ``unit_length`` times the swatch's height (no vertical change).
    patch_radius : float or "auto"
        Radius of a patch in swatch units. ``"auto"``: a quarter of the extent of the swatch's element
        centres (the disc must fit inside it, with room for candidate offsets).
    candidate_step : float or "auto"
        Step in swatch units between the candidate offsets tried. ``"auto"``: a fifth of the swatch's
        median element spacing.
    error_tolerance : float
        An offset is drawn among those whose element-set distance is within ``(1 + error_tolerance)``
        of the best (quilting's 0.1).
    placement : {"matched", "random"}
        ``"matched"``: the offsets by geometry matching (the paper); ``"random"``: uniform random
        offsets with the same correspondence and merging (a baseline).
    rng : None, int or numpy.random.Generator
        Seed of the first patch's centre and offset and of the draws among near-best offsets.
    return_info : bool
        Also return a :class:`MeshQuiltingInfo`.
    progress : bool or callable
        A bar over the patches, or a callable ``(step, total, info)``.

    Returns
    -------
    vertices : numpy.ndarray
        float64 ``(N, 3)``, the placed elements' vertices in the shell.
    faces : numpy.ndarray
        int64 ``(M, 3)``; each element a closed component. With the surface's own mesh beside it, the
        pair is a mesh for :func:`texsynth.render_mesh` and :func:`texsynth.write_mesh`.
    info : MeshQuiltingInfo
        With ``return_info=True``.

    Raises
    ------
    ValueError
        Bad meshes (named: ``swatch`` or ``surface``), a patch too large for the swatch, bad options.
    """
    t0 = time.perf_counter()
    sw = _swatch(swatch)
    surf = _surface(surface)
    unit_length = check_positive_float(unit_length, "unit_length")
    thickness = unit_length * sw.height if is_auto(thickness) else check_positive_float(thickness, "thickness")
    extent = float((sw.high - sw.low).min())
    radius = 0.25 * extent if is_auto(patch_radius) else check_positive_float(patch_radius, "patch_radius")
    if 2 * radius >= extent:
        raise ValueError(f"patch_radius={radius:g} swatch units does not fit in the swatch: its element centres "
                         f"span {extent:g}; pass patch_radius below {extent / 2:g} or a larger swatch")
    step = 0.2 * sw.spacing if is_auto(candidate_step) else check_positive_float(candidate_step, "candidate_step")
    error_tolerance = check_positive_float(error_tolerance, "error_tolerance", allow_zero=True)
    placement = check_choice(placement, "placement", QUILT_PLACEMENTS)
    return_info = check_bool(return_info, "return_info")
    gen = as_rng(rng)
    n_offsets = np.prod([np.floor((hi - lo - 2 * radius) / step + 1e-9) + 1 for lo, hi in zip(sw.low, sw.high)])
    # a patch's query: every (offset, swatch element) pair and every (offset, placed element near it) pair
    check_memory(8.0 * n_offsets * (6 * len(sw.centers) + 200), step, "candidate_step",
                 "the candidate offsets' element-set distances")
    axes = [np.arange(lo + radius, hi - radius + 1e-9, step) for lo, hi in zip(sw.low, sw.high)]
    offsets = np.stack(np.meshgrid(*axes, indexing="ij"), -1).reshape(-1, 2)

    centers = _patch_centers(surf, radius * unit_length, gen)
    placed_v, placed_f, placed_src, placed_patch = [], [], [], []
    base, sphere_c, sphere_r = np.empty((0, 3)), np.empty((0, 3)), np.empty(0)  # the placed elements' feet, spheres
    chosen, costs = np.zeros((len(centers), 2)), np.zeros(len(centers))
    n_duplicates = n_collisions = n_folded = 0
    h_scale = thickness / sw.height
    with Progress(progress, len(centers), "mesh quilting") as bar:
        for p, vertex in enumerate(centers):  # sequential by nature: each patch matches the ones placed before
            center, normal = surf.vertices[vertex], surf.normals[vertex]
            t1, t2 = _frame(normal)
            near = np.linalg.norm(base - center, axis=1) < (radius + 0.5 * sw.spacing) * unit_length  # the overlap
            old_uv = np.c_[(base[near] - center) @ t1, (base[near] - center) @ t2] / unit_length
            if placement == "random" or not near.any():
                choice = int(gen.integers(len(offsets)))
                if near.any():  # the baseline's element-set distance, for comparison
                    costs[p] = _match(sw, old_uv, offsets[choice:choice + 1], radius)[0]
            else:
                cost = _match(sw, old_uv, offsets, radius)
                choice = int(gen.choice(within_tolerance(cost, error_tolerance)))
                costs[p] = cost[choice]
            chosen[p] = offsets[choice]
            local = sw.centers - offsets[choice]
            take = np.flatnonzero(np.hypot(local[:, 0], local[:, 1]) < radius)
            # the elements' centres through the patch's map; correspondence with the placed elements first (see the
            # loop below), so that only the kept ones are deformed
            _, feet, up = _to_shell(surf, center, t1, t2, local[take] * unit_length, np.zeros(len(take)))
            free = ~np.any(np.linalg.norm(feet[:, None] - base[None], axis=2) < sw.closest * unit_length, axis=1)
            n_duplicates += int(np.sum(~free))
            take, feet, up = take[free], feet[free], up[free]
            if len(take) == 0:
                bar.advance({"elements": len(placed_v)})
                continue
            points, sizes = _deform(surf, sw, take, feet, up, t1, unit_length, h_scale)
            ends = np.cumsum(sizes)
            for i, e in enumerate(take):  # element by element: each is tested against all kept before
                if np.any(np.linalg.norm(base - feet[i], axis=1) < sw.closest * unit_length):
                    n_duplicates += 1  # correspondence: nearer a placed element than any two swatch elements are
                    continue  # to each other, it takes that one's place: the placed one stays
                element = points[ends[i] - sizes[i]:ends[i]]
                ratio = _areas(element, sw.faces[e]) / (sw.areas[e] * unit_length * min(unit_length, h_scale))
                if ratio.min() < MIN_AREA_RATIO:  # the local map folds here (a crease of the surface)
                    n_folded += 1
                    continue
                mid = element.mean(0)
                reach = float(np.linalg.norm(element - mid, axis=1).max())
                close = np.flatnonzero(np.linalg.norm(sphere_c - mid, axis=1) < sphere_r + reach)
                if any(_meets(element, sw.faces[e], placed_v[o], placed_f[o]) for o in close):
                    n_collisions += 1
                    continue
                placed_v.append(element)
                placed_f.append(sw.faces[e])
                placed_src.append(e)
                placed_patch.append(p)
                base, sphere_c = np.vstack([base, feet[i]]), np.vstack([sphere_c, mid])
                sphere_r = np.r_[sphere_r, reach]
            bar.advance({"elements": len(placed_v)})
    counts = np.array([len(v) for v in placed_v], np.int64)
    starts = np.r_[0, np.cumsum(counts)[:-1]]
    vertices = np.concatenate(placed_v) if placed_v else np.empty((0, 3))
    faces = (np.concatenate([f + s for f, s in zip(placed_f, starts)]) if placed_f
             else np.empty((0, 3), np.int64)).astype(np.int64)
    if not return_info:
        return vertices, faces
    info = MeshQuiltingInfo(
        patch_centers=surf.vertices[centers], offsets=chosen, costs=costs,
        element_sources=np.array(placed_src, np.int64), element_patches=np.array(placed_patch, np.int64),
        element_centers=base,
        face_elements=np.repeat(np.arange(len(placed_f)), [len(f) for f in placed_f]).astype(np.int64),
        n_duplicates=n_duplicates, n_collisions=n_collisions, n_folded=n_folded, unit_length=unit_length,
        thickness=float(thickness), patch_radius=float(radius), seconds=time.perf_counter() - t0)
    return vertices, faces, info
