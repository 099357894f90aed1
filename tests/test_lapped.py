"""Lapped textures (issue 20, part 2): coverage, alignment with the field, scale, bad input."""

import numpy as np
import pytest

from texsynth.data import load
from texsynth.surface._lapped import _sample, lapped_textures
from texsynth.surface._shapes import sphere, torus


def _uv_gradients(mesh, faces, uv):
    """Per face, the 3-D gradients of u and v of a linear map given at the corners."""
    p = mesh.vertices[mesh.faces[faces]]
    e1, e2 = p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]
    n = np.cross(e1, e2)
    nn = np.einsum("ij,ij->i", n, n)[:, None]
    # gradient of a linear function f with f1 - f0 = a along e1, f2 - f0 = b along e2
    g1, g2 = np.cross(e2, n) / nn, np.cross(n, e1) / nn
    du, dv = uv[:, 1] - uv[:, 0], uv[:, 2] - uv[:, 0]
    return du[:, 0, None] * g1 + dv[:, 0, None] * g2, du[:, 1, None] * g1 + dv[:, 1, None] * g2


@pytest.fixture(scope="module")
def torus_result():
    mesh = torus(4000)
    out, info = lapped_textures(mesh, load("brick")[:64, :64], pixel_size=1 / 64, rng=0, return_info=True)
    return mesh, out, info


def test_every_face_is_covered_by_an_opaque_patch(torus_result):
    mesh, out, info = torus_result
    assert out.texture is not None and out.uv.shape == (len(mesh.faces), 3, 2)
    opaque = np.zeros(len(mesh.faces), dtype=bool)
    for faces, uv in info.patches:
        alpha = _sample(info.splotch[..., -1:], uv)[..., 0]
        opaque[faces[(alpha >= 0.99).all(axis=1)]] = True
    # every face lies wholly in some patch's opaque part (the seeds of patches count as covered by construction:
    # allow those few only where the splotch's opaque part is smaller than a face, not here)
    assert opaque.mean() > 0.99
    assert info.layers.min() >= 1
    # no gaps: the atlas at every face corner and centre holds blended brick colour, not the black of an empty
    # texel (the brick's darkest pixels have a channel above 0.1)
    corners = np.concatenate([out.uv, out.uv.mean(axis=1, keepdims=True)], axis=1)
    assert _sample(out.texture, corners).max(axis=-1).min() > 0.05


def test_patches_follow_the_field_at_the_pixel_size(torus_result):
    mesh, out, info = torus_result
    cosines, lengths = [], []
    for faces, uv in info.patches:
        gu, _ = _uv_gradients(mesh, faces, uv)
        t = info.field[mesh.faces[faces]].mean(axis=1)
        t /= np.linalg.norm(t, axis=1, keepdims=True)
        norm = np.linalg.norm(gu, axis=1)
        cosines.append(np.einsum("ij,ij->i", gu, t) / norm)
        lengths.append(norm)
    cosines, lengths = np.concatenate(cosines), np.concatenate(lengths)
    # Aligned: u grows along the field. An unaligned parametrisation has a uniform angle (mean cosine 0, median
    # |cosine| 0.71); the least squares measured a median cosine of about 0.99 (distortion only where the
    # torus curves the patch). 0.95 fails for anything not aligned.
    assert np.median(cosines) > 0.95
    # scale: |grad u| = 1 / (64 pixels x pixel_size) = 1 within 10 % for the median face
    assert abs(np.median(lengths) - 1.0) < 0.1


def test_user_field_turns_the_patches():
    mesh = sphere(642)
    _, info = lapped_textures(mesh, load("brick")[:32, :32], field=lambda p: np.cross([0, 0, 1.0], p),
                              pixel_size=1 / 32, rng=0, return_info=True)
    faces, uv = info.patches[0]
    gu, gv = _uv_gradients(mesh, faces, uv)
    centroid = mesh.vertices[mesh.faces[faces]].mean(axis=1)
    east = np.cross([0, 0, 1.0], centroid)
    east /= np.linalg.norm(east, axis=1, keepdims=True)
    keep = np.abs(centroid[:, 2]) < 0.8
    assert np.median(np.einsum("ij,ij->i", gu, east)[keep] / np.linalg.norm(gu[keep], axis=1)) > 0.9


