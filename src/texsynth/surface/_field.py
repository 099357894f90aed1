"""Tangent vector fields over a surface: which way the texture's x axis runs at every point.

Surface synthesis lays the exemplar's pixel grid on the surface along a
tangent field: at a point with normal ``n`` and field vector ``t``, the
exemplar's columns run along ``t`` and its rows (downwards) along
``-(n x t)``, so the texture is seen unmirrored from outside. The field comes
from the user, or is made here:

- **user vectors**: one ``(x, y, z)`` vector per mesh vertex (projected into
  the tangent plane and normalised), or a callable of positions ``(P, 3) ->
  (P, 3)`` such as ``lambda p: np.cross([0, 0, 1], p)`` (latitude lines);
- **random**: an independent direction per point, for isotropic textures
  (whose look does not depend on the direction; whether Wei & Levoy 2001
  [2]_ orient them at random could not be checked);
- **smooth**: relaxation (Turk 2001 [1]_ and Praun et al. 2000 [3]_ both
  relax a field), started from the circles about the surface's axis of
  least spread (two singularities on a sphere, none on a torus; from a
  random start the same relaxation left a pair of singularities on a torus
  in two of three seeds): every vector is repeatedly replaced by the mean
  of its neighbours' vectors carried into its tangent plane, coarse to fine
  over a hierarchy of nested random subsets of the points (so the far-apart
  vectors agree after few iterations). With ``symmetry=s`` the
  mean is taken over the angles multiplied by ``s`` (an ``s``-RoSy field), so a
  texture with 2- or 4-fold rotational symmetry may turn by ``2 pi / s``
  between neighbours, which removes needless singularities.

Points where a user vector has no tangential part (a latitude field at the
poles) are filled by the same relaxation from their neighbours: those are
the field's singularities.

What could not be checked: the papers were not at hand. Turk relaxes over
his mesh hierarchy, coarse to fine, with a user-given direction at a few
vertices; the nested random subsets, the 8 nearest neighbours, the iteration
counts, the rotational starting guess and the ``s``-fold angle averaging
(the usual n-RoSy construction) are this implementation's choices.

References
----------
.. [1] G. Turk, "Texture synthesis on surfaces", SIGGRAPH 2001, pp. 347-354.
   :doi:`10.1145/383259.383297`
.. [2] L.-Y. Wei and M. Levoy, "Texture synthesis over arbitrary manifold
   surfaces", SIGGRAPH 2001, pp. 355-360. :doi:`10.1145/383259.383298`
.. [3] E. Praun, A. Finkelstein and H. Hoppe, "Lapped textures", SIGGRAPH
   2000, pp. 465-470. :doi:`10.1145/344779.344987`
"""

from __future__ import annotations

import numpy as np

from ..core._validate import as_rng
from ..core.search import point_tree
from ._meshio import as_mesh

__all__ = ["tangent_field", "FIELDS"]

#: The named fields: ``"smooth"`` (relaxed) and ``"random"``.
FIELDS = ("smooth", "random")
#: Symmetries of the texture the relaxation may use.
SYMMETRIES = (1, 2, 4)

_NEIGHBORS = 8            # graph of the relaxation: each point's nearest points
_COARSEST = 256           # points at the coarsest relaxation level
_COARSE_ITERATIONS = 200  # relaxation sweeps there (the graph's diameter is ~ sqrt(256) = 16 hops)
_FINE_ITERATIONS = 12     # sweeps at each finer level (4x the points: the error left is local)


def tangent_frames(normals):
    """An orthonormal tangent basis ``(e1, e2)`` per unit normal (``e1 x e2 = n``)."""
    axis = np.zeros_like(normals)
    axis[np.arange(len(normals)), np.argmin(np.abs(normals), axis=1)] = 1.0
    e1 = np.cross(normals, axis)
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    return e1, np.cross(normals, e1)


def _angles(vectors, e1, e2):
    return np.arctan2(np.einsum("ij,ij->i", vectors, e2), np.einsum("ij,ij->i", vectors, e1))


