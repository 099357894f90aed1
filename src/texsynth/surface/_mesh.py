"""The triangle mesh every surface method works on, and its validation.

A :class:`Mesh` is an indexed triangle list with optional per-vertex colours
or a texture image indexed by per-face-corner uv coordinates. It is immutable
(its arrays are read-only), so derived quantities -- normals, areas, edges,
adjacency -- are computed once on first use and cached.

:func:`~texsynth.surface.as_mesh` is the public boundary (in
``_meshio``, since it also reads a file path; :func:`checked` here does the
rest): it accepts a :class:`Mesh`, a ``(vertices, faces)`` pair or a file
path, and refuses meshes the surface
methods cannot work on (empty, NaN coordinates, out-of-range indices,
zero-area faces, unused vertices, edges shared by more than two faces) with a
ValueError that names the parameter, counts the offenders, gives the first one
and says how to fix it. Faces whose orientations disagree across an edge get a
warning (the normals flip there) rather than an error.
"""

from __future__ import annotations

import dataclasses
import warnings
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import scipy.sparse

from ..core._validate import as_array, as_float_array, as_image

__all__ = ["Mesh", "checked"]

# a face is degenerate when twice its area is below this fraction of the squared bounding-box diagonal
_DEGENERATE_AREA = 1e-14
# cached properties that depend on the geometry only (kept by with_colors / with_texture)
_GEOMETRY_CACHE = ("_cross", "face_normals", "face_areas", "vertex_normals", "edges", "vertex_adjacency",
                   "face_adjacency", "mean_edge_length", "bounds", "_edge_faces", "_edge_pairs", "_same_direction",
                   "_checked")


