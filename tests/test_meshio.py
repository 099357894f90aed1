"""Mesh files (texsynth.surface._meshio): read_mesh and write_mesh for OBJ and PLY, other formats through trimesh."""

import warnings

import numpy as np
import pytest

from texsynth.surface import Mesh, as_mesh, read_mesh, sphere, write_mesh

from test_mesh import TETRA_F, TETRA_V


# ---------------------------------------------------------------------------- mesh files
def _decorated(kind):
    mesh = sphere(92)
    rng = np.random.default_rng(0)
    if kind == "colors":
        return mesh.with_colors(rng.random((len(mesh.vertices), 3)))
    if kind == "rgba":
        return mesh.with_colors(rng.random((len(mesh.vertices), 4)))
    if kind == "texture":
        return mesh.with_texture(rng.random((len(mesh.faces), 3, 2)), rng.random((6, 10, 3)))
    return mesh


def _eight_bit(values):
    return np.round(np.asarray(values, np.float64) * 255) / 255


@pytest.mark.parametrize("suffix", [".obj", ".ply"])
@pytest.mark.parametrize("kind", ["plain", "colors", "rgba", "texture"])
def test_round_trip(tmp_path, suffix, kind):
    mesh = _decorated(kind)
    path = write_mesh(tmp_path / f"m{suffix}", mesh)
    back = read_mesh(path)
    np.testing.assert_array_equal(back.vertices, mesh.vertices)  # OBJ: 17 digits, PLY: doubles
    np.testing.assert_array_equal(back.faces, mesh.faces)
    if kind in ("colors", "rgba"):
        if suffix == ".obj":  # v x y z r g b: RGB only, exact
            np.testing.assert_array_equal(back.colors, mesh.colors[:, :3])
        else:  # uchar red green blue [alpha]
            np.testing.assert_allclose(back.colors, _eight_bit(mesh.colors), atol=1e-7)
    else:
        assert back.colors is None
    if kind == "texture":
        np.testing.assert_allclose(back.uv, mesh.uv, atol=0 if suffix == ".obj" else 1e-7)  # PLY texcoord: float
        np.testing.assert_allclose(back.texture, _eight_bit(mesh.texture), atol=1e-12)  # an 8-bit PNG beside it
        beside = sorted(p.name for p in tmp_path.iterdir())
        assert beside == (["m.mtl", "m.obj", "m.png"] if suffix == ".obj" else ["m.ply", "m.png"])
    else:
        assert back.uv is None and back.texture is None


def test_read_obj_with_quads_negative_indices_normals_and_mtl_options(tmp_path):
    from texsynth.io import save_image

    save_image(tmp_path / "checker.png", np.kron([[1, 0], [0, 1]], np.ones((2, 2))))
    (tmp_path / "quad.mtl").write_text("newmtl plain\nKd 1 1 1\nnewmtl checker\nmap_Kd -s 1 1 1 -clamp on checker.png\n")
    (tmp_path / "quad.obj").write_text(
        "# a square as one quad, then a triangle using relative indices\nmtllib quad.mtl\no square\n"
        "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0.5 0.5 1\n"
        "vt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\nusemtl checker\ns off\n"
        "f 1/1/1 2/2/1 3/3/1 4/4/1\nf -4/-3/1 -5/-4/1 -1/-1/1\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # everything is readable: no warning
        mesh = read_mesh(tmp_path / "quad.obj")
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [1, 0, 4]]  # the quad as a fan, in file order
    np.testing.assert_array_equal(mesh.uv[1], [[0, 0], [1, 1], [0, 1]])
    np.testing.assert_array_equal(mesh.uv[2], [[1, 0], [0, 0], [0, 1]])
    assert mesh.texture.shape == (4, 4)


def test_read_obj_with_0_255_vertex_colours_and_missing_texture(tmp_path):
    (tmp_path / "a.mtl").write_text("newmtl m\nmap_Kd gone.png\n")
    (tmp_path / "a.obj").write_text("mtllib a.mtl\nusemtl m\nv 0 0 0 255 0 0\nv 1 0 0 0 255 0\nv 0 1 0 0 0 255\n"
                                    "vt 0 0\nf 1/1 2/1 3/1\n")
    with pytest.warns(UserWarning, match="names the texture 'gone.png', which cannot be read"):
        mesh = read_mesh(tmp_path / "a.obj")
    np.testing.assert_array_equal(mesh.colors, np.eye(3))
    assert mesh.texture is None and mesh.uv.shape == (1, 3, 2)


