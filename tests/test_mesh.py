"""texsynth.surface's Mesh (texsynth.surface._mesh): its arrays, derived geometry and the checks of as_mesh."""

import warnings

import numpy as np
import pytest
import scipy.sparse

from texsynth.surface import Mesh, as_mesh

# a tetrahedron, faces counter-clockwise seen from outside
TETRA_V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [0, 0, 1]], dtype=float)
TETRA_F = np.array([[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]])


def tetra(**kwargs):
    return Mesh(TETRA_V, TETRA_F, **kwargs)


# ---------------------------------------------------------------------------- Mesh
def test_mesh_stores_arrays_read_only_with_the_documented_dtypes():
    mesh = Mesh(TETRA_V.astype(np.float32), TETRA_F.astype(np.int32), colors=np.full((4, 3), 255, np.uint8))
    assert mesh.vertices.dtype == np.float64 and mesh.faces.dtype == np.int64
    assert mesh.colors.dtype == np.float32 and np.all(mesh.colors == 1)
    with pytest.raises(ValueError, match="read-only"):
        mesh.vertices[0, 0] = 5
    assert repr(mesh) == "Mesh(4 vertices, 4 faces, colors 3 channels)"


def test_face_normals_and_areas_of_the_tetrahedron():
    mesh = tetra()
    np.testing.assert_allclose(mesh.face_areas, [0.5, 0.5, 0.5, np.sqrt(3) / 2])
    np.testing.assert_allclose(mesh.face_normals, [[0, 0, -1], [0, -1, 0], [-1, 0, 0], np.ones(3) / np.sqrt(3)],
                               atol=1e-12)
    # outward: each face normal points away from the centroid
    centre = TETRA_V.mean(axis=0)
    to_face = TETRA_V[TETRA_F].mean(axis=1) - centre
    assert np.all(np.sum(to_face * mesh.face_normals, axis=1) > 0)


def test_vertex_normals_are_area_weighted():
    mesh = tetra()
    # vertex 1 touches faces 0 (normal -z, area 1/2), 1 (-y, 1/2) and 3 ((1,1,1)/sqrt3, sqrt3/2):
    # the weighted sum is (1/2, 0, 0), so the unit normal is +x
    np.testing.assert_allclose(mesh.vertex_normals[1], [1, 0, 0], atol=1e-12)
    np.testing.assert_allclose(mesh.vertex_normals[0], -np.ones(3) / np.sqrt(3), atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(mesh.vertex_normals, axis=1), 1)


def test_edges_and_adjacency():
    mesh = tetra()
    assert mesh.edges.tolist() == [[0, 1], [0, 2], [0, 3], [1, 2], [1, 3], [2, 3]]
    adjacency = mesh.vertex_adjacency
    assert scipy.sparse.issparse(adjacency) and adjacency.format == "csr" and adjacency.shape == (4, 4)
    np.testing.assert_array_equal(adjacency.toarray(), 1 - np.eye(4))
    # edge k of a face joins corners k and k+1; the face across shares exactly that vertex pair
    across = mesh.face_adjacency
    assert across.dtype == np.int64 and across.shape == (4, 3)
    for f in range(4):
        for k in range(3):
            edge = {TETRA_F[f, k], TETRA_F[f, (k + 1) % 3]}
            g = across[f, k]
            assert g != f and edge <= set(TETRA_F[g])
    np.testing.assert_allclose(mesh.mean_edge_length, (3 + 3 * np.sqrt(2)) / 6)
    np.testing.assert_array_equal(mesh.bounds, [[0, 0, 0], [1, 1, 1]])


def test_face_adjacency_is_minus_one_on_a_boundary():
    # two triangles sharing the diagonal of a square
    mesh = Mesh([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0]], [[0, 1, 2], [0, 2, 3]])
    assert mesh.face_adjacency.tolist() == [[-1, -1, 1], [0, -1, -1]]


def test_with_colors_and_with_texture_keep_the_geometry_caches():
    mesh = tetra()
    normals = mesh.face_normals
    red = mesh.with_colors(np.tile([1.0, 0, 0], (4, 1)))
    assert red.face_normals is normals and red.colors.shape == (4, 3) and mesh.colors is None
    uv = np.zeros((4, 3, 2))
    textured = red.with_texture(uv, np.zeros((2, 2, 3)))
    assert textured.texture.shape == (2, 2, 3) and textured.face_normals is normals


def test_compact_and_select_faces():
    mesh = Mesh(np.vstack([TETRA_V, [[9, 9, 9]]]), TETRA_F + (TETRA_F >= 2),  # vertex 2 unused
                colors=np.linspace(0, 1, 5)[:, None])
    small = mesh.compact()
    np.testing.assert_array_equal(small.vertices, np.delete(mesh.vertices, 2, axis=0))
    np.testing.assert_array_equal(small.vertices[small.faces], mesh.vertices[mesh.faces])
    np.testing.assert_allclose(small.colors[:, 0], np.delete(np.linspace(0, 1, 5), 2), atol=1e-7)
    mesh = tetra(uv=np.arange(24.0).reshape(4, 3, 2) / 24)
    assert mesh.compact() is mesh  # nothing to drop: the mesh itself
    two = mesh.select_faces([1, 3])
    np.testing.assert_array_equal(two.faces, TETRA_F[[1, 3]])
    np.testing.assert_array_equal(two.uv, mesh.uv[[1, 3]])


