"""A closed triangle mesh as a signed distance volume: the way a mesh file enters geometry synthesis.

Voxel centres are classified inside or outside by ray parity: a vertical ray
(along the volume's depth, the meshes' ``z``) from a centre up to infinity
crosses a closed surface an odd number of times exactly when the centre is
inside. All crossings of all columns are found at once: each triangle is
tested against the voxel columns under its bounding box (barycentric
coordinates in ``(x, y)``), the height of each crossing is binned among the
column's voxel centres, and a reversed cumulative sum counts the crossings
above every voxel. A column crossed an odd number of times in all passes
through a hole in the surface: the mesh is then refused as not closed (a hole
between the columns, smaller than a voxel, is not seen and does no harm). The occupancy becomes
a distance volume by :func:`as_distance_field` (two Euclidean distance
transforms), so the surface is placed to within half a voxel.

The columns are shifted by a small irrational fraction of a voxel so that no
ray passes exactly through a vertex or an edge of a mesh built on a grid (a
ray through a shared edge would count its two triangles twice).
"""

from __future__ import annotations

import numpy as np

from ..core._validate import as_array, check_memory, check_positive_int
from ._lagae import as_distance_field

__all__ = ["mesh_to_sdf"]

#: Columns are shifted by these fractions of a voxel (x, y), away from any grid a mesh is built on.
_JITTER = (np.sqrt(2.0) * 1e-4, np.sqrt(3.0) * 1e-4)


def _as_vertices_faces(mesh):
    """``(vertices (N, 3) float64, faces (M, 3) int64)`` of a mesh object or a ``(vertices, faces)`` pair."""
    if hasattr(mesh, "vertices") and hasattr(mesh, "faces"):
        vertices, faces = mesh.vertices, mesh.faces
    elif isinstance(mesh, (tuple, list)) and len(mesh) == 2:
        vertices, faces = mesh
    else:
        raise TypeError(f"mesh must be a Mesh or a (vertices, faces) pair, got {type(mesh).__name__}")
    vertices = as_array(vertices, "mesh vertices")
    faces = as_array(faces, "mesh faces")
    if vertices.ndim != 2 or vertices.shape[1] != 3 or not np.issubdtype(vertices.dtype, np.number):
        raise ValueError(f"mesh vertices must be an (N, 3) array of positions, got shape {vertices.shape}")
    vertices = vertices.astype(np.float64)
    if not np.all(np.isfinite(vertices)):
        raise ValueError("mesh vertices contain NaN or infinite values")
    if faces.ndim != 2 or faces.shape[1] != 3 or len(faces) == 0 or not np.issubdtype(faces.dtype, np.integer):
        raise ValueError(f"mesh faces must be a non-empty (M, 3) array of vertex indices, got shape {faces.shape} "
                         f"and dtype {faces.dtype}")
    if faces.min() < 0 or faces.max() >= len(vertices):
        raise ValueError(f"mesh faces index vertices 0..{len(vertices) - 1}, got indices {int(faces.min())}.."
                         f"{int(faces.max())}")
    return vertices, faces.astype(np.int64)


def mesh_to_sdf(mesh, voxels=48, *, margin=0):
    """A closed mesh as a signed distance volume for :func:`synthesize_geometry`, and where its voxels lie.

    Examples
    --------
    >>> import texsynth.geometry
    >>> vertices, faces = texsynth.geometry.sdf_to_mesh(texsynth.data.volume("pebbles", 32))
    >>> sdf, spacing, origin = texsynth.geometry.mesh_to_sdf((vertices, faces), 32)
    >>> sdf.ndim, bool((sdf < 0).any() and (sdf > 0).any())
    (3, True)

    Parameters
    ----------
    mesh : Mesh or (vertices, faces)
        A closed (watertight) triangle mesh: a :class:`texsynth.surface.Mesh`
        (e.g. from :func:`texsynth.read_mesh`) or a pair of arrays, positions
        ``(N, 3)`` as ``(x, y, z)`` and vertex indices ``(M, 3)``.
    voxels : int
        Voxels along the longest side of the mesh's bounding box; the other
        sides get as many voxels of the same size as they need.
    margin : int
        Voxels of outside added around the bounding box on every side (0:
        the volume is the bounding box, as an example tile whose shape
        reaches its sides should be).

    Returns
    -------
    sdf : numpy.ndarray
        float64 ``(depth, height, width)`` distances in voxels, negative
        inside; depth runs along ``z``, width along ``x``.
    spacing : float
        The side of a voxel in the mesh's units.
    origin : numpy.ndarray
        ``(x, y, z)`` of the centre of voxel ``[0, 0, 0]``: a mesh from
        ``sdf_to_mesh(sdf, spacing=spacing)`` plus ``origin`` lies where the
        input did.

    Raises
    ------
    ValueError
        If the mesh is not closed (a column of voxels crosses its surface an
        odd number of times), is flat, or the volume will not fit in memory.
    """
    vertices, faces = _as_vertices_faces(mesh)
    voxels = check_positive_int(voxels, "voxels", minimum=2)
    margin = check_positive_int(margin, "margin", minimum=0)
    low, high = vertices[np.unique(faces)].min(axis=0), vertices[np.unique(faces)].max(axis=0)
    extent = high - low
    if extent.max() <= 0:
        raise ValueError("mesh is a single point; it has no inside to measure")
    spacing = float(extent.max()) / voxels
    cells = np.maximum(np.ceil(extent / spacing - 1e-9).astype(np.int64), 1)  # (x, y, z)
    shape = (int(cells[2]) + 2 * margin, int(cells[1]) + 2 * margin, int(cells[0]) + 2 * margin)
    # occupancy, crossing counts and the two distance transforms: about 40 bytes a voxel
    check_memory(40 * int(np.prod(shape)), voxels, "voxels", "the distance volume")
    origin = low - (cells * spacing - extent) / 2 + spacing / 2 - margin * spacing  # centre of voxel [0, 0, 0]
    inside = _ray_parity(vertices, faces, shape, spacing, origin, voxels)
    return as_distance_field(inside), spacing, origin