def test_read_ascii_ply_with_polygons_of_mixed_sizes_and_texcoords(tmp_path):
    (tmp_path / "a.ply").write_text(
        "ply\nformat ascii 1.0\ncomment made by hand\nelement vertex 5\nproperty float x\nproperty float y\n"
        "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\n"
        "element face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\n"
        "element edge 1\nproperty int vertex1\nproperty int vertex2\nend_header\n"
        "0 0 0 255 0 0\n1 0 0 0 255 0\n1 1 0 0 0 255\n0 1 0 255 255 255\n0.5 0.5 1 0 0 0\n"
        "4 0 1 2 3 8 0 0 1 0 1 1 0 1\n3 1 0 4 6 1 0 0 0 0.5 0.5\n0 1\n")
    mesh = read_mesh(tmp_path / "a.ply")
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3], [1, 0, 4]]
    np.testing.assert_allclose(mesh.uv[1], [[0, 0], [1, 1], [0, 1]])
    np.testing.assert_allclose(mesh.uv[2], [[1, 0], [0, 0], [0.5, 0.5]])
    np.testing.assert_array_equal(mesh.colors[3], [1, 1, 1])


def test_read_big_endian_ply_with_per_vertex_uv_as_blender_writes(tmp_path):
    vertex = np.array([(0, 0, 0, 0, 0), (1, 0, 0, 1, 0), (0, 1, 0, 0, 1)],
                      dtype=[("x", ">f4"), ("y", ">f4"), ("z", ">f4"), ("s", ">f4"), ("t", ">f4")])
    face = np.array([(3, (0, 1, 2))], dtype=[("n", "u1"), ("i", ">i4", (3,))])
    header = ("ply\nformat binary_big_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
              "property float z\nproperty float s\nproperty float t\nelement face 1\n"
              "property list uchar int vertex_indices\nend_header\n")
    (tmp_path / "b.ply").write_bytes(header.encode() + vertex.tobytes() + face.tobytes())
    mesh = read_mesh(tmp_path / "b.ply")
    np.testing.assert_array_equal(mesh.vertices, [[0, 0, 0], [1, 0, 0], [0, 1, 0]])
    np.testing.assert_array_equal(mesh.uv[0], [[0, 0], [1, 0], [0, 1]])


def test_binary_ply_with_polygons_of_mixed_sizes(tmp_path):
    vertices = np.array([[0, 0, 0], [1, 0, 0], [1, 1, 0], [0, 1, 0], [2, 0, 0]], dtype="<f4")
    rows = b"".join([np.uint8(4).tobytes() + np.array([0, 1, 2, 3], "<i4").tobytes(),
                     np.uint8(3).tobytes() + np.array([1, 4, 2], "<i4").tobytes()])
    header = ("ply\nformat binary_little_endian 1.0\nelement vertex 5\nproperty float x\nproperty float y\n"
              "property float z\nelement face 2\nproperty list uchar int vertex_indices\nend_header\n")
    (tmp_path / "q.ply").write_bytes(header.encode() + vertices.tobytes() + rows)
    assert read_mesh(tmp_path / "q.ply").faces.tolist() == [[0, 1, 2], [0, 2, 3], [1, 4, 2]]


_PLY_HEAD = ("ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
             "element face 2\nproperty list uchar int vertex_indices\nend_header\n")


@pytest.mark.parametrize("name, content, message", [
    ("a.obj", "hello world\n", r"it holds no faces \(0 vertices"),
    ("a.obj", "v 0 0 0\nv 1 0 0\n", r"it holds no faces \(2 vertices: a point cloud\?\)"),
    ("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2\n", "line 4: a face needs at least 3 corners"),
    ("a.obj", "v 0 0 0\nv 1 0 zero\n", r"line 2: cannot read 'v 1 0 zero'"),
    ("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n", "line 4: vertex index 0 \\(OBJ indices count from 1\\)"),
    ("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\nf 1 2 7\n", "line 5: a face uses vertex 7, but the file has 3 "
                                                                 "vertices"),
    ("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 -4\n", "line 4: vertex index -4 points before the first vertex"),
    ("a.obj", "v 0 0 0\nv 1 nan 0\nv 0 1 0\nf 1 2 3\n", r"line 2: vertex \(1.0, nan, 0.0\) is not finite"),
    ("a.obj", "v 0 0 0\nv 1 0 0\nv 0 1 inf\nf 1 2 3\n", r"line 3: vertex \(0.0, 1.0, inf\) is not finite"),
    ("a.ply", "not a ply file", "does not start with 'ply'"),
    ("a.ply", "ply\nformat binary_middle_endian 1.0\nend_header\n", "format 'binary_middle_endian'"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n0 0 0\n1 0 0\n0 1 0\n", r"no 'element face' in the header \(a point cloud\?\)"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n"
              "element face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n",
     "the data end before"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n"
              "end_header\n0 zero 0\n", "something that is not a number"),
    ("a.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty quaternion x\nend_header\n",
     "header line 4: cannot read property"),
    ("a.ply", _PLY_HEAD + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 3\n",
     r"face 1 \(element face\) uses vertex 3, but the file has 3 vertices \(0\.\.2\)"),
    ("a.ply", _PLY_HEAD + "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n4 0 1 -1 2\n", r"face 1 \(element face\) uses vertex -1"),
    ("a.ply", _PLY_HEAD + "0 0 0\n1 nan 0\n0 1 0\n3 0 1 2\n3 0 2 1\n",
     r"vertex 1 \(element vertex\) is \(1.0, nan, 0.0\), not finite"),
])
def test_garbled_files_give_a_value_error_naming_the_file(tmp_path, name, content, message):
    path = tmp_path / name
    path.write_text(content)
    with pytest.raises(ValueError, match=f"cannot read '.*{name}' as a {name[2:].upper()} mesh: .*{message}"):
        read_mesh(path)