# ---------------------------------------------------------------------------- as_mesh
def test_as_mesh_accepts_a_mesh_and_a_pair():
    mesh = tetra()
    assert as_mesh(mesh) is mesh
    pair = as_mesh((TETRA_V, TETRA_F))
    np.testing.assert_array_equal(pair.faces, TETRA_F)


@pytest.mark.parametrize("value, error, message", [
    (([], []), ValueError, r"surface is empty \(0 vertices, 0 faces\)"),
    ((TETRA_V, np.zeros((0, 3), int)), ValueError, r"surface is empty \(4 vertices, 0 faces\)"),
    ((np.vstack([TETRA_V[:3], [[np.nan, 0, 0]]]), TETRA_F), ValueError,
     r"1 vertices with NaN or infinite coordinates \(first: vertex 3\)"),
    ((TETRA_V, np.vstack([TETRA_F, [[1, 2, 4]], [[-1, 0, 2]]])), ValueError,
     r"surface has 2 faces with vertex indices outside 0\.\.3 \(first: face 4 = \[1, 2, 4\]\)"),
    ((TETRA_V, np.vstack([TETRA_F, [[1, 1, 2]]])), ValueError,
     r"1 faces of zero area \(first: face 4 = \[1, 1, 2\]\); drop them with surface\.select_faces"),
    ((np.vstack([TETRA_V, [[2, 0, 0]]]), np.vstack([TETRA_F, [[0, 1, 4]]])), ValueError,
     r"1 faces of zero area \(first: face 4"),  # collinear corners
    ((np.vstack([TETRA_V, [[5, 5, 5], [6, 6, 6]]]), TETRA_F), ValueError,
     r"surface has 2 isolated vertices .* \(first: vertex 4\); remove the unused vertices with surface\.compact\(\)"),
    ((np.vstack([TETRA_V, [[1, 1, 1]]]), np.vstack([TETRA_F, [[1, 2, 4]]])), ValueError,
     r"surface has 1 non-manifold edges shared by more than two faces \(first: edge \(1, 2\) of faces \[0, 3, 4\]\)"),
    ((TETRA_V[:, :2], TETRA_F), ValueError, r"surface: vertices must have shape \(N, 3\)"),
    ((TETRA_V, TETRA_F.astype(float)), TypeError, r"surface: faces must be integer vertex indices"),
    ((TETRA_V, np.zeros((2, 4), int)), ValueError, r"faces must have shape \(M, 3\).*triangulated"),
    (TETRA_V, TypeError, r"surface must be a texsynth\.surface\.Mesh, a \(vertices, faces\) pair"),
    (None, TypeError, r"surface must be a texsynth\.surface\.Mesh"),
])
def test_as_mesh_refuses_bad_meshes_with_the_fix(value, error, message):
    with pytest.raises(error, match=message):
        as_mesh(value, "surface")


def test_the_suggested_fixes_work():
    bad = Mesh(np.vstack([TETRA_V, [[5, 5, 5]]]), np.vstack([TETRA_F, [[1, 1, 2]]]))
    with pytest.raises(ValueError, match="zero area"):
        as_mesh(bad)
    fixed = as_mesh(bad.select_faces(bad.face_areas > 0).compact())
    np.testing.assert_array_equal(fixed.faces, TETRA_F)


def test_inconsistent_orientation_is_a_warning_with_a_fix():
    flipped = TETRA_F.copy()
    flipped[3] = flipped[3, ::-1]
    with pytest.warns(UserWarning, match=r"surface's faces are not consistently oriented: 3 edges .* "
                                         r"\(first: edge \(1, 2\) of faces 0 and 3\)"):
        mesh = as_mesh((TETRA_V, flipped), "surface")
    import trimesh

    repaired = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False)
    trimesh.repair.fix_winding(repaired)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        as_mesh((repaired.vertices, repaired.faces))


@pytest.mark.parametrize("kwargs, message", [
    ({"colors": np.zeros((3, 3))}, r"colors must have shape \(N, C\) = \(4, 1\.\.4\)"),
    ({"colors": np.full((4, 3), 2.0)}, r"colors is floating point with values in \[2, 2\]"),
    ({"uv": np.zeros((4, 2))}, r"uv must have shape \(M, 3, 2\) = \(4, 3, 2\)"),
    ({"uv": np.full((4, 3, 2), np.inf)}, r"uv contains NaN or infinite values"),
    ({"texture": np.zeros((4, 4))}, r"texture needs uv coordinates"),
    ({"uv": np.zeros((4, 3, 2)), "texture": np.zeros(4)}, r"texture must have shape \(H, W\)"),
])
def test_mesh_refuses_bad_attributes(kwargs, message):
    with pytest.raises(ValueError, match=message):
        tetra(**kwargs)
