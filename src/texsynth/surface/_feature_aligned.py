"""Feature-aligned texturing of surfaces (Xu, Cohen-Or, Ju, Liu, Zhang, Zhou & Xiong 2009).

Xu et al. [1]_ texture a shape automatically by two principles: the
texture's direction follows the surface's **salient curves** (its ridges
and valleys), and the exemplar's own prominent **feature lines** are laid
exactly onto those curves. The steps, as followed here:

1. **Salient curves.** The principal curvatures of every vertex, from a
   quadric ``h = a u^2 + b u v + c v^2 + d u + e v`` fitted by least squares
   to its nearest vertices in its tangent frame ``(u, v, n)`` (all vertices
   at once: one batched 5 x 5 solve); the shape operator ``[[2a, b], [b,
   2c]]`` gives the curvatures and their directions. A vertex is *salient*
   where the curvature of largest magnitude ``k`` is above a threshold and
   an extremum across its curvature line: ``|k|`` is at least that of every
   near vertex that lies along its principal direction ``d`` (within 30
   degrees; a non-maximum suppression, as a ridge is the extremum of ``k``
   along ``d``), ``k < 0`` a ridge (convex: the surface bends away from its
   outward normal), ``k > 0`` a valley. Salient vertices of one kind within
   2 mean edge lengths of each other are **chained** into curves (connected
   pieces of that graph); pieces of fewer than ``min_vertices`` vertices are
   dropped. :func:`salient_curves`; the user may give curves instead, as a
   mask of vertices.
2. **Curve orientation.** Each curve vertex's tangent is the main axis of
   the curve vertices near it (a local principal component analysis,
   projected into its tangent plane). A curve has no direction of its own:
   the tangents of each curve are made consistent by walking it breadth
   first (each vertex takes the sign closer to its predecessor's).
3. **A vector field constrained by the curves.** At the curve vertices the
   field is fixed to the tangent turned by the exemplar's feature angle
   (so that the exemplar's feature lines, not its x axis, run along the
   curves); everywhere else it is the smoothest field: one sparse solve of
   ``min sum over edges |z_i - r_ij z_j|^2`` for ``z = exp(i s theta)`` in
   the vertices' tangent frames (``r_ij`` carries a neighbour's frame into
   the vertex's), the curve vertices held (:func:`_smooth_angles`; the
   Jacobi relaxation of :func:`~texsynth.surface.tangent_field`, with the
   curve vertices held, left the field 39-45 degrees off the crests of the
   test mesh beyond 6 vertex spacings: the constraints hardly reached past
   their neighbours). First a line field (``s = 2``: a curve's tangent and
   its opposite are the same constraint, so no sign is needed; ``s = 4``
   for ``symmetry=4``); for a texture without that symmetry
   (``symmetry=1``) the line field is combed into vectors over the mesh,
   each curve takes the sign most of its vertices then have, and the field
   is solved again as a vector field (``s = 1``) with the curves so
   oriented.
4. **Feature-aligned synthesis.** The exemplar's feature lines are its edge
   map (Canny, as :func:`~texsynth.optimization._ruiters_neighborhoods.edge_feature_map`
   makes it) or a map the user gives; a *feature channel* ``f = exp(-d^2 / 2
   sigma^2)`` of the distance ``d`` to the nearest feature line (``sigma``
   1.5 pixels of each pyramid level) is added to the exemplar. Every surface
   vertex gets the same channel of its distance to the nearest curve, but
   given, not synthesised: ``g = m + (1 - m) exp(-d^2 / 2 sigma^2)``, ``m``
   the exemplar channel's mean (away from the curves every exemplar
   neighbourhood is about equally far from ``m``, so the term leaves the
   texture free there). The vertex synthesis of
   :func:`~texsynth.surface.synthesize_surface` (retiled hierarchy,
   neighbourhoods flattened along the field, global search at the coarsest
   level and k-coherent candidates below, parallel passes) then matches
   ``|T(p) - T(x)|^2 + w_F |f(p) - g(x)|^2`` summed over the neighbourhood,
   so that exemplar neighbourhoods whose feature lines lie where the curves
   are win near the curves: the paper's feature alignment term in the
   distance of the synthesis.

What could not be checked: the paper was not at hand; this follows its
published description (abstract, the issue's summary) and the lecture slides
that show its curve orientation, vector field and results. The paper
optimises the texture (Kwatra et al. 2005) with its feature term on the
surface; here the feature term is an extra channel of
Turk's and Wei & Levoy's vertex synthesis (the library's surface method).
Its curve extraction, the orientation of the curves (how the paper makes
their signs consistent could not be checked; here a comb and a majority
vote), the field's
constraints and solver, and all constants (the quadric's 12 neighbours, the
30-degree cone, 3 times the median curvature as the ``"auto"`` threshold,
1.5-pixel feature width, ``w_F = 1``) are this implementation's choices.

References
----------
.. [1] K. Xu, D. Cohen-Or, T. Ju, L. Liu, H. Zhang, S. Zhou and Y. Xiong,
   "Feature-aligned shape texturing", ACM TOG 28(5) (SIGGRAPH Asia 2009),
   article 108. :doi:`10.1145/1618452.1618454`
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field as dataclass_field

import numpy as np
import scipy.ndimage
import scipy.sparse
import scipy.sparse.csgraph
import scipy.sparse.linalg

from ..core._progress import Progress
from ..core._validate import (as_array, as_image, as_rng, check_memory, check_positive_float, check_positive_int,
                              is_auto, with_channels)
from ..core.pyramid import gaussian_pyramid
from ..core.search import Search, point_tree
from ..metrics import dominant_orientation
from ._field import check_symmetry, tangent_frames
from ._meshio import as_mesh
from ._retile import mesh_hierarchy, resolve_count
from ._vertex_synthesis import SurfaceSchedule, guided_levels, guided_options, level_frames

__all__ = ["feature_aligned_surface", "salient_curves", "curve_alignment", "SalientCurves", "FeatureAlignedInfo"]

_QUADRIC_NEIGHBORS = 12   # nearest vertices of the quadric fit
_CONE = np.cos(np.radians(30.0))  # a neighbour lies "across" the curve within this cone about the direction d
_AUTO_THRESHOLD = 3.0     # "auto" min_curvature: this many times the median |k| over the mesh
_CHAIN = 2.0              # salient vertices closer than this many (mean) vertex spacings are one curve
_TANGENT_NEIGHBORS = 9    # curve vertices of the local PCA of the tangent
_TANGENT_RADIUS = 3.0     # ... within this many vertex spacings
_FEATURE_SIGMA = 1.5      # width of the feature channel, in pixels (vertex spacings) of each level
_CANNY_SIGMA = 2.0        # the exemplar's edge map (as texsynth.optimization's edge_feature_map)
# the field's complex sparse LU per input vertex: vertex synthesis measured its real sweep-distance solve at
# 2.1-3.0 kB per vertex (50,000 to 10^6 vertices); complex values double it, with a margin
_FIELD_BYTES = 8192


@dataclass
class SalientCurves:
    """Curves on a mesh: the vertices they pass through and their consistent tangents (:func:`salient_curves`).

    Attributes
    ----------
    vertices : numpy.ndarray of int
        ``(K,)`` the mesh vertices on a curve.
    tangents : numpy.ndarray
        ``(K, 3)`` the unit tangent of the curve at each, in its tangent
        plane, of one sign along each curve.
    labels : numpy.ndarray of int
        ``(K,)`` which curve each vertex belongs to (0, 1, ...).
    kind : numpy.ndarray of int
        ``(K,)`` +1 on a ridge, -1 on a valley, 0 for curves the user gave.
    points : numpy.ndarray
        ``(K, 3)`` the vertices' positions.
    curvature : numpy.ndarray or None
        ``(N,)`` per mesh vertex, the principal curvature of largest
        magnitude (negative where convex); None for curves the user gave.
    directions : numpy.ndarray or None
        ``(N, 3)`` its principal direction (across a ridge).
    """

    vertices: np.ndarray
    tangents: np.ndarray
    labels: np.ndarray
    kind: np.ndarray
    points: np.ndarray
    curvature: np.ndarray | None = None
    directions: np.ndarray | None = None

    @property
    def n_curves(self):
        """How many curves."""
        return int(self.labels.max()) + 1 if len(self.labels) else 0


@dataclass
class FeatureAlignedInfo:
    """Extra results of :func:`feature_aligned_surface`.

    Attributes
    ----------
    levels : list of Mesh
        The mesh hierarchy, finest first, each coloured by its level's result.
    curves : SalientCurves
        The curves the texture follows (found or given).
    field : numpy.ndarray
        ``(N, 3)`` the tangent vector (the exemplar's x axis) at each output
        vertex.
    guide : numpy.ndarray
        ``(N,)`` the feature channel ``g`` given at each output vertex (1 on
        the curves).
    sources : numpy.ndarray of int
        ``(N, 2)`` the exemplar pixel each output vertex copies.
    feature_angle : float
        Degrees, counter-clockwise as the exemplar is shown: the direction of
        its feature lines, laid along the curves.
    energy : numpy.ndarray
        Per level, coarsest first: the mean weighted squared distance of the
        matches.
    stage : numpy.ndarray
        The stage (level, in synthesis order: 0 the coarsest) of each value
        of ``energy``.
    pixel_size : float
        The length on the surface of one exemplar pixel.
    seconds : float
        Total wall time.
    stage_seconds : dict
        Wall time of ``"curves"``, ``"hierarchy"``, ``"field"`` and each
        ``"level l"``.
    """

    levels: list = dataclass_field(default_factory=list)
    curves: SalientCurves | None = None
    field: np.ndarray | None = None
    guide: np.ndarray | None = None
    sources: np.ndarray | None = None
    feature_angle: float = 0.0
    energy: np.ndarray | None = None
    stage: np.ndarray | None = None
    pixel_size: float = 0.0
    seconds: float = 0.0
    stage_seconds: dict = dataclass_field(default_factory=dict)


# --------------------------------------------------------------------------- step 1: curvature and curves
def _principal_curvatures(points, normals, near):
    """Per vertex the curvature of largest magnitude ``k`` and its direction ``d`` (quadric fit, module notes).

    ``near`` ``(N, K)``: each vertex's nearest vertices (itself excluded). Normals point outwards, so a convex
    bend (a ridge) has ``k < 0``.
    """
    e1, e2 = tangent_frames(normals)
    rel = points[near] - points[:, None, :]                              # (N, K, 3)
    u, v = np.einsum("nkd,nd->nk", rel, e1), np.einsum("nkd,nd->nk", rel, e2)
    h = np.einsum("nkd,nd->nk", rel, normals)
    design = np.stack([u * u, u * v, v * v, u, v], axis=-1)              # (N, K, 5)
    scale = np.sqrt(np.mean(u * u + v * v, axis=1))[:, None, None] + 1e-300
    design = design / np.stack([scale[..., 0] ** 2] * 3 + [scale[..., 0]] * 2, axis=-1)  # conditioning
    gram = np.einsum("nki,nkj->nij", design, design) + 1e-12 * np.eye(5)
    coef = np.linalg.solve(gram, np.einsum("nki,nk->ni", design, h)[..., None])[..., 0]
    a, b, c = (coef[:, :3] / scale[:, 0] ** 2).T
    # the shape operator [[2a, b], [b, 2c]]: eigenvalues and the eigenvector of the larger magnitude
    mean, half = a + c, np.sqrt((a - c) ** 2 + b * b)
    k1, k2 = mean + half, mean - half
    k = np.where(np.abs(k1) >= np.abs(k2), k1, k2)
    angle = 0.5 * np.arctan2(b, a - c)                                   # the eigenvector of k1
    angle = np.where(np.abs(k1) >= np.abs(k2), angle, angle + np.pi / 2)
    d = np.cos(angle)[:, None] * e1 + np.sin(angle)[:, None] * e2
    return k, d


def _tangents(points, normals, labels, fallback, spacing):
    """Curve tangents: the main axis of each curve vertex's near vertices on the same curve, in its tangent plane."""
    k = min(_TANGENT_NEIGHBORS, len(points))
    dist, near = point_tree(points).query(points, k=k)
    use = (labels[near] == labels[:, None]) & (dist <= _TANGENT_RADIUS * spacing)
    rel = (points[near] - points[:, None, :]) * use[..., None]
    rel = rel - (rel.sum(1, keepdims=True) / use.sum(1)[:, None, None]) * use[..., None]
    cov = np.einsum("nki,nkj->nij", rel, rel)
    axis = np.linalg.eigh(cov)[1][:, :, -1]
    axis = axis - np.einsum("ij,ij->i", axis, normals)[:, None] * normals
    length = np.linalg.norm(axis, axis=1)
    weak = (use.sum(1) < 2) | (length < 1e-9)        # a lone vertex: across its principal direction
    axis[weak] = np.cross(normals[weak], fallback[weak])
    return axis / np.linalg.norm(axis, axis=1, keepdims=True)


def _orient(tangents, points, labels, spacing):
    """One sign per curve: walk each curve breadth first, each vertex taking the sign nearer its predecessor's."""
    pairs = point_tree(points).query_pairs(_TANGENT_RADIUS * spacing, output_type="ndarray")
    pairs = pairs[labels[pairs[:, 0]] == labels[pairs[:, 1]]]
    n = len(points)
    graph = scipy.sparse.csr_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    tangents = tangents.copy()
    for root in np.unique(labels, return_index=True)[1]:
        order, pred = scipy.sparse.csgraph.breadth_first_order(graph, root, directed=False)
        for v in order[1:]:          # sequential by nature: each sign follows the one before it
            if tangents[v] @ tangents[pred[v]] < 0:
                tangents[v] = -tangents[v]
    return tangents


def _chain(points, kind, spacing, min_vertices):
    """Connected pieces of salient vertices of one kind closer than ``_CHAIN`` spacings; small pieces dropped."""
    n = len(points)
    pairs = point_tree(points).query_pairs(_CHAIN * spacing, output_type="ndarray") if n else np.zeros((0, 2), int)
    pairs = pairs[kind[pairs[:, 0]] == kind[pairs[:, 1]]]
    graph = scipy.sparse.csr_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    _, labels = scipy.sparse.csgraph.connected_components(graph, directed=False)
    counts = np.bincount(labels, minlength=1)
    keep = counts[labels] >= min_vertices
    _, labels = np.unique(labels[keep], return_inverse=True)
    return keep, labels


def _curves_from(mesh, vertices, kind, curvature, directions, min_vertices):
    spacing = mesh.mean_edge_length
    points, normals = mesh.vertices[vertices], mesh.vertex_normals[vertices]
    keep, labels = _chain(points, kind, spacing, min_vertices)
    vertices, kind, points, normals = vertices[keep], kind[keep], points[keep], normals[keep]
    fallback = directions[vertices] if directions is not None else np.cross(normals, tangent_frames(normals)[0])
    tangents = _tangents(points, normals, labels, fallback, spacing) if len(vertices) else np.zeros((0, 3))
    if len(vertices):
        tangents = _orient(tangents, points, labels, spacing)
    return SalientCurves(vertices=vertices, tangents=tangents, labels=labels, kind=kind, points=points,
                         curvature=curvature, directions=directions)


def salient_curves(mesh, *, min_curvature="auto", min_vertices=8):
    """The ridges and valleys of a mesh, chained into curves with consistent tangents (Xu et al. 2009, step 1).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> from texsynth.surface import salient_curves
    >>> ball = texsynth.surface.sphere(2562)
    >>> v = ball.vertices * (1 + 0.3 * np.exp(-(ball.vertices[:, 2] / 0.2) ** 2))[:, None]  # a crest at z = 0
    >>> curves = salient_curves((v, ball.faces))
    >>> curves.n_curves, bool(np.abs(curves.points[:, 2]).max() < 0.1), set(curves.kind.tolist())  # one ridge
    (1, True, {1})

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`), with outward
        normals.
    min_curvature : float or "auto"
        The smallest magnitude of principal curvature (1 / mesh length) of a
        salient vertex. ``"auto"``: 3 times its median over the mesh (a
        sphere has none).
    min_vertices : int
        Curves with fewer vertices are dropped (speckle of a noisy surface).

    Returns
    -------
    SalientCurves
        The curve vertices, their tangents (one sign per curve), curve
        labels, kind (+1 ridge, -1 valley) and the curvature fields.

    Raises
    ------
    ValueError, TypeError
        For an invalid mesh, a ``min_curvature`` that is not positive, or a
        ``min_vertices`` below 1.
    """
    mesh = as_mesh(mesh)
    if not is_auto(min_curvature):
        min_curvature = check_positive_float(min_curvature, "min_curvature")
    min_vertices = check_positive_int(min_vertices, "min_vertices")
    points, normals = mesh.vertices, mesh.vertex_normals
    k = min(_QUADRIC_NEIGHBORS + 1, len(points))
    if k < 6:
        raise ValueError(f"mesh has {len(points)} vertices; curvature needs at least 6: pass a finer mesh")
    _, near = point_tree(points).query(points, k=k)
    near = near[:, 1:]
    curvature, directions = _principal_curvatures(points, normals, near)
    magnitude = np.abs(curvature)
    limit = _AUTO_THRESHOLD * float(np.median(magnitude)) if is_auto(min_curvature) else min_curvature
    # non-maximum suppression across the curve: |k| at least that of every near vertex along d
    rel = points[near] - points[:, None, :]
    cosine = np.abs(np.einsum("nkd,nd->nk", rel, directions)) / (np.linalg.norm(rel, axis=2) + 1e-300)
    across = np.where(cosine >= _CONE, magnitude[near], 0.0).max(axis=1)
    salient = (magnitude > limit) & (magnitude >= across)
    vertices = np.flatnonzero(salient)
    kind = np.where(curvature[vertices] < 0, 1, -1)
    return _curves_from(mesh, vertices, kind, curvature, directions, min_vertices)


def _user_curves(mesh, curves):
    """Curves the user gave: a boolean mask of the mesh's vertices (or the indices of the curve vertices)."""
    arr = as_array(curves, "curves")
    n = len(mesh.vertices)
    if arr.dtype == bool or (arr.shape == (n,) and np.isin(arr, (0, 1)).all()):
        if arr.shape != (n,):
            raise ValueError(f"curves as a mask must have one value per mesh vertex, shape ({n},), got shape "
                             f"{arr.shape}; pass a bool mask, vertex indices, 'auto' or salient_curves(mesh)")
        vertices = np.flatnonzero(arr)
    else:
        if arr.ndim != 1 or not np.issubdtype(arr.dtype, np.integer) or (arr.size and (arr.min() < 0
                                                                                          or arr.max() >= n)):
            raise ValueError(f"curves must be 'auto', a SalientCurves, a bool mask of shape ({n},) or indices of "
                             f"mesh vertices in 0..{n - 1}")
        vertices = np.unique(arr)
    if len(vertices) < 2:
        raise ValueError("curves marks fewer than 2 vertices; mark the vertices along each curve")
    return _curves_from(mesh, vertices.astype(np.int64), np.zeros(len(vertices), np.int64), None, None, 2)


# --------------------------------------------------------------------------- step 3: the field
def _comb(mesh, vectors):
    """A line field as vectors of one sign between mesh neighbours wherever it can be (breadth first by depth)."""
    i, j = mesh.edges.T
    n = len(vectors)
    graph = scipy.sparse.csr_matrix((np.ones(len(i)), (i, j)), shape=(n, n))
    _, label = scipy.sparse.csgraph.connected_components(graph, directed=False)
    roots = np.unique(label, return_index=True)[1]
    depth, pred = scipy.sparse.csgraph.shortest_path(graph, directed=False, unweighted=True, indices=roots,
                                                     return_predecessors=True)
    depth, pred = depth[label, np.arange(n)], pred[label, np.arange(n)]
    combed = vectors.copy()
    for d in range(1, int(depth.max()) + 1):   # one depth of the tree at a time, each depth at once
        v = np.flatnonzero(depth == d)
        flip = np.einsum("ij,ij->i", combed[v], combed[pred[v]]) < 0
        combed[v[flip]] *= -1
    return combed


def _smooth_angles(mesh, fixed, angles, symmetry):
    """The smoothest ``symmetry``-RoSy field with the angles at the vertices ``fixed`` held (a sparse solve).

    Unknowns ``z_i = exp(i s theta_i)`` in each vertex's :func:`~texsynth.surface._field.tangent_frames`;
    the energy ``sum over edges |z_i - r_ij z_j|^2``, ``r_ij = exp(i s alpha_ij)`` carrying vertex ``j``'s frame
    into ``i``'s (``alpha_ij``: the angle of ``j``'s ``e1`` projected into ``i``'s tangent plane), is
    minimised with the fixed ``z`` as boundary values: one sparse Hermitian system over the free vertices.
    Returns the angles of every vertex.
    """
    normals = mesh.vertex_normals
    e1, e2 = tangent_frames(normals)
    i, j = mesh.edges.T
    alpha = np.arctan2(np.einsum("ij,ij->i", e1[j], e2[i]), np.einsum("ij,ij->i", e1[j], e1[i]))
    r = np.exp(1j * symmetry * alpha)
    n = len(normals)
    degree = np.bincount(np.concatenate([i, j]), minlength=n).astype(np.float64)
    laplacian = scipy.sparse.csr_matrix((np.concatenate([-r, -np.conj(r)]), (np.concatenate([i, j]),
                                                                               np.concatenate([j, i]))),
                                        shape=(n, n)) + scipy.sparse.diags(degree.astype(np.complex128))
    free = np.ones(n, bool)
    free[fixed] = False
    z = np.zeros(n, np.complex128)
    z[fixed] = np.exp(1j * symmetry * angles)
    if free.any():
        system = laplacian[free][:, free].tocsc()
        system = system + 1e-9 * scipy.sparse.identity(system.shape[0], format="csc")  # pieces without a curve
        z[free] = scipy.sparse.linalg.spsolve(system, -(laplacian[free][:, ~free] @ z[~free]))
    return np.angle(z) / symmetry


def _constrained_field(mesh, curves, feature_angle, symmetry):
    """The field of step 3: fixed along the curves (turned by the feature angle), the smoothest elsewhere."""
    normals = mesh.vertex_normals
    e1, e2 = tangent_frames(normals)
    v, c = curves.vertices, curves.tangents
    theta = np.radians(feature_angle)
    # the exemplar's x axis t, so that its feature direction (cos, sin) in (t, n x t) is the curve's tangent
    t = np.cos(theta) * c - np.sin(theta) * np.cross(normals[v], c)

    def solve(t, s):
        angles = _smooth_angles(mesh, v, np.arctan2(np.einsum("ij,ij->i", t, e2[v]),
                                                    np.einsum("ij,ij->i", t, e1[v])), s)
        return np.cos(angles)[:, None] * e1 + np.sin(angles)[:, None] * e2

    field = _comb(mesh, solve(t, 4 if symmetry == 4 else 2))   # a line (cross) field: no sign needed
    if symmetry != 1:
        return field
    # a vector field: each curve takes the sign most of its vertices have in the combed line field
    agree = np.einsum("ij,ij->i", field[v], t) >= 0
    votes = np.bincount(curves.labels, weights=np.where(agree, 1.0, -1.0), minlength=curves.n_curves)
    return solve(t * np.where(votes[curves.labels] >= 0, 1.0, -1.0)[:, None], 1)


# --------------------------------------------------------------------------- step 4: features and synthesis
def _feature(distance):
    """The feature channel of a distance to the nearest feature line, in pixels of its level."""
    return np.exp(-0.5 * (distance / _FEATURE_SIGMA) ** 2)


def _exemplar_features(exemplar_features, image):
    """The exemplar's feature lines: Canny edges of its luminance, or the user's map."""
    if is_auto(exemplar_features):
        from skimage.feature import canny

        grey = image[..., :3].mean(axis=-1)
        return canny(grey, sigma=_CANNY_SIGMA)
    arr = as_array(exemplar_features, "exemplar_features")
    if arr.shape != image.shape[:2]:
        raise ValueError(f"exemplar_features must have the exemplar's size {image.shape[:2]}, got shape {arr.shape}; "
                         "pass a bool map of its feature lines or 'auto'")
    if not np.isfinite(arr.astype(np.float64)).all():
        raise ValueError("exemplar_features has NaN or infinite values; pass a map of 0/1 or bool")
    return arr.astype(np.float64) > 0.5


def feature_aligned_surface(
    mesh,
    exemplar,
    *,
    curves="auto",
    exemplar_features="auto",
    alignment_weight=1.0,
    n_vertices=None,
    symmetry=1,
    schedule=SurfaceSchedule(),
    search=Search(candidates="auto"),
    rng=None,
    progress=False,
    return_info=False,
):
    """Texture a surface along its salient curves, the exemplar's feature lines laid on them (Xu et al. 2009).

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> from texsynth.surface import feature_aligned_surface
    >>> ball = texsynth.surface.sphere(2562)
    >>> v = ball.vertices * (1 + 0.3 * np.exp(-(ball.vertices[:, 2] / 0.2) ** 2))[:, None]
    >>> stripes = np.tile((np.arange(32) % 8 < 4)[:, None], (1, 32)).astype(float)
    >>> out = feature_aligned_surface((v, ball.faces), stripes, n_vertices=1500, rng=0,
    ...                               schedule=texsynth.SurfaceSchedule(levels=2, neighborhood_size=5, parent_size=3))
    >>> out.colors.shape[1]
    1

    The surface's ridges and valleys (:func:`salient_curves`) or curves the
    user gives are oriented consistently, a tangent field is constrained to
    follow them and relaxed elsewhere, and the texture is synthesised along
    that field with a feature channel that pulls the exemplar's own feature
    lines (its edge map) onto the curves [1]_ (module notes: the steps, and
    what could not be checked).

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The surface (:func:`~texsynth.surface.as_mesh`).
    exemplar : array_like
        ``(h, w)`` or ``(h, w, C)`` texture sample.
    curves : "auto", SalientCurves or array_like
        ``"auto"``: :func:`salient_curves` with its defaults; a
        :class:`SalientCurves` (e.g. ``salient_curves(mesh,
        min_curvature=...)``); or the user's curves, a bool mask of the mesh's
        vertices (or their indices) along which the texture must run.
    exemplar_features : "auto" or array_like
        The exemplar's feature lines: ``"auto"``, its Canny edges (sigma 2);
        or a bool map of the exemplar's size.
    alignment_weight : float
        ``w_F``, the weight of the feature channel against the colours
        (0: the field alone aligns the texture).
    n_vertices : int, optional
        Retile the surface to about this many vertices; None colours the
        mesh's own vertices.
    symmetry : {1, 2, 4}
        The texture's rotational symmetry: with 2 or 4 the field stays a
        line (cross) field, without signs.
    schedule : SurfaceSchedule
        As in :func:`~texsynth.synthesize_surface` (its ``"default"``
        preset); ``order`` must be ``"independent"``.
    search : texsynth.core.search.Search
        ``k`` (2) and ``method`` of the k-coherent search below the
        coarsest level (``candidates`` must be ``"auto"`` or
        ``"k-coherent"``).
    rng, progress, return_info
        As in :func:`~texsynth.synthesize_surface`; the info is a
        :class:`FeatureAlignedInfo`.

    Returns
    -------
    Mesh
        The (retiled) surface with per-vertex colours.
    info : FeatureAlignedInfo
        Only with ``return_info=True``.

    Raises
    ------
    ValueError, TypeError
        For an invalid mesh, exemplar, feature map, curves (wrong length,
        none found), option, a neighbourhood larger than the exemplar's
        coarsest level, or a density needing more memory than is available.

    References
    ----------
    .. [1] K. Xu, D. Cohen-Or, T. Ju, L. Liu, H. Zhang, S. Zhou and Y. Xiong,
       "Feature-aligned shape texturing", ACM TOG 28(5) (SIGGRAPH Asia
       2009), article 108. :doi:`10.1145/1618452.1618454`
    """
    start = time.perf_counter()
    mesh = as_mesh(mesh)
    opts = guided_options(schedule, search, "feature_aligned_surface", "the tangent field already orients the "
                          "exemplar")
    size, psize, levels, passes = opts.size, opts.parent_size, opts.levels, opts.passes
    alignment_weight = check_positive_float(alignment_weight, "alignment_weight", allow_zero=True, maximum=1e6)
    symmetry = check_symmetry(symmetry)
    rng = as_rng(rng)
    image = with_channels(as_image(exemplar, "exemplar"))[0]
    features = _exemplar_features(exemplar_features, image)
    pyramid = gaussian_pyramid(image, levels)
    coarsest = pyramid[-1].shape[:2]
    need = (max(size[0], psize[0]), max(size[1], psize[1]))
    if coarsest[0] < need[0] or coarsest[1] < need[1]:
        raise ValueError(f"the exemplar's coarsest level (levels={levels}) is {coarsest[0]}x{coarsest[1]} pixels, "
                         f"smaller than the {need[0]}x{need[1]} neighbourhood; pass fewer levels, a smaller "
                         "neighborhood_size or a larger exemplar")
    n = len(mesh.vertices) if n_vertices is None else resolve_count(mesh, n_vertices, None, "n_vertices")
    per_vertex = (size[0] * size[1] + psize[0] * psize[1]) * (4 * 24 + 8 * (image.shape[2] + 1)) * 2
    check_memory(float(n) * per_vertex + float(len(mesh.vertices)) * _FIELD_BYTES, n, "n_vertices",
                 "the surface neighbourhoods and the field's sparse solve")
    info = FeatureAlignedInfo()

    # steps 1-2: the curves, oriented
    t0 = time.perf_counter()
    if isinstance(curves, SalientCurves):
        found = curves
        if len(found.vertices) and found.vertices.max() >= len(mesh.vertices):
            raise ValueError("curves (a SalientCurves) belongs to another mesh: its vertices run past this mesh's; "
                             "pass salient_curves(mesh)")
    elif isinstance(curves, str):
        if curves != "auto":
            raise ValueError(f"curves must be 'auto', a SalientCurves or a vertex mask, got {curves!r}")
        found = salient_curves(mesh)
    else:
        found = _user_curves(mesh, curves)
    if len(found.vertices) == 0:
        raise ValueError("no salient curves were found on the mesh (it has no ridge or valley sharper than the "
                         "threshold); pass salient_curves(mesh, min_curvature=...) with a lower value, or curves as "
                         "a vertex mask")
    info.curves = found
    if features.any():  # the direction of the exemplar's feature lines, in [0, 180)
        info.feature_angle = dominant_orientation(features.astype(np.float64), levels=1)[0] % 180.0
    info.stage_seconds["curves"] = time.perf_counter() - t0

    # step 3: the field on the input mesh, carried to the hierarchy by the nearest vertex
    t0 = time.perf_counter()
    vectors = _constrained_field(mesh, found, info.feature_angle, symmetry)
    info.stage_seconds["field"] = time.perf_counter() - t0
    t0 = time.perf_counter()
    hierarchy = mesh_hierarchy(mesh, n, levels, finest=mesh if n_vertices is None else None, rng=rng)
    info.stage_seconds["hierarchy"] = time.perf_counter() - t0
    frames, info.pixel_size = level_frames(mesh, hierarchy, vectors, symmetry, rng)

    # step 4: the feature channel of the exemplar (per level) and of the vertices, then the synthesis
    distance = scipy.ndimage.distance_transform_edt(~features) if features.any() else np.full(features.shape, np.inf)
    wf = np.sqrt(alignment_weight)
    curve_tree = point_tree(found.points)
    work, guides, given = [], [], []
    for level, (colors, frame) in enumerate(zip(pyramid, frames)):
        f = 2 ** level
        channel = _feature(distance[::f, ::f] / f)
        mean = float(channel.mean())
        work.append(np.concatenate([colors, wf * channel[..., None]], axis=-1))
        near = curve_tree.query(frame.points)[0] / frame.spacing
        given.append(mean + (1.0 - mean) * _feature(near))
        guides.append(wf * given[-1][:, None])
    with Progress(progress, levels * passes, "Xu et al.") as bar:
        values, sources, energies = guided_levels(frames, work, guides, opts, rng, bar, info.stage_seconds)
    info.energy, info.stage = np.array(energies), np.arange(levels)
    count = image.shape[2]
    info.levels = [m.with_colors(np.clip(values[level][:, :count], 0, 1)) for level, m in enumerate(hierarchy)]
    out = info.levels[0]
    info.field, info.guide, info.sources = frames[0].t, given[0], sources
    info.seconds = time.perf_counter() - start
    return (out, info) if return_info else out


# --------------------------------------------------------------------------- evaluation
def curve_alignment(mesh, curves, *, max_distance=3.0):
    """The mean angle in degrees between a textured surface's dominant orientation along each curve and the curve.

    Examples
    --------
    >>> import numpy as np, texsynth
    >>> from texsynth.surface import SalientCurves, curve_alignment
    >>> ball = texsynth.surface.sphere(2562)
    >>> ring = np.flatnonzero(np.abs(ball.vertices[:, 2]) < 0.05)
    >>> along = np.cross([0, 0, 1.0], ball.vertices[ring])
    >>> curves = SalientCurves(ring, along / np.linalg.norm(along, axis=1, keepdims=True), np.zeros(len(ring), int),
    ...                        np.zeros(len(ring), int), ball.vertices[ring])
    >>> latitude = ball.with_colors(0.5 + 0.5 * np.sin(12 * ball.vertices[:, 2:]))      # stripes along the ring
    >>> meridian = ball.with_colors(0.5 + 0.5 * np.sin(12 * np.arctan2(*ball.vertices[:, :2].T))[:, None])
    >>> round(curve_alignment(latitude, curves)), round(curve_alignment(meridian, curves))  # along, across
    (0, 90)

    Every vertex within ``max_distance`` vertex spacings of a curve gets the
    gradient of the colours' mean by a least-squares plane through its 12
    nearest vertices in its tangent plane; the texture there runs across
    the gradient (``n x grad``), at an angle ``a`` to the nearest curve
    vertex's tangent. The texture's dominant orientation along a curve is
    the direction of the resultant of ``exp(2 i a)`` over the vertices
    nearest to that curve, weighted by ``|grad|^2`` (the structure tensor's
    energy; as :func:`texsynth.metrics.dominant_orientation` averages
    orientations on the doubled-angle circle, so a brick wall's vertical
    joints weaken its horizontal orientation but do not turn it); the result
    is the mean of its angle, folded into [0, 90], over the curves, weighted
    by their energy. 0: the texture runs along the curves; 90: across them.

    Parameters
    ----------
    mesh : Mesh
        A surface with per-vertex colours (e.g. the output of
        :func:`feature_aligned_surface`).
    curves : SalientCurves
        The curves (their ``points`` and ``tangents``).
    max_distance : float
        Vertices up to this many vertex spacings (mean edge lengths) from a
        curve count.

    Returns
    -------
    float
        Degrees in [0, 90].
    """
    mesh = as_mesh(mesh)
    if mesh.colors is None:
        raise ValueError("mesh has no vertex colours; pass a textured surface (e.g. feature_aligned_surface's output)")
    if not isinstance(curves, SalientCurves) or len(curves.points) == 0:
        raise TypeError("curves must be a SalientCurves with at least one vertex (salient_curves(mesh))")
    max_distance = check_positive_float(max_distance, "max_distance")
    points, normals = mesh.vertices, mesh.vertex_normals
    spacing = mesh.mean_edge_length
    dist, nearest = point_tree(curves.points).query(points)
    rows = np.flatnonzero(dist <= max_distance * spacing)
    if len(rows) == 0:
        raise ValueError("no vertex of mesh lies near the curves; pass the curves of this surface or a larger "
                         "max_distance")
    value = np.asarray(mesh.colors, np.float64).mean(axis=1)
    _, near = point_tree(points).query(points[rows], k=min(_QUADRIC_NEIGHBORS + 1, len(points)))
    e1, e2 = tangent_frames(normals[rows])
    rel = points[near] - points[rows, None, :]
    design = np.stack([np.einsum("nkd,nd->nk", rel, e1), np.einsum("nkd,nd->nk", rel, e2),
                       np.ones(near.shape)], axis=-1)
    gram = np.einsum("nki,nkj->nij", design, design) + 1e-12 * np.eye(3) * spacing ** 2
    coef = np.linalg.solve(gram, np.einsum("nki,nk->ni", design, value[near])[..., None])[..., 0]
    grad = coef[:, :1] * e1 + coef[:, 1:2] * e2
    along = np.cross(normals[rows], grad)
    energy = np.einsum("ij,ij->i", grad, grad)
    tangent = curves.tangents[nearest[rows]]
    side = np.cross(normals[rows], tangent)
    a = np.arctan2(np.einsum("ij,ij->i", along, side), np.einsum("ij,ij->i", along, tangent))
    # the dominant orientation along each curve: the resultant over the vertices nearest to it
    owner = curves.labels[nearest[rows]]
    k = curves.n_curves
    resultant = (np.bincount(owner, energy * np.cos(2 * a), minlength=k)
                 + 1j * np.bincount(owner, energy * np.sin(2 * a), minlength=k))
    angle = np.abs(np.degrees(np.angle(resultant)) / 2)
    weight = np.bincount(owner, energy, minlength=k)
    return float(np.sum(angle * weight) / max(float(weight.sum()), 1e-300))