def _relax(points, normals, angles, free, symmetry, iterations):
    """Jacobi sweeps: each free point's angle becomes the symmetric mean of its neighbours'."""
    if not free.any() or len(points) < 2:
        return angles
    e1, e2 = tangent_frames(normals)
    k = min(_NEIGHBORS + 1, len(points))
    _, nbr = point_tree(points).query(points, k=k)
    nbr = nbr[:, 1:]
    rows = np.flatnonzero(free)
    nbr = nbr[rows]
    angles = angles.copy()
    for _ in range(iterations):
        t = np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2
        carried = t[nbr]                                             # (F, K, 3), projected below
        phi = np.arctan2(np.einsum("ikj,ij->ik", carried, e2[rows]), np.einsum("ikj,ij->ik", carried, e1[rows]))
        z = np.exp(1j * symmetry * phi).sum(axis=1)
        ok = np.abs(z) > 1e-9
        angles[rows[ok]] = np.angle(z[ok]) / symmetry
    return angles


def _initial_angles(points, e1, e2, rng):
    """The relaxation's start: the circles about the points' axis of least spread through their centroid.

    ``a x (p - c)`` has the fewest singularities a sphere allows (two, at the poles), none on a torus about
    its axis, and is smooth elsewhere; points on the axis (and any with no tangential part) start random.
    """
    centered = points - points.mean(axis=0)
    axis = np.linalg.eigh(centered.T @ centered)[1][:, 0] if len(points) > 1 else np.array([0.0, 0.0, 1.0])
    guess = np.cross(axis, centered)
    angles = _angles(guess, e1, e2)
    tangential = np.hypot(np.einsum("ij,ij->i", guess, e1), np.einsum("ij,ij->i", guess, e2))
    weak = tangential <= 1e-3 * max(float(np.abs(centered).max()), 1e-300)
    angles[weak] = rng.uniform(-np.pi, np.pi, int(weak.sum()))
    return angles


