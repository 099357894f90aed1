"""Retiling: evenly spaced vertices over a surface, and the mesh hierarchy surface synthesis runs on.

Turk [1]_ retiles a polygonal surface in three steps, followed here:

1. **Point placement**: ``n`` points scattered at random over the surface
   (area-weighted), then spread by *repulsion*: every point is pushed away
   from the points within the repulsion radius ``r`` with a force falling
   linearly from the point to ``r``, the push is projected into the tangent
   plane, and the moved point is projected back onto the surface (its
   closest point on the original triangles). After a few dozen rounds the
   points are evenly spaced.
2. **Re-triangulation**: Turk's mutual tessellation inserts the points into
   the original mesh and removes the old vertices. Here the new mesh is
   instead the dual of the points' Voronoi regions on the surface: the
   surface is subdivided finely (4-to-1 splits until its edges are shorter
   than half the point spacing), every fine vertex takes the label of its
   nearest point, and every fine triangle whose three corners carry three
   different labels ``(a, b, c)`` yields the triangle ``(a, b, c)``, in the
   orientation of the fine triangle it came from (an approximate restricted
   Delaunay triangulation), turned to face outwards like that fine
   triangle. Where four regions meet almost at a point the triangles can
   overlap: edges that would be shared by more than two triangles, or run
   the same way by two, lose the triangles found last, and the small holes
   this leaves (loops of at most 8 edges) are closed by fans. Points whose
   region meets no junction are dropped.
3. **Hierarchy**: surface synthesis (Turk 2001 [2]_, Wei & Levoy 2001 [3]_)
   runs coarse to fine over meshes of decreasing density, each with a
   quarter of the points of the next finer one, so that the point spacing
   doubles per level like an image pyramid's pixel spacing. As in Turk 2001
   (as a presentation of the paper summarises it: "each layer contains every
   vertex of the layer above it"), the coarsest points are placed first and
   each finer level spreads three times as many new points among the
   coarser ones, which stay where they are (:func:`mesh_hierarchy`).

The spacing of ``n`` points on area ``A`` is that of a triangular lattice,
``s = sqrt(2 A / (sqrt(3) n))``; the repulsion radius is ``r = 2 s`` (Turk
sets it from the area per point as well; his exact constant could not be
checked).

What could not be checked: the papers were not at hand. The force law,
radius constant, the 40 rounds with a step shrinking from ``0.4 s`` to
``0.05 s`` and the Voronoi-dual triangulation (instead of mutual
tessellation) are this implementation's choices; the result was checked by
the spread of nearest-point distances (coefficient of variation about 0.05
after repulsion against about 0.5 for random points) and by closed,
consistently oriented meshes of the right Euler characteristic on spheres
and tori.

References
----------
.. [1] G. Turk, "Re-tiling polygonal surfaces", SIGGRAPH 1992, pp. 55-64.
   :doi:`10.1145/142920.134008`
.. [2] G. Turk, "Texture synthesis on surfaces", SIGGRAPH 2001, pp. 347-354.
   :doi:`10.1145/383259.383297`
.. [3] L.-Y. Wei and M. Levoy, "Texture synthesis over arbitrary manifold
   surfaces", SIGGRAPH 2001, pp. 355-360. :doi:`10.1145/383259.383298`
"""

from __future__ import annotations

import numbers

import numpy as np

from ..core._validate import as_rng, check_memory, check_positive_float, check_positive_int
from ..core.search import point_tree
from ..core.triangles import closest_on_triangles
from ._mesh import Mesh
from ._meshio import as_mesh

__all__ = ["retile", "mesh_hierarchy", "lattice_spacing", "closest_points"]

_REPULSION_ROUNDS = 40
_CANDIDATE_FACES = 8      # original faces tried per closest-point query
_SUBDIVIDE_RATIO = 0.5    # fine edges at most this fraction of the point spacing
_MIN_POINTS = 12
_REPAIR_ROUNDS = 4      # rounds of dropping overlaps and filling holes
_MAX_HOLE = 8          # boundary loops of at most this many edges are gaps of the triangulation, filled
# bytes per point of the largest retiling allocation: the fine mesh (about 4 vertices and 8 faces per point at
# the subdivision ratio, up to 4x more after the last split) and the repulsion pairs
_BYTES_PER_POINT = 4 * 16 * (3 * 8 + 3 * 8 + 8) + 40 * 8 * 4