def _textured_obj(folder, mtllib="m.mtl", map_kd="t.png"):
    """A textured triangle in ``folder/mesh/m.obj``; its material file and texture are where the names say."""
    from texsynth.io import save_image

    mesh_folder = folder / "mesh"
    for place in (folder, mesh_folder):
        place.mkdir(exist_ok=True)
        save_image(place / "t.png", np.ones((2, 2)), overwrite=True)
        (place / "m.mtl").write_text(f"newmtl m\nmap_Kd {map_kd}\n")
    (mesh_folder / "m.obj").write_text(f"mtllib {mtllib}\nusemtl m\nv 0 0 0\nv 1 0 0\nv 0 1 0\nvt 0 0\n"
                                       "f 1/1 2/1 3/1\n")
    return mesh_folder / "m.obj"


@pytest.mark.parametrize("mtllib, map_kd, message", [
    ("../m.mtl", "t.png", r"m.obj' as a OBJ mesh: line 1: mtllib '\.\./m\.mtl' is outside the mesh's folder"),
    ("ABSOLUTE", "t.png", r"m.obj' as a OBJ mesh: line 1: mtllib '/.*/m\.mtl' is outside the mesh's folder"),
    ("m.mtl", "../t.png", r"m.obj' as a OBJ mesh: m\.mtl line 2: map_Kd '\.\./t\.png' is outside the mesh's folder"),
    ("m.mtl", "ABSOLUTE", r"m.obj' as a OBJ mesh: m\.mtl line 2: map_Kd '/.*/t\.png' is outside the mesh's folder"),
])
def test_files_named_outside_the_mesh_folder_are_refused_unless_allowed(tmp_path, mtllib, map_kd, message):
    mtllib = str(tmp_path / "m.mtl") if mtllib == "ABSOLUTE" else mtllib
    map_kd = str(tmp_path / "t.png") if map_kd == "ABSOLUTE" else map_kd
    path = _textured_obj(tmp_path, mtllib, map_kd)
    with pytest.raises(ValueError, match=message + r" \(.*mesh\); .*pass allow_outside=True"):
        read_mesh(path)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # read, texture and all
        assert read_mesh(path, allow_outside=True).texture.shape == (2, 2)
    with pytest.raises(TypeError, match="allow_outside must be True or False"):
        read_mesh(path, allow_outside="yes")


def test_files_in_the_mesh_folder_and_below_are_followed(tmp_path):
    path = _textured_obj(tmp_path)
    (path.parent / "sub").mkdir()
    (path.parent / "t.png").rename(path.parent / "sub" / "t.png")
    (path.parent / "m.mtl").write_text("newmtl m\nmap_Kd sub/../sub/t.png\n")
    assert read_mesh(path).texture.shape == (2, 2)


def test_a_ply_texture_outside_the_mesh_folder_is_refused_unless_allowed(tmp_path):
    from texsynth.io import save_image

    save_image(tmp_path / "t.png", np.ones((2, 2)))
    (tmp_path / "mesh").mkdir()
    path = write_mesh(tmp_path / "mesh" / "a.ply", _decorated("texture"))
    path.write_bytes(path.read_bytes().replace(b"TextureFile a.png", b"TextureFile ../t.png"))
    with pytest.raises(ValueError, match=r"a.ply' as a PLY mesh: comment TextureFile '\.\./t\.png' is outside"):
        read_mesh(path)
    assert read_mesh(path, allow_outside=True).texture.shape == (2, 2)