def relaxed_angles(points, normals, angles, free, *, symmetry=1, rng=None):
    """Fill the ``free`` angles by relaxation, coarse to fine over nested random subsets.

    ``angles`` are in each point's :func:`tangent_frames`; fixed (not free)
    angles are kept and steer the rest. Returns the new angles.
    """
    rng = as_rng(rng)
    n = len(points)
    order = rng.permutation(n)
    sizes = [n]
    while sizes[-1] > _COARSEST:
        sizes.append(max(_COARSEST, sizes[-1] // 4))
    angles = angles.copy()
    prev = 0
    for level, m in enumerate(reversed(sizes)):
        idx = order[:m]
        if level:  # new points start from their nearest point of the coarser level
            coarse = order[:prev]
            new = idx[prev:]
            new = new[free[new]]
            if len(new):
                _, near = point_tree(points[coarse]).query(points[new])
                src = coarse[near]
                e1, e2 = tangent_frames(normals)
                t = np.cos(angles[src])[:, None] * e1[src] + np.sin(angles[src])[:, None] * e2[src]
                angles[new] = _angles(t, e1[new], e2[new])
        sweeps = _COARSE_ITERATIONS if level == 0 else _FINE_ITERATIONS
        angles[idx] = _relax(points[idx], normals[idx], angles[idx], free[idx], symmetry, sweeps)
        prev = m
    return angles


def field_vectors(points, normals, field, *, symmetry=1, rng=None, vertices=None):
    """Unit tangent vectors ``(P, 3)`` at ``points`` for a field specification.

    ``field`` is ``"smooth"``, ``"random"``, a callable of positions, or an
    array of vectors at ``vertices`` (the user's mesh vertices, carried to
    ``points`` by the nearest vertex). See :func:`tangent_field`.
    """
    rng = as_rng(rng)
    e1, e2 = tangent_frames(normals)
    n = len(points)
    if isinstance(field, str):
        if field == "random":
            angles = rng.uniform(-np.pi, np.pi, n)
            return np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2
        angles = relaxed_angles(points, normals, _initial_angles(points, e1, e2, rng), np.ones(n, bool),
                                symmetry=symmetry, rng=rng)
        return np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2
    if callable(field):
        vectors = _check_vectors(field(points.copy()), n, "field(points)", "return")
    else:
        vectors = field
        if vertices is not None and not (vertices.shape == points.shape and np.array_equal(vertices, points)):
            _, near = point_tree(vertices).query(points)
            vectors = vectors[near]
    tangential = vectors - np.einsum("ij,ij->i", vectors, normals)[:, None] * normals
    length = np.linalg.norm(tangential, axis=1)
    scale = np.linalg.norm(vectors, axis=1).max() if n else 0.0
    free = length <= 1e-6 * max(scale, 1e-300)
    if free.all():
        raise ValueError("field has no vector with a component along the surface (all are zero or normal to it); "
                         "pass vectors tangent to the surface, or field='smooth'")
    angles = _angles(tangential, e1, e2)
    if free.any():
        angles = relaxed_angles(points, normals, angles, free, symmetry=symmetry, rng=rng)
    return np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2


def _check_vectors(vectors, n, name, verb="be"):
    arr = np.asarray(vectors)
    if arr.dtype == object or not np.issubdtype(arr.dtype, np.number) or np.iscomplexobj(arr):
        raise TypeError(f"{name} must {verb} real (x, y, z) vectors, got dtype {arr.dtype}")
    if arr.shape != (n, 3):
        raise ValueError(f"{name} must {verb} one (x, y, z) vector per vertex, shape ({n}, 3), got shape {arr.shape}; "
                         "pass a vector for every mesh vertex, or a callable of positions")
    arr = arr.astype(np.float64)
    bad = ~np.all(np.isfinite(arr), axis=1)
    if bad.any():
        raise ValueError(f"{name} has {int(bad.sum())} vectors with NaN or infinite values (first: vertex "
                         f"{int(np.flatnonzero(bad)[0])}); pass finite vectors (a zero vector marks a singularity)")
    return arr


def check_field(field, n, symmetry):
    """Validate a field specification for a mesh of ``n`` vertices; returns it (arrays as float64)."""
    check_symmetry(symmetry)
    if isinstance(field, str):
        if field not in FIELDS:
            raise ValueError(f"field must be one of {', '.join(map(repr, FIELDS))}, an (N, 3) array of vectors or a "
                             f"callable of positions, got {field!r}")
        return field
    if callable(field):
        return field
    return _check_vectors(field, n, "field")


def check_symmetry(symmetry):
    """``symmetry`` as 1, 2 or 4."""
    if isinstance(symmetry, bool) or symmetry not in SYMMETRIES:
        raise ValueError(f"symmetry must be 1, 2 or 4 (the texture's rotational symmetry), got {symmetry!r}")
    return int(symmetry)


def tangent_field(mesh, field="smooth", *, symmetry=1, rng=None):
    """A unit tangent vector at every vertex of a mesh.

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    field : {"smooth", "random"}, array_like (N, 3) or callable
        ``"smooth"`` (default): relaxed from random directions, coarse to
        fine (see the module notes). ``"random"``: independent directions,
        for isotropic textures. An ``(N, 3)`` array: a vector per vertex,
        projected into the tangent plane (zero vectors are filled by
        relaxation). A callable ``f(points) -> vectors`` of ``(P, 3)``
        positions, e.g. ``lambda p: np.cross([0, 0, 1], p)`` for latitude
        lines.
    symmetry : {1, 2, 4}
        Rotational symmetry of the texture the relaxation may use: with 2 a
        vector and its opposite are the same direction, with 4 also its
        quarter turns.
    rng : None, int or numpy.random.Generator
        Seeds the random directions. Same seed, same field.

    Returns
    -------
    numpy.ndarray, shape (N, 3)
        Unit vectors perpendicular to the vertex normals.

    Raises
    ------
    ValueError, TypeError
        For a field of the wrong length, with NaN, wholly normal to the
        surface, or an unknown name or symmetry.

    Examples
    --------
    >>> from texsynth.surface import sphere
    >>> s = sphere(2)
    >>> t = tangent_field(s, lambda p: np.cross([0, 0, 1], p))
    >>> bool(np.allclose(np.linalg.norm(t, axis=1), 1)), bool(np.abs((t * s.vertex_normals).sum(1)).max() < 1e-9)
    (True, True)
    """
    mesh = as_mesh(mesh)
    field = check_field(field, len(mesh.vertices), symmetry)
    return field_vectors(mesh.vertices, mesh.vertex_normals, field, symmetry=symmetry, rng=rng,
                         vertices=mesh.vertices)