def lattice_spacing(area, n):
    """Edge of the triangular lattice that puts ``n`` points on ``area``: ``sqrt(2 A / (sqrt(3) n))``."""
    return float(np.sqrt(2.0 * area / (np.sqrt(3.0) * n)))


def closest_points(mesh, queries, *, tree=None, chunk=20000):
    """The closest point of the surface to each query, and its face.

    Tries the ``8`` faces with the nearest centroids (exact for queries
    near the surface, the only ones retiling asks about).

    Returns
    -------
    points : numpy.ndarray, shape (P, 3)
    faces : numpy.ndarray of int64, shape (P,)
    """
    tri = mesh.vertices[mesh.faces]
    tree = point_tree(tri.mean(axis=1)) if tree is None else tree
    k = min(_CANDIDATE_FACES, len(mesh.faces))
    points = np.empty_like(queries)
    faces = np.empty(len(queries), dtype=np.int64)
    for start in range(0, len(queries), chunk):
        q = queries[start:start + chunk]
        _, cand = tree.query(q, k=k)
        cand = cand.reshape(len(q), k)
        t = tri[cand]
        p, _ = closest_on_triangles(q[:, None, :], t[:, :, 0], t[:, :, 1], t[:, :, 2])
        d = np.einsum("pkj,pkj->pk", p - q[:, None, :], p - q[:, None, :])
        best = np.argmin(d, axis=1)
        rows = np.arange(len(q))
        points[start:start + chunk] = p[rows, best]
        faces[start:start + chunk] = cand[rows, best]
    return points, faces


def _random_surface_points(mesh, n, rng):
    face = rng.choice(len(mesh.faces), size=n, p=mesh.face_areas / mesh.face_areas.sum())
    r1, r2 = rng.random(n), rng.random(n)
    s = np.sqrt(r1)
    tri = mesh.vertices[mesh.faces[face]]
    return (1 - s)[:, None] * tri[:, 0] + (s * (1 - r2))[:, None] * tri[:, 1] + (s * r2)[:, None] * tri[:, 2], face


def _repel(mesh, n, rng, rounds=_REPULSION_ROUNDS, fixed=None):
    """Turk's point placement: ``n`` random surface points spread by repulsion (step 1).

    With ``fixed`` (points already placed, and their faces), ``n`` new points are spread among them: the fixed
    points push but do not move (Turk 2001's hierarchy). Returns the fixed points followed by the new ones.
    """
    held = 0 if fixed is None else len(fixed[0])
    spacing = lattice_spacing(mesh.face_areas.sum(), n + held)
    radius = 2.0 * spacing
    points, face = _random_surface_points(mesh, n, rng)
    if fixed is not None:
        points, face = np.concatenate([fixed[0], points]), np.concatenate([fixed[1], face])
    tree = point_tree(mesh.vertices[mesh.faces].mean(axis=1))
    for step in np.geomspace(0.4, 0.05, rounds) * spacing:
        i, j = point_tree(points).query_pairs(radius, output_type="ndarray").T
        diff = points[i] - points[j]
        dist = np.linalg.norm(diff, axis=1)
        push = (1.0 - dist / radius)[:, None] * diff / np.maximum(dist, 1e-12 * spacing)[:, None]
        force = np.zeros_like(points)
        np.add.at(force, i, push)
        np.add.at(force, j, -push)
        normal = mesh.face_normals[face]
        force -= np.einsum("ij,ij->i", force, normal)[:, None] * normal
        length = np.linalg.norm(force, axis=1, keepdims=True)
        move = force * np.minimum(1.0, 1.0 / np.maximum(length, 1e-300))  # a unit-capped push
        moved, face[held:] = closest_points(mesh, points[held:] + step * move[held:], tree=tree)
        points = np.concatenate([points[:held], moved])
    return points, face


def _subdivide(mesh, max_edge):
    """4-to-1 midpoint splits until every edge is at most ``max_edge`` (the surface is unchanged)."""
    vertices, faces = mesh.vertices, mesh.faces
    while True:
        a, b = np.roll(faces, -1, axis=1), faces
        lengths = np.linalg.norm(vertices[a] - vertices[b], axis=2)
        if lengths.max() <= max_edge:
            return vertices, faces
        edges = np.sort(np.stack([b, a], axis=2).reshape(-1, 2), axis=1)
        unique, inverse = np.unique(edges, axis=0, return_inverse=True)
        mid = len(vertices) + inverse.reshape(-1, 3)  # midpoint of edge k (corner k to k + 1)
        vertices = np.concatenate([vertices, 0.5 * (vertices[unique[:, 0]] + vertices[unique[:, 1]])])
        f0, f1, f2 = faces.T
        m0, m1, m2 = mid.T
        faces = np.concatenate([np.stack(s, axis=1) for s in
                                ((f0, m0, m2), (m0, f1, m1), (m2, m1, f2), (m0, m1, m2))])