def _frozen(array):
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class Mesh:
    """A triangle mesh, optionally coloured per vertex or textured through uv coordinates.

    Parameters
    ----------
    vertices : array_like, shape (N, 3)
        Vertex positions; stored as float64.
    faces : array_like of int, shape (M, 3)
        Vertex indices of each triangle, counter-clockwise seen from outside
        (so that :attr:`face_normals` point outwards); stored as int64.
    colors : array_like, shape (N, C), optional
        One colour per vertex, ``C`` in 1..4 channels, converted like an image
        (uint8 / uint16 / bool / float in [0, 1]) and stored as float32.
    uv : array_like, shape (M, 3, 2), optional
        Texture coordinates of each face corner, ``(u, v)`` with ``v`` pointing
        up (the OBJ convention: ``v = 0`` is the bottom row of ``texture``).
        Coordinates outside [0, 1] repeat the texture, as OBJ viewers do.
    texture : array_like, shape (h, w[, C]), optional
        The image ``uv`` indexes; needs ``uv``.

    Notes
    -----
    The constructor checks shapes and types only; :func:`as_mesh` also checks
    the values and the topology, and every public function of
    :mod:`texsynth.surface` calls it. The arrays are made read-only, so a
    mesh never changes after its cached properties were computed; derive a
    new mesh with :meth:`with_colors`, :meth:`with_texture`,
    :meth:`select_faces` or :meth:`compact`.

    Examples
    --------
    >>> tetra = Mesh([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]],
    ...              [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])
    >>> tetra
    Mesh(4 vertices, 4 faces)
    >>> tetra.edges.shape, tetra.face_adjacency[0].tolist()
    ((6, 2), [2, 3, 1])
    """

    vertices: np.ndarray
    faces: np.ndarray
    colors: np.ndarray | None = None
    uv: np.ndarray | None = None
    texture: np.ndarray | None = None

    def __post_init__(self):
        vertices = as_array(self.vertices, "vertices")
        if vertices.size == 0 and vertices.ndim <= 2:
            vertices = vertices.reshape(0, 3)
        if vertices.ndim != 2 or vertices.shape[1] != 3:
            raise ValueError(f"vertices must have shape (N, 3), one (x, y, z) row per vertex, got shape "
                             f"{vertices.shape}")
        if not (np.issubdtype(vertices.dtype, np.floating) or np.issubdtype(vertices.dtype, np.integer)):
            raise TypeError(f"vertices must be real numbers, got dtype {vertices.dtype}")
        faces = as_array(self.faces, "faces")
        if faces.size == 0 and faces.ndim <= 2:
            faces = faces.reshape(0, 3).astype(np.int64)
        if faces.ndim != 2 or faces.shape[1] != 3:
            hint = (" (polygons with more corners must be triangulated first; read_mesh does this for files)"
                    if faces.ndim == 2 and faces.shape[1] > 3 else "")
            raise ValueError(f"faces must have shape (M, 3), three vertex indices per triangle, got shape "
                             f"{faces.shape}{hint}")
        if not np.issubdtype(faces.dtype, np.integer):
            raise TypeError(f"faces must be integer vertex indices, got dtype {faces.dtype}; "
                            "convert with faces.astype(np.int64) if they are whole numbers")
        object.__setattr__(self, "vertices", _frozen(np.array(vertices, dtype=np.float64)))
        object.__setattr__(self, "faces", _frozen(np.array(faces, dtype=np.int64)))
        n, m = len(self.vertices), len(self.faces)
        if self.colors is not None:
            colors = as_array(self.colors, "colors")
            if colors.ndim != 2 or colors.shape[0] != n or not 1 <= colors.shape[1] <= 4:
                raise ValueError(f"colors must have shape (N, C) = ({n}, 1..4), one colour per vertex, got shape "
                                 f"{colors.shape}")
            object.__setattr__(self, "colors", _frozen(as_float_array(colors, "colors").astype(np.float32)))
        if self.uv is not None:
            uv = as_array(self.uv, "uv")
            if uv.shape != (m, 3, 2):
                raise ValueError(f"uv must have shape (M, 3, 2) = ({m}, 3, 2), a (u, v) pair per face corner, "
                                 f"got shape {uv.shape}")
            if not np.issubdtype(uv.dtype, np.number) or np.iscomplexobj(uv):
                raise TypeError(f"uv must be real numbers, got dtype {uv.dtype}")
            uv = np.array(uv, dtype=np.float64)
            if not np.all(np.isfinite(uv)):
                raise ValueError("uv contains NaN or infinite values; every face corner needs finite (u, v)")
            object.__setattr__(self, "uv", _frozen(uv))
        if self.texture is not None:
            if self.uv is None:
                raise ValueError("texture needs uv coordinates (uv=, shape (M, 3, 2)) telling where each face "
                                 "corner lies in it; pass both, e.g. mesh.with_texture(uv, texture)")
            object.__setattr__(self, "texture", _frozen(as_image(self.texture, "texture")))

    def __repr__(self):
        parts = [f"{len(self.vertices)} vertices", f"{len(self.faces)} faces"]
        if self.colors is not None:
            parts.append(f"colors {self.colors.shape[1]} channel{'s' if self.colors.shape[1] > 1 else ''}")
        if self.texture is not None:
            parts.append(f"texture {self.texture.shape[1]}x{self.texture.shape[0]}")
        elif self.uv is not None:
            parts.append("uv")
        return f"Mesh({', '.join(parts)})"

    # ------------------------------------------------------------------ geometry
    @cached_property
    def _cross(self):
        v = self.vertices[self.faces]
        return np.cross(v[:, 1] - v[:, 0], v[:, 2] - v[:, 0])

    @cached_property
    def face_areas(self):
        """(M,) float64: the area of each triangle."""
        return _frozen(0.5 * np.linalg.norm(self._cross, axis=1))

    @cached_property
    def face_normals(self):
        """(M, 3) float64: unit normal of each triangle (right-hand rule on its corners; zero if degenerate)."""
        length = 2.0 * self.face_areas[:, None]
        return _frozen(np.divide(self._cross, length, out=np.zeros_like(self._cross), where=length > 0))

    @cached_property
    def vertex_normals(self):
        """(N, 3) float64: unit vertex normals, the area-weighted mean of the adjacent face normals."""
        total = np.zeros_like(self.vertices)
        for k in range(3):  # the cross product is the normal times twice the area: area weighting for free
            np.add.at(total, self.faces[:, k], self._cross)
        length = np.linalg.norm(total, axis=1, keepdims=True)
        return _frozen(np.divide(total, length, out=np.zeros_like(total), where=length > 0))

    @cached_property
    def _edge_faces(self):
        """Half-edges grouped by undirected edge: (edge key per half-edge, sort order)."""
        a = self.faces
        b = np.roll(self.faces, -1, axis=1)  # half-edge k runs from corner k to corner k + 1
        keys = np.minimum(a, b) * np.int64(max(len(self.vertices), 1)) + np.maximum(a, b)
        keys = keys.ravel()
        order = np.argsort(keys, kind="stable")
        return keys, order

    @cached_property
    def edges(self):
        """(E, 2) int64: each undirected edge once, as ``(i, j)`` with ``i < j``, sorted."""
        keys = np.unique(self._edge_faces[0])
        n = np.int64(max(len(self.vertices), 1))
        return _frozen(np.stack([keys // n, keys % n], axis=1))

    @cached_property
    def vertex_adjacency(self):
        """(N, N) ``scipy.sparse.csr_matrix`` of float64: 1 where two vertices share an edge, else 0; symmetric."""
        i, j = self.edges.T
        n = len(self.vertices)
        data = np.ones(2 * len(i))  # float64: products and Laplacians need no cast
        return scipy.sparse.csr_matrix((data, (np.concatenate([i, j]), np.concatenate([j, i]))), shape=(n, n))

    @cached_property
    def face_adjacency(self):
        """(M, 3) int64: the face across edge ``k`` (corners ``k``, ``k + 1``) of each face, -1 on a boundary.

        Defined for meshes whose edges have at most two faces (:func:`as_mesh` checks this).
        """
        first, second = self._edge_pairs
        across = np.full(3 * len(self.faces), -1, dtype=np.int64)
        across[first] = second // 3
        across[second] = first // 3
        return _frozen(across.reshape(-1, 3))

    @cached_property
    def _edge_pairs(self):
        """The two half-edges (indices into ``faces.ravel()``) of each edge that has two faces."""
        keys, order = self._edge_faces
        sorted_keys = keys[order]
        pair = np.nonzero(sorted_keys[1:] == sorted_keys[:-1])[0]
        return order[pair], order[pair + 1]

    @cached_property
    def _same_direction(self):
        """Bool per two-face edge: both faces run along it the same way (their orientations disagree)."""
        first, second = self._edge_pairs
        return self.faces.ravel()[first] == self.faces.ravel()[second]

    @cached_property
    def mean_edge_length(self):
        """float: the mean length of the undirected edges."""
        i, j = self.edges.T
        return float(np.linalg.norm(self.vertices[i] - self.vertices[j], axis=1).mean()) if len(i) else 0.0

    @cached_property
    def bounds(self):
        """(2, 3) float64: the lowest and highest corner of the axis-aligned bounding box."""
        return _frozen(np.stack([self.vertices.min(axis=0), self.vertices.max(axis=0)]))

    # ------------------------------------------------------------------ derived meshes
    def _derive(self, **changes):
        mesh = dataclasses.replace(self, **changes)
        if "vertices" not in changes and "faces" not in changes:
            mesh.__dict__.update({k: v for k, v in self.__dict__.items() if k in _GEOMETRY_CACHE})
        return mesh

    def with_colors(self, colors):
        """A copy with per-vertex ``colors`` (N, C) instead of this mesh's colours (geometry caches kept)."""
        return self._derive(colors=colors)

    def with_texture(self, uv, texture):
        """A copy textured by ``texture`` through per-face-corner ``uv`` (M, 3, 2) (geometry caches kept)."""
        return self._derive(uv=uv, texture=texture)

    def select_faces(self, keep):
        """A copy with only the faces ``keep`` (a boolean mask of length M or face indices), uv kept along.

        Vertices are kept too; follow with :meth:`compact` to drop the ones no face uses any more.
        """
        keep = np.asarray(keep)
        uv = None if self.uv is None else self.uv[keep]
        return dataclasses.replace(self, faces=self.faces[keep], uv=uv)

    def compact(self):
        """A copy without the vertices no face uses (their colours dropped too, faces renumbered)."""
        used = np.zeros(len(self.vertices), dtype=bool)
        used[self.faces.ravel()] = True
        if used.all():
            return self
        new_index = np.cumsum(used) - 1
        colors = None if self.colors is None else self.colors[used]
        return dataclasses.replace(self, vertices=self.vertices[used], faces=new_index[self.faces], colors=colors)


# ---------------------------------------------------------------------------- validation
def _first(mask):
    return int(np.flatnonzero(mask)[0])


def _check(mesh, name):
    """The value and topology checks of :func:`as_mesh` (ValueError naming ``name``)."""
    n, m = len(mesh.vertices), len(mesh.faces)
    if n == 0 or m == 0:
        raise ValueError(f"{name} is empty ({n} vertices, {m} faces); pass a mesh with at least one triangle")
    bad = ~np.all(np.isfinite(mesh.vertices), axis=1)
    if bad.any():
        raise ValueError(f"{name} has {int(bad.sum())} vertices with NaN or infinite coordinates (first: vertex "
                         f"{_first(bad)}); remove or repair them before calling")
    out = np.any((mesh.faces < 0) | (mesh.faces >= n), axis=1)
    if out.any():
        f = _first(out)
        raise ValueError(f"{name} has {int(out.sum())} faces with vertex indices outside 0..{n - 1} (first: face "
                         f"{f} = {mesh.faces[f].tolist()}); indices count from 0 (OBJ files count from 1: "
                         "read them with texsynth.surface.read_mesh)")
    diagonal = float(np.linalg.norm(np.ptp(mesh.vertices, axis=0)))
    degenerate = 2.0 * mesh.face_areas <= _DEGENERATE_AREA * diagonal ** 2
    if degenerate.any():
        f = _first(degenerate)
        raise ValueError(f"{name} has {int(degenerate.sum())} faces of zero area (first: face {f} = "
                         f"{mesh.faces[f].tolist()}); drop them with "
                         f"{name}.select_faces({name}.face_areas > 0).compact(), or repair the mesh")
    used = np.zeros(n, dtype=bool)
    used[mesh.faces.ravel()] = True
    if not used.all():
        raise ValueError(f"{name} has {int((~used).sum())} isolated vertices that no face uses (first: vertex "
                         f"{_first(~used)}); remove the unused vertices with {name}.compact()")
    keys, order = mesh._edge_faces
    _, first, counts = np.unique(keys[order], return_index=True, return_counts=True)
    crowded = counts > 2
    if crowded.any():
        k = int(np.flatnonzero(crowded)[0])
        half = order[first[k]]
        a, b = mesh.faces.ravel()[half], np.roll(mesh.faces, -1, axis=1).ravel()[half]
        faces = sorted(int(h) // 3 for h in order[first[k]:first[k] + counts[k]])
        raise ValueError(f"{name} has {int(crowded.sum())} non-manifold edges shared by more than two faces "
                         f"(first: edge ({min(a, b)}, {max(a, b)}) of faces {faces}); surface methods need each "
                         "edge on at most two faces: split or repair the mesh (e.g. MeshLab's 'Repair "
                         "non-manifold edges')")
    flipped = mesh._same_direction
    if flipped.any():
        first, second = (h[flipped][0] for h in mesh._edge_pairs)
        a, b = mesh.faces.ravel()[first], np.roll(mesh.faces, -1, axis=1).ravel()[first]
        warnings.warn(f"{name}'s faces are not consistently oriented: {int(flipped.sum())} edges are run the same way "
                      f"by both their faces (first: edge ({min(a, b)}, {max(a, b)}) of faces {first // 3} and "
                      f"{second // 3}), so normals flip between them; reorient the faces coherently (e.g. "
                      "trimesh.repair.fix_winding, or MeshLab's 'Re-Orient all faces coherently')", stacklevel=3)


def checked(value, name="mesh"):
    """:func:`~texsynth.surface.as_mesh` of a :class:`Mesh` or a ``(vertices, faces)`` pair (no path)."""
    if isinstance(value, Mesh):
        mesh = value
    elif isinstance(value, (tuple, list)) and len(value) == 2:
        try:
            mesh = Mesh(*value)
        except (TypeError, ValueError) as exc:
            raise type(exc)(f"{name}: {exc}") from None
    else:
        raise TypeError(f"{name} must be a texsynth.surface.Mesh, a (vertices, faces) pair of arrays or the path "
                        f"of a mesh file, got {type(value).__name__}")
    if "_checked" not in mesh.__dict__:
        _check(mesh, name)
        mesh.__dict__["_checked"] = True
    return mesh
