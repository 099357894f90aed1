"""texsynth.surface.render_mesh: the z-buffer preview draws what the mesh holds, where it should."""

import numpy as np
import pytest

from texsynth.surface import Mesh, render_mesh, sphere

WHITE = np.ones(3)


def _covered(image, background=WHITE):
    return np.any(np.abs(image - background) > 1e-9, axis=-1)


def _square(x, half=1.0, center=(0.0, 0.0)):
    """Two triangles of a square in the plane at ``x``, facing +x (counter-clockwise seen from +x)."""
    y, z = center
    corners = np.array([[x, y - half, z - half], [x, y + half, z - half], [x, y + half, z + half],
                        [x, y - half, z + half]])
    return corners, np.array([[0, 1, 2], [0, 2, 3]])


def _two_squares(front_first):
    """A red square at x = 1 in front of a larger blue one at x = -1, seen from +x (azimuth 0)."""
    v_front, f_front = _square(1.0, 0.5)
    v_back, f_back = _square(-1.0, 1.0)
    parts = [(v_front, f_front, [1, 0, 0]), (v_back, f_back, [0, 0, 1])]
    if not front_first:
        parts = parts[::-1]
    vertices = np.vstack([p[0] for p in parts])
    faces = np.vstack([parts[0][1], parts[1][1] + 4])
    colors = np.vstack([np.tile(p[2], (4, 1)) for p in parts]).astype(float)
    return Mesh(vertices, faces, colors=colors)


@pytest.mark.parametrize("projection", ["orthographic", "perspective"])
def test_sphere_silhouette_is_a_disc(projection):
    image = render_mesh(sphere(2562), 160, views=1, projection=projection)
    mask = _covered(image)
    rows, cols = np.nonzero(mask)
    radius = (cols.max() - cols.min() + 1 + rows.max() - rows.min() + 1) / 4
    # a disc: pi r^2 pixels (a square of the same width would have 4 r^2, 27 % more); the sphere is a
    # polyhedron inscribed in the ball, slightly smaller than its disc, and the boundary pixels are
    # sampled at their centres: 2 % covers both at this size
    assert mask.sum() == pytest.approx(np.pi * radius ** 2, rel=0.02)
    centre = np.array(image.shape[:2]) / 2 - 0.5
    assert np.allclose([rows.mean(), cols.mean()], centre, atol=0.5)  # centred in the view
    assert radius > 0.4 * 160  # fitted: the bounding sphere fills most of the view


@pytest.mark.parametrize("front_first", [True, False])
def test_the_front_face_occludes_the_back_face(front_first):
    image = render_mesh(_two_squares(front_first), 101, views=[(0, 0)], projection="orthographic", ambient=1.0)
    assert np.allclose(image[50, 50], [1, 0, 0])  # the red square in front, whatever the face order
    assert np.allclose(image[50, 30], [0, 0, 1])  # the blue one around it
    assert np.allclose(image[2, 2], WHITE)  # the background beyond both
    seen_from_behind = render_mesh(_two_squares(front_first), 101, views=[(180, 0)], projection="orthographic",
                                   ambient=1.0)
    assert np.allclose(seen_from_behind[50, 50], [0, 0, 1])  # from -x the blue square hides the red one


def test_vertex_colours_show_where_they_are():
    mesh = sphere(642)
    red_or_blue = np.where(mesh.vertices[:, :1] > 0, [[1.0, 0, 0]], [[0, 0, 1.0]])
    image = render_mesh(mesh.with_colors(red_or_blue), 64, views=[(0, 0), (180, 0)], projection="orthographic")
    front, back = image[:, :32], image[:, 32:]
    for view, (hot, cold) in ((front, (0, 2)), (back, (2, 0))):
        centre = view[32, 16]
        assert centre[hot] > 0.5 and centre[cold] < 1e-9 and centre[1] < 1e-9
    # shading: the lit centre is brighter than the rim of the same colour
    assert front[32, 16, 0] > front[32, 2, 0]


def test_grey_without_colours_and_ambient_one_shows_the_flat_albedo():
    image = render_mesh(sphere(162), 48, views=1, ambient=1.0)
    inside = image[_covered(image)]
    assert np.allclose(inside, inside[0]) and np.allclose(inside[0], inside[0][0])  # one grey everywhere
    assert 0.5 < inside[0][0] < 0.9