def _triangulate(mesh, points):
    """Dual of the points' Voronoi regions on the surface (step 2); returns a compacted Mesh."""
    spacing = lattice_spacing(mesh.face_areas.sum(), len(points))
    fine_vertices, fine_faces = _subdivide(mesh, _SUBDIVIDE_RATIO * spacing)
    _, label = point_tree(points).query(fine_vertices)
    tri = label[fine_faces]
    distinct = (tri[:, 0] != tri[:, 1]) & (tri[:, 1] != tri[:, 2]) & (tri[:, 0] != tri[:, 2])
    tri, source = tri[distinct], fine_faces[distinct]
    _, first = np.unique(np.sort(tri, axis=1), axis=0, return_index=True)
    first = np.sort(first)
    tri, source = tri[first], source[first]
    # the labels keep the fine face's winding, but the points may lie the other way round: face outwards
    fine = fine_vertices[source]
    outward = np.cross(fine[:, 1] - fine[:, 0], fine[:, 2] - fine[:, 0])
    p = points[tri]
    flip = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), outward) < 0
    tri[flip] = tri[flip][:, ::-1]
    return Mesh(points, _repair(tri, len(points))).compact()


def _repair(tri, n):
    """Make the dual triangles a consistently oriented manifold: drop the triangles on edges with more than two
    (the later ones) or run the same way by two, then close the small holes left (loops of at most
    ``_MAX_HOLE`` edges) by fans, a few rounds; longer loops are the surface's own boundary and stay open."""
    for _ in range(_REPAIR_ROUNDS):
        tri = _drop_overlaps(tri, n)
        fans = _fill_holes(tri, n)
        if not fans:
            return tri
        tri = np.concatenate([tri, *fans])
    return _drop_overlaps(tri, n)


def _drop_overlaps(tri, n):
    """Without the later triangles on edges with more than two, or run the same way by two."""
    while len(tri):
        a, b = tri, np.roll(tri, -1, axis=1)
        keys = (np.minimum(a, b) * n + np.maximum(a, b)).ravel()
        _, inverse, counts = np.unique(keys, return_inverse=True, return_counts=True)
        _, d_inverse, d_counts = np.unique((a * n + b).ravel(), return_inverse=True, return_counts=True)
        # among the triangles on an edge, the rank of each (first found first)
        order = np.argsort(inverse, kind="stable")
        rank = np.empty_like(inverse)
        rank[order] = np.arange(len(keys)) - np.repeat(np.concatenate([[0], np.cumsum(counts)[:-1]]), counts)
        drop = ((rank >= 2) | ((d_counts[d_inverse] > 1) & (rank >= 1))).reshape(-1, 3).any(axis=1)
        if not drop.any():
            break
        tri = tri[~drop]
    return tri


def _fill_holes(tri, n):
    """Fan triangles closing every boundary loop of at most ``_MAX_HOLE`` edges."""
    a, b = tri.ravel(), np.roll(tri, -1, axis=1).ravel()
    directed = a * n + b
    boundary = ~np.isin(b * n + a, directed)
    nxt = {}
    for u, v in zip(a[boundary].tolist(), b[boundary].tolist()):
        nxt.setdefault(u, []).append(v)
    fans, seen = [], set()
    for start in list(nxt):  # a walk round each loop: sequential by nature, loops are few and short
        if start in seen or len(nxt[start]) != 1:
            continue
        loop = [start]
        while len(loop) <= _MAX_HOLE:
            following = nxt.get(loop[-1], [])
            if len(following) != 1 or following[0] == start:
                break
            loop.append(following[0])
        seen.update(loop)
        if 3 <= len(loop) <= _MAX_HOLE and nxt.get(loop[-1], [None])[0] == start:
            v = np.array(loop)
            fans.append(np.stack([np.full(len(v) - 2, v[0]), v[2:], v[1:-1]], axis=1))
    return fans


def _check_count(n_vertices, mesh):
    n = check_positive_int(n_vertices, "n_vertices", _MIN_POINTS)
    check_memory(float(_BYTES_PER_POINT) * n, n, "n_vertices", "retiling the surface")
    return n