def test_each_patch_grows_over_the_whole_splotch_and_stays_connected(torus_result):
    # Praun et al.'s growth: a patch takes adjacent faces while they reach into the splotch, so it is
    # one edge-connected piece around its seed and, where the surface is smooth at the splotch's scale
    # (a torus 2.8 wide with a 0.4 tube; the exemplar 1 unit wide at pixel_size 1/64), it reaches the
    # splotch's rim on every side
    import scipy.sparse
    import scipy.sparse.csgraph

    mesh, _, info = torus_result
    adjacency = mesh.face_adjacency
    rows = np.repeat(np.arange(len(mesh.faces)), 3)
    keep = adjacency.ravel() >= 0
    graph = scipy.sparse.csr_matrix((np.ones(keep.sum()), (rows[keep], adjacency.ravel()[keep])),
                                    shape=(len(mesh.faces),) * 2)
    spans = []
    for faces, uv in info.patches:
        n_parts, _ = scipy.sparse.csgraph.connected_components(graph[faces][:, faces], directed=False)
        assert n_parts == 1
        spans.append(uv.reshape(-1, 2).max(axis=0) - uv.reshape(-1, 2).min(axis=0))
    # the default blob's soft rim reaches about 0.04-0.96 of the unit square, and the faces that touch
    # it stick out a little: every patch spanned 0.92-0.95 in u and v (rng=0); a patch stopped short of
    # the rim on one side (half a splotch missing) would span about 0.5-0.6
    assert np.min(spans) > 0.85


def test_lapped_repeats_with_rng_and_uses_the_alpha_channel():
    mesh = sphere(162)
    ex = load("brick")[:32, :32]
    a = lapped_textures(mesh, ex, rng=1)
    b = lapped_textures(mesh, ex, rng=1)
    assert np.array_equal(a.texture, b.texture) and np.array_equal(a.uv, b.uv)
    # an RGBA exemplar: its alpha is the splotch (a square opaque core here)
    alpha = np.zeros((32, 32))
    alpha[4:28, 4:28] = 1
    _, info = lapped_textures(mesh, np.dstack([ex, alpha]), rng=1, return_info=True)
    assert np.array_equal(info.splotch[..., -1], alpha)


def test_lapped_bad_input():
    mesh = sphere(162)
    ex = load("brick")[:32, :32]
    with pytest.raises(ValueError, match=r"field must be one \(x, y, z\) vector per vertex, shape \(162, 3\)"):
        lapped_textures(mesh, ex, field=np.ones((3, 3)))
    with pytest.raises(ValueError, match="field has 162 vectors with NaN"):
        lapped_textures(mesh, ex, field=np.full((162, 3), np.nan))
    with pytest.raises(ValueError, match="mask must be one alpha value per exemplar pixel"):
        lapped_textures(mesh, ex, mask=np.ones((5, 5)))
    with pytest.raises(ValueError, match="no opaque pixel"):
        lapped_textures(mesh, ex, mask=np.zeros((32, 32)))
    with pytest.raises(ValueError, match="pixel_size"):
        lapped_textures(mesh, ex, pixel_size=-1.0)
    with pytest.raises(ValueError, match="texels=10000000 needs about"):
        lapped_textures(mesh, ex, texels=10**7)


def test_cli_surface_both_modes(tmp_path, capsys):
    from texsynth.cli import main
    from texsynth.io import save_image
    from texsynth.surface import read_mesh, write_mesh

    write_mesh(tmp_path / "s.ply", sphere(162))
    save_image(tmp_path / "ex.png", load("brick")[:32, :32])
    base = [str(tmp_path / "s.ply"), str(tmp_path / "ex.png")]
    assert main(["surface", *base, "-o", str(tmp_path / "v.ply"), "--n-vertices", "400", "--levels", "2", "--field",
                 "latitude", "--seed", "0"]) == 0
    vertex = read_mesh(tmp_path / "v.ply")
    assert vertex.colors is not None and 380 <= len(vertex.vertices) <= 400
    # --order reaches synthesize_surface: Turk's sweep gives other colours on the same retiled mesh
    assert main(["surface", *base, "-o", str(tmp_path / "w.ply"), "--n-vertices", "400", "--levels", "2", "--field",
                 "latitude", "--seed", "0", "--order", "sweep"]) == 0
    swept = read_mesh(tmp_path / "w.ply")
    assert np.array_equal(swept.vertices, vertex.vertices) and not np.array_equal(swept.colors, vertex.colors)
    assert main(["surface", *base, "-o", str(tmp_path / "l.obj"), "--mode", "lapped", "--seed", "0"]) == 0
    lapped = read_mesh(tmp_path / "l.obj")
    assert lapped.texture is not None and lapped.uv.shape == (320, 3, 2)
    capsys.readouterr()
    assert main(["surface", *base, "-o", str(tmp_path / "x.ply"), "--mode", "lapped", "--order", "sweep"]) == 2
    assert "--order belong to --mode vertex" in capsys.readouterr().err
    assert main(["surface", *base, "-o", str(tmp_path / "x.ply"), "--field", "swirl"]) == 2
    assert "--field must be smooth, random, latitude, meridian" in capsys.readouterr().err
    np.save(tmp_path / "f.npy", np.ones((7, 3)))
    assert main(["surface", *base, "-o", str(tmp_path / "x.ply"), "--field", str(tmp_path / "f.npy")]) == 2
    assert "field must be one (x, y, z) vector per vertex, shape (162, 3)" in capsys.readouterr().err