def test_texture_is_looked_up_with_v_up():
    # a square facing +x with uv (0, 0) at its lower left; the texture's top half blue, bottom half red,
    # left column green: seen from +x (screen right = +y, up = +z) it must appear the same way up
    vertices, faces = _square(0.0)
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)[faces]
    texture = np.zeros((8, 8, 3))
    texture[:4, :, 2] = 1
    texture[4:, :, 0] = 1
    texture[:, :1] = [0, 1, 0]
    mesh = Mesh(vertices, faces, uv=uv, texture=texture)
    image = render_mesh(mesh, 101, views=[(0, 0)], projection="orthographic", ambient=1.0)
    assert np.allclose(image[20, 50], [0, 0, 1])  # upper half blue, up to the edge (no wrap to the bottom)
    assert np.allclose(image[80, 50], [1, 0, 0])  # lower half red
    assert image[50, 20, 1] > 0.9 and image[50, 80, 1] < 1e-9  # green on the left only
    # bilinear: across the middle row the colour changes gradually, not in one step
    column = image[30:71, 50]
    assert np.sum((column[:, 0] > 0.05) & (column[:, 2] > 0.05)) >= 2


def test_interpolation_is_perspective_correct():
    # a long floor strip seen at a grazing angle: its texture midpoint (u = 0.5) is its 3-D midpoint, which
    # perspective draws above the midpoint of the strip's image (the far half looks shorter)
    vertices = np.array([[-4, -1, 0], [4, -1, 0], [4, 1, 0], [-4, 1, 0]], dtype=float)
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    uv = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)[faces]
    texture = np.zeros((2, 2, 3))
    texture[:, 0] = [1, 0, 0]  # u < 0.5 (far, at x < 0): red; u > 0.5 (near): blue
    texture[:, 1] = [0, 0, 1]
    image = render_mesh(Mesh(vertices, faces, uv=uv, texture=texture), 200, views=[(0, 15)], ambient=1.0)
    column = image[:, 100]
    rows = np.flatnonzero(_covered(column[:, None])[:, 0])
    red_rows = np.flatnonzero(column[:, 0] > column[:, 2])
    blue_rows = np.flatnonzero(column[:, 2] > column[:, 0])
    assert red_rows.max() < blue_rows.min()  # far (red) above near (blue)
    boundary = (red_rows.max() + blue_rows.min()) / 2
    image_middle = (rows.min() + rows.max()) / 2
    assert boundary < image_middle - 3  # the 3-D midpoint is drawn well above the image's middle


def test_views_fill_a_grid_and_background_is_respected():
    image = render_mesh(sphere(162), (60, 90), views=5, background=(0, 0.5, 0))
    assert image.shape == (60, 90, 3)
    # 5 views: 3 columns x 2 rows of 30 x 30 tiles, the sixth tile empty
    for k in range(6):
        r, c = divmod(k, 3)
        tile = image[r * 30:(r + 1) * 30, c * 30:(c + 1) * 30]
        assert _covered(tile, [0, 0.5, 0]).any() == (k < 5)


def test_an_open_mesh_is_drawn_from_both_sides():
    vertices, faces = _square(0.0)
    front = render_mesh((vertices, faces), 32, views=[(0, 0)])
    back = render_mesh((vertices, faces), 32, views=[(180, 0)])
    assert _covered(front).sum() > 200 and _covered(back).sum() == _covered(front).sum()


@pytest.mark.parametrize("kwargs, error, message", [
    ({"views": 0}, ValueError, "views must be a count >= 1"),
    ({"views": [(0, 100)]}, ValueError, r"elevation must lie in \[-90, 90\]"),
    ({"views": "front"}, TypeError, "views must be a count or a list of"),
    ({"views": []}, ValueError, "views must be a non-empty list"),
    ({"projection": "fisheye"}, ValueError, r"projection must be one of \('perspective', 'orthographic'\)"),
    ({"light": (0, 0, 0)}, ValueError, "light must be a non-zero direction"),
    ({"ambient": 2.0}, ValueError, r"ambient must lie in \[0.0, 1.0\]"),
    ({"background": (1, 2, 3)}, ValueError, "background must be a grey level or an"),
    ({"size": 0}, ValueError, "size must be positive integers"),
    ({"size": (1, 1), "views": 4}, ValueError, "too small for 4 views in a 2 x 2 grid"),
    ({"size": 10**7}, ValueError, r"size=\(10000000, 10000000\) needs about .* GiB for the preview"),
])
def test_bad_arguments(kwargs, error, message):
    with pytest.raises(error, match=message):
        render_mesh(sphere(12), **{"size": 32, **kwargs})


def test_bad_mesh_is_named():
    with pytest.raises(ValueError, match="mesh has 1 faces of zero area"):
        render_mesh(([[0, 0, 0], [1, 0, 0], [2, 0, 0]], [[0, 1, 2]]))


def test_a_badly_oriented_closed_mesh_is_not_culled_into_holes():
    mesh = sphere(162)
    faces = mesh.faces.copy()
    faces[::3] = faces[::3, ::-1]  # a third of the faces wound the wrong way: their normals point inwards
    with pytest.warns(UserWarning, match="not consistently oriented"):
        flipped = render_mesh((mesh.vertices, faces), 64, views=1, ambient=1.0)
    good = render_mesh(mesh, 64, views=1, ambient=1.0)
    np.testing.assert_array_equal(_covered(flipped), _covered(good))