def retile(mesh, n_vertices=None, *, spacing=None, rng=None):
    """Turk's retiling: a new mesh of evenly spaced vertices over the same surface.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    n_vertices : int, optional
        About how many vertices the new mesh has (a few points whose Voronoi
        region meets no other two are dropped).
    spacing : float, optional
        Instead of ``n_vertices``: the spacing of the vertices, in the mesh's
        length unit (``n_vertices`` then follows from the surface area).
    rng : None, int or numpy.random.Generator
        Seeds the initial random points. Same seed, same mesh.

    Returns
    -------
    Mesh
        The retiled surface (no colours or texture).

    Raises
    ------
    ValueError, TypeError
        For neither or both of ``n_vertices`` and ``spacing``, fewer than 12
        vertices, or more than the memory available holds.

    Notes
    -----
    See the module notes: repulsion (Turk 1992) and a Voronoi-dual
    re-triangulation in place of his mutual tessellation.

    Examples
    --------
    >>> from texsynth.surface import sphere
    >>> r = retile(sphere(3), 200, rng=0)
    >>> 190 <= len(r.vertices) <= 200, r.faces.shape[1]
    (True, 3)
    """
    mesh = as_mesh(mesh)
    n = resolve_count(mesh, n_vertices, spacing, "spacing")
    points, _ = _repel(mesh, n, as_rng(rng))
    return _triangulate(mesh, points)


def resolve_count(mesh, n_vertices, spacing, spacing_name):
    """The vertex count from ``n_vertices`` or from a vertex ``spacing`` (named ``spacing_name``)."""
    if (n_vertices is None) == (spacing is None):
        raise ValueError(f"pass exactly one of n_vertices (how many vertices) and {spacing_name} (their spacing), "
                         f"got n_vertices={n_vertices!r} and {spacing_name}={spacing!r}")
    if spacing is not None:
        spacing = check_positive_float(spacing, spacing_name)
        area = float(mesh.face_areas.sum())
        n = 2.0 * area / (np.sqrt(3.0) * spacing ** 2)
        if n > 2**40:
            raise ValueError(f"{spacing_name}={spacing:g} on a surface of area {area:g} means {n:.3g} vertices; pass "
                             f"a larger {spacing_name}")
        n = max(_MIN_POINTS, int(round(n)))
        check_memory(float(_BYTES_PER_POINT) * n, spacing, spacing_name, f"retiling the surface into {n} vertices")
        return n
    return _check_count(n_vertices, mesh)


def mesh_hierarchy(mesh, n_vertices, levels, *, finest=None, rng=None):
    """Meshes of decreasing density over one surface, finest first (step 3).

    Turk 2001's hierarchy: the coarsest level's points are placed first (by
    repulsion); each finer level keeps the coarser one's points where they
    are and spreads three times as many new ones among them (the fixed
    points push, only the new ones move), so every level holds the vertices
    of the levels above it (but for the rare point whose Voronoi region the
    triangulation drops). With ``finest`` (a mesh's own vertices) the coarser
    levels are retiled each on its own.

    Parameters
    ----------
    mesh : Mesh
        The surface (already checked).
    n_vertices : int
        Vertices of the finest level (ignored with ``finest``).
    levels : int
        Number of meshes; level ``l`` has about ``n_vertices / 4**l``.
    finest : Mesh, optional
        Use this mesh as the finest level instead of retiling it.
    rng : numpy.random.Generator

    Returns
    -------
    list of Mesh
    """
    if not isinstance(levels, numbers.Integral):
        raise TypeError(f"levels must be an integer, got {levels!r}")
    rng = as_rng(rng)
    if finest is not None:
        return [finest] + [_triangulate(mesh, _repel(mesh, count, rng)[0])
                           for count in _level_counts(len(finest.vertices), levels)[1:]]
    placed, out = None, []
    for count in _level_counts(n_vertices, levels)[::-1]:
        placed = _repel(mesh, count - (0 if placed is None else len(placed[0])), rng, fixed=placed)
        out.insert(0, _triangulate(mesh, placed[0]))
    return out


def _level_counts(n, levels):
    """Vertices of each level, finest first: a quarter per level."""
    counts = [n // 4 ** level for level in range(levels)]
    if counts[-1] < _MIN_POINTS:
        raise ValueError(f"levels={levels} leaves {counts[-1]} vertices at the coarsest level of a {n}-vertex mesh; "
                         "pass fewer levels or more vertices")
    return counts