def test_truncated_binary_ply(tmp_path):
    write_mesh(tmp_path / "full.ply", sphere(42))
    data = (tmp_path / "full.ply").read_bytes()
    (tmp_path / "cut.ply").write_bytes(data[:-7])
    with pytest.raises(ValueError, match="cut.ply' as a PLY mesh: the data end before"):
        read_mesh(tmp_path / "cut.ply")


def test_missing_files_and_folders(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        read_mesh(tmp_path / "nothing.obj")
    with pytest.raises(FileNotFoundError, match="is a folder"):
        read_mesh(tmp_path)
    with pytest.raises(TypeError, match="path must be a str or os.PathLike"):
        read_mesh(3)
    with pytest.raises(FileNotFoundError, match="does not exist; create it first"):
        write_mesh(tmp_path / "no" / "a.ply", sphere(12))
    with pytest.raises(ValueError, match="has no suffix"):
        write_mesh(tmp_path / "a", sphere(12))


def test_write_refuses_to_overwrite_and_leaves_nothing_behind(tmp_path):
    textured = _decorated("texture")
    (tmp_path / "t.png").write_bytes(b"someone's image")
    with pytest.raises(FileExistsError, match=r"t\.png' already exists; pass overwrite=True"):
        write_mesh(tmp_path / "t.obj", textured)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["t.png"]  # not even the .obj was written
    write_mesh(tmp_path / "t.obj", textured, overwrite=True)
    assert read_mesh(tmp_path / "t.obj").texture.shape == (6, 10, 3)
    with pytest.raises(FileExistsError, match="already exists"):
        write_mesh(tmp_path / "t.obj", sphere(12))
    assert not [p for p in tmp_path.iterdir() if p.name.startswith(".")]  # no temporary files left


def test_write_checks_the_mesh(tmp_path):
    with pytest.raises(ValueError, match="mesh has 1 isolated vertices"):
        write_mesh(tmp_path / "a.ply", (np.vstack([TETRA_V, [[5, 5, 5]]]), TETRA_F))
    assert not list(tmp_path.iterdir())


def test_as_mesh_reads_a_path(tmp_path):
    write_mesh(tmp_path / "s.ply", sphere(42))
    assert as_mesh(tmp_path / "s.ply").vertices.shape == (42, 3)
    assert as_mesh(str(tmp_path / "s.ply")).faces.shape == (80, 3)


def test_other_formats_go_through_trimesh(tmp_path):
    mesh = sphere(162)
    back = read_mesh(write_mesh(tmp_path / "s.stl", mesh))  # STL: float32 corners per triangle, joined again
    assert back.vertices.shape == mesh.vertices.shape  # the corners were joined into shared vertices
    np.testing.assert_allclose(back.vertices[back.faces], mesh.vertices[mesh.faces], atol=1e-6)
    coloured = _decorated("colors")
    back = read_mesh(write_mesh(tmp_path / "s.glb", coloured))  # binary glTF: float32 positions, RGBA8 colours
    np.testing.assert_allclose(back.vertices, coloured.vertices, atol=1e-6)
    np.testing.assert_array_equal(back.faces, coloured.faces)
    np.testing.assert_allclose(back.colors[:, :3], _eight_bit(coloured.colors), atol=1e-7)
    (tmp_path / "bad.stl").write_text("solid nothing here\nfacet normal garbage\n")
    with pytest.raises(ValueError, match="cannot read '.*bad.stl' as a STL mesh"):
        read_mesh(tmp_path / "bad.stl")


def test_other_formats_name_the_extra_when_trimesh_is_missing(tmp_path, monkeypatch):
    import importlib

    real = importlib.import_module

    def no_trimesh(name, *args):
        if name == "trimesh":
            raise ModuleNotFoundError("No module named 'trimesh'")
        return real(name, *args)

    monkeypatch.setattr(importlib, "import_module", no_trimesh)
    with pytest.raises(ModuleNotFoundError, match=r"through trimesh, which is not installed; python -m pip install 'trimesh>=4'"):
        write_mesh(tmp_path / "s.stl", sphere(12))
    assert not list(tmp_path.iterdir())


def test_files_interoperate_with_trimesh(tmp_path):
    """Files trimesh writes read here, and files written here read in trimesh (another tool's reading)."""
    import trimesh
    from PIL import Image

    mesh = sphere(162)
    rng = np.random.default_rng(1)
    rgba = (rng.random((162, 4)) * 255).astype(np.uint8)
    theirs = trimesh.Trimesh(mesh.vertices, mesh.faces, vertex_colors=rgba, process=False)
    for name, options in (("c.ply", {}), ("a.ply", {"encoding": "ascii"}), ("c.obj", {})):
        theirs.export(tmp_path / name, **options)
        back = read_mesh(tmp_path / name)
        np.testing.assert_array_equal(back.faces, mesh.faces)
        np.testing.assert_allclose(back.vertices, mesh.vertices, atol=1e-7)
        channels = 4 if name.endswith(".ply") else 3  # trimesh's OBJ writes r g b
        np.testing.assert_allclose(back.colors * 255, rgba[:, :channels], atol=1e-3)
    uv = rng.random((162, 2))
    image = (rng.random((8, 8, 3)) * 255).astype(np.uint8)
    textured = trimesh.Trimesh(mesh.vertices, mesh.faces, process=False,
                               visual=trimesh.visual.TextureVisuals(uv=uv, image=Image.fromarray(image)))
    textured.export(tmp_path / "t.obj")  # with material.mtl and material_0.png
    back = read_mesh(tmp_path / "t.obj")
    np.testing.assert_allclose(back.uv, uv[mesh.faces], atol=1e-7)
    np.testing.assert_array_equal(back.texture, image / 255)
    # ours, read by trimesh
    ours = mesh.with_colors(rgba / 255)
    for name in ("o.ply", "o.obj"):
        loaded = trimesh.load(write_mesh(tmp_path / name, ours), process=False)
        np.testing.assert_array_equal(loaded.faces, mesh.faces)
        np.testing.assert_array_equal(loaded.visual.vertex_colors[:, :3], rgba[:, :3])
    loaded = trimesh.load(write_mesh(tmp_path / "ot.obj", mesh.with_texture(uv[mesh.faces], image)), process=False)
    assert loaded.visual.kind == "texture"
    np.testing.assert_array_equal(np.asarray(loaded.visual.material.image), image)


def test_obj_texture_cases_that_are_read_without_the_texture(tmp_path):
    body = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 1 1 0\nvt 0 0\nvt 1 0\nvt 0 1\n"
    (tmp_path / "some.obj").write_text(body + "f 1/1 2/2 3/3\nf 2 4 3\n")
    with pytest.warns(UserWarning, match="only some faces have texture coordinates"):
        mesh = read_mesh(tmp_path / "some.obj")
    assert mesh.uv is None and mesh.faces.shape == (2, 3)
    from texsynth.io import save_image

    for name in ("a.png", "b.png"):
        save_image(tmp_path / name, np.zeros((2, 2)))
    (tmp_path / "two.mtl").write_text("newmtl a\nmap_Kd a.png\nnewmtl b\nmap_Kd b.png\n")
    (tmp_path / "two.obj").write_text("mtllib two.mtl\n" + body + "usemtl a\nf 1/1 2/2 3/3\nusemtl b\nf 2/2 4/1 3/3\n")
    with pytest.warns(UserWarning, match=r"uses 2 texture images \(\['a.png', 'b.png'\]\); a texsynth Mesh holds one"):
        mesh = read_mesh(tmp_path / "two.obj")
    assert mesh.texture is None and mesh.uv.shape == (2, 3, 2)
    (tmp_path / "nomtl.obj").write_text("mtllib gone.mtl\nusemtl a\n" + body + "f 1/1 2/2 3/3\n")
    with pytest.warns(UserWarning, match="names the material file 'gone.mtl', which cannot be read"):
        assert read_mesh(tmp_path / "nomtl.obj").texture is None


def test_ply_faces_without_their_texcoords_are_read_without_uv(tmp_path):
    (tmp_path / "a.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nproperty list uchar float texcoord\nend_header\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n3 0 1 2 6 0 0 1 0 1 1\n3 0 2 3 0\n")
    with pytest.warns(UserWarning, match="some faces' texcoord lists do not hold one"):
        mesh = read_mesh(tmp_path / "a.ply")
    assert mesh.faces.tolist() == [[0, 1, 2], [0, 2, 3]] and mesh.uv is None


def test_truncated_ascii_ply_with_polygons_of_mixed_sizes(tmp_path):
    (tmp_path / "a.ply").write_text(
        "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\n"
        "element face 2\nproperty list uchar int vertex_indices\nend_header\n"
        "0 0 0\n1 0 0\n1 1 0\n0 1 0\n2 0 0\n4 0 1 2 3\n3 1 4\n")  # the last face is cut short
    with pytest.raises(ValueError, match="a.ply' as a PLY mesh: the data end before"):
        read_mesh(tmp_path / "a.ply")