def _ray_parity(vertices, faces, shape, spacing, origin, voxels):
    """Occupancy ``(D, H, W)`` of the voxel centres by the parity of the crossings above them."""
    depth, height, width = shape
    grid = (vertices - origin) / spacing  # voxel index units: centre of voxel (k, j, i) at (i, j, k)
    grid[:, 0] -= _JITTER[0]
    grid[:, 1] -= _JITTER[1]
    tri = grid[faces]  # (M, 3 corners, 3)
    i0 = np.clip(np.ceil(tri[:, :, 0].min(axis=1)), 0, width).astype(np.int64)
    i1 = np.clip(np.floor(tri[:, :, 0].max(axis=1)) + 1, 0, width).astype(np.int64)
    j0 = np.clip(np.ceil(tri[:, :, 1].min(axis=1)), 0, height).astype(np.int64)
    j1 = np.clip(np.floor(tri[:, :, 1].max(axis=1)) + 1, 0, height).astype(np.int64)
    ni, nj = np.maximum(i1 - i0, 0), np.maximum(j1 - j0, 0)
    count = ni * nj  # columns under each triangle's bounding box
    pairs = int(count.sum())
    check_memory(96 * pairs, voxels, "voxels", "the mesh's triangle-column tests")
    above = np.zeros((height, width, depth + 1), np.int64)
    if pairs:
        t = np.repeat(np.arange(len(faces)), count)
        local = np.arange(pairs) - np.repeat(np.cumsum(count) - count, count)
        i = i0[t] + local % ni[t]
        j = j0[t] + local // ni[t]
        a, b, c = tri[t, 0], tri[t, 1], tri[t, 2]
        # barycentric coordinates of the column (i, j) in the triangle's (x, y) projection
        det = (b[:, 1] - c[:, 1]) * (a[:, 0] - c[:, 0]) + (c[:, 0] - b[:, 0]) * (a[:, 1] - c[:, 1])
        with np.errstate(divide="ignore", invalid="ignore"):
            la = ((b[:, 1] - c[:, 1]) * (i - c[:, 0]) + (c[:, 0] - b[:, 0]) * (j - c[:, 1])) / det
            lb = ((c[:, 1] - a[:, 1]) * (i - c[:, 0]) + (a[:, 0] - c[:, 0]) * (j - c[:, 1])) / det
            lc = 1.0 - la - lb
        hit = (det != 0) & (la >= 0) & (lb >= 0) & (lc >= 0)
        z = la[hit] * a[hit, 2] + lb[hit] * b[hit, 2] + lc[hit] * c[hit, 2]
        # a crossing at height z lies above the voxel centres k < z: bin it at the first centre above it
        level = np.clip(np.floor(z).astype(np.int64) + 1, 0, depth)
        np.add.at(above, (j[hit], i[hit], level), 1)
    total = above.sum(axis=2)
    if np.any(total % 2):
        j, i = np.argwhere(total % 2)[0]
        raise ValueError(f"mesh is not closed: the vertical line at x={origin[0] + i * spacing:.4g}, "
                         f"y={origin[1] + j * spacing:.4g} crosses its surface an odd number of times; "
                         "close its holes (or pass a voxel volume)")
    # crossings above voxel k: those binned at levels k + 1 and higher
    crossings = np.cumsum(above[:, :, :0:-1], axis=2)[:, :, ::-1]
    return np.ascontiguousarray(np.moveaxis(crossings % 2 == 1, 2, 0))
