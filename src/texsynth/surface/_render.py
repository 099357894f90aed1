"""A preview renderer for meshes: a z-buffer rasteriser in numpy.

Each view projects the vertices (perspective or orthographic), finds for
every face the pixel centres inside it, keeps per pixel the nearest face
(z-buffer), and shades it with Lambert's cosine law plus an ambient term,
using normals interpolated from the vertex normals (Phong-style smooth
shading). The colour comes from the vertex colours (interpolated with the
barycentric coordinates), from the texture (bilinear lookup at the
interpolated uv), or is a uniform grey. Interpolation is perspective-correct.

Rasterisation is vectorised over faces: faces are grouped by the size of
their pixel bounding box (1, 2, 4, 8, ... pixels), and every face of a group
tests all pixel centres of its box at once, in chunks of a bounded number of
candidate pixels; a face never loops over pixels in Python.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

from ..core._validate import as_size, check_in_range, check_memory
from ._meshio import as_mesh

__all__ = ["render_mesh", "PROJECTIONS"]

PROJECTIONS = ("perspective", "orthographic")
_FIELD_OF_VIEW = np.radians(30.0)  # of the perspective camera, fitted to the mesh's bounding sphere
_MARGIN = 0.92  # the bounding sphere fills this fraction of the smaller side of a view
_GREY = 0.72  # the colour of a mesh without colours or texture
_ELEVATION = 20.0  # degrees above the horizon of the views views=n places around the mesh
_CANDIDATES_PER_CHUNK = 1_000_000  # pixel candidates tested at once (bounded memory for huge faces)
_INSIDE = -1e-9  # a pixel centre on a shared edge belongs to both faces: no cracks between them
# bytes per output pixel: the image (24), a view's z-buffer, face and weights (40) and its shaded tile (24);
# plus a chunk of candidates (about 12 arrays of 8 bytes each)
_BYTES_PER_PIXEL, _BYTES_PER_CHUNK = 88, 12 * 8 * _CANDIDATES_PER_CHUNK


def _check_views(views):
    """A list of (azimuth, elevation) in degrees from an int count or a list of pairs."""
    if isinstance(views, numbers.Integral) and not isinstance(views, bool):
        if views < 1:
            raise ValueError(f"views must be a count >= 1 or a list of (azimuth, elevation) pairs, got {views}")
        return [(360.0 * k / views, _ELEVATION) for k in range(int(views))]
    try:
        pairs = [tuple(float(a) for a in view) for view in views]
    except (TypeError, ValueError):
        raise TypeError(f"views must be a count or a list of (azimuth, elevation) pairs in degrees, got {views!r}"
                        ) from None
    if not pairs or any(len(p) != 2 or not all(np.isfinite(p)) for p in pairs):
        raise ValueError(f"views must be a non-empty list of finite (azimuth, elevation) pairs in degrees, got "
                         f"{views!r}")
    if any(abs(p[1]) > 90 for p in pairs):
        raise ValueError(f"every view's elevation must lie in [-90, 90] degrees, got {views!r}")
    return pairs


def _check_color(value, name):
    """A grey level or an (r, g, b) triple in [0, 1], as an RGB array."""
    try:
        rgb = np.array(value, dtype=np.float64) * np.ones(3)
    except (TypeError, ValueError):
        rgb = None
    if rgb is None or rgb.shape != (3,) or not np.all((rgb >= 0) & (rgb <= 1)):
        raise ValueError(f"{name} must be a grey level or an (r, g, b) triple in [0, 1], got {value!r}")
    return rgb


def _camera(azimuth, elevation):
    """Rows: the camera's right, up and backward (towards the viewer) axes in world coordinates, z up."""
    a, e = np.radians(azimuth), np.radians(elevation)
    back = np.array([np.cos(e) * np.cos(a), np.cos(e) * np.sin(a), np.sin(e)])  # from the centre to the camera
    world_up = np.array([0.0, 0.0, 1.0]) if abs(elevation) < 89.9 else np.array([-np.cos(a), -np.sin(a), 0.0])
    right = np.cross(world_up, back)
    right /= np.linalg.norm(right)
    return np.stack([right, np.cross(back, right), back])


def _project(vertices, center, radius, axes, shape, projection):
    """Pixel column, row and depth (distance along the view axis, positive in front) of every vertex."""
    h, w = shape
    local = (vertices - center) @ axes.T  # right, up, back
    half = _MARGIN * min(h, w) / 2
    if projection == "orthographic":
        scale = np.full(len(vertices), half / radius)
        depth = 2 * radius - local[:, 2]
    else:
        distance = radius / np.sin(_FIELD_OF_VIEW / 2)
        depth = distance - local[:, 2]
        scale = half / np.tan(_FIELD_OF_VIEW / 2) / depth
    return w / 2 + local[:, 0] * scale, h / 2 - local[:, 1] * scale, depth


def _rasterize(x, y, depth, faces, shape, perspective):
    """Z-buffer: the nearest face at every pixel centre and its barycentric coordinates there.

    Returns ``face`` (H*W,) int64 (-1: background) and ``bary`` (H*W, 3) perspective-correct weights.
    """
    h, w = shape
    best_depth = np.full(h * w, np.inf)
    best_face = np.full(h * w, -1, dtype=np.int64)
    best_bary = np.zeros((h * w, 3))
    fx, fy, fz = x[faces], y[faces], depth[faces]
    x0 = np.floor(fx.min(axis=1) - 0.5).astype(np.int64)
    y0 = np.floor(fy.min(axis=1) - 0.5).astype(np.int64)
    extent = np.maximum(np.ceil(fx.max(axis=1) - 0.5) - x0, np.ceil(fy.max(axis=1) - 0.5) - y0) + 1
    # twice the signed screen area; faces seen edge-on (or behind the camera) cover no pixel centre
    area = (fx[:, 1] - fx[:, 0]) * (fy[:, 2] - fy[:, 0]) - (fx[:, 2] - fx[:, 0]) * (fy[:, 1] - fy[:, 0])
    visible = (np.abs(area) > 1e-12) & np.all(fz > 0, axis=1) & (x0 < w) & (y0 < h) & (x0 + extent > 0) & (
        y0 + extent > 0)
    side = np.maximum(1, 2 ** np.ceil(np.log2(np.maximum(extent, 1)))).astype(np.int64)
    for k in np.unique(side[visible]):
        group = np.flatnonzero(visible & (side == k))
        offsets_y, offsets_x = np.divmod(np.arange(k * k), k)
        per_chunk = max(1, _CANDIDATES_PER_CHUNK // (k * k))
        for start in range(0, len(group), per_chunk):
            f = group[start:start + per_chunk]
            px = x0[f, None] + offsets_x  # candidate pixels (len(f), k*k)
            py = y0[f, None] + offsets_y
            cx, cy = px + 0.5, py + 0.5
            ax, ay = fx[f], fy[f]
            # screen-space barycentric coordinates of the pixel centres (edge functions / area)
            b0 = ((ax[:, 1, None] - cx) * (ay[:, 2, None] - cy) - (ax[:, 2, None] - cx) * (ay[:, 1, None] - cy))
            b1 = ((ax[:, 2, None] - cx) * (ay[:, 0, None] - cy) - (ax[:, 0, None] - cx) * (ay[:, 2, None] - cy))
            b0, b1 = b0 / area[f, None], b1 / area[f, None]
            b2 = 1 - b0 - b1
            inside = (b0 >= _INSIDE) & (b1 >= _INSIDE) & (b2 >= _INSIDE) & (px >= 0) & (px < w) & (py >= 0) & (
                py < h)
            row, col = np.nonzero(inside)
            if not len(row):
                continue
            bary = np.stack([b0[row, col], b1[row, col], b2[row, col]], axis=1)
            faces_hit = f[row]
            if perspective:  # attributes are linear in 1/depth on screen, not in depth
                bary = bary / fz[faces_hit]
                z = 1 / bary.sum(axis=1)
                bary *= z[:, None]
            else:
                z = np.sum(bary * fz[faces_hit], axis=1)
            pixel = py[row, col] * w + px[row, col]
            order = np.lexsort((z, pixel))  # nearest candidate first within each pixel
            pixel, z = pixel[order], z[order]
            first = np.ones(len(pixel), dtype=bool)
            first[1:] = pixel[1:] != pixel[:-1]
            keep = order[first]
            pixel, z = pixel[first], z[first]
            nearer = z < best_depth[pixel]
            pixel, keep = pixel[nearer], keep[nearer]
            best_depth[pixel] = z[nearer]
            best_face[pixel] = faces_hit[keep]
            best_bary[pixel] = bary[keep]
    return best_face, best_bary


def _albedo(mesh, face, bary):
    """RGB colour of each covered pixel: vertex colours, texture, or grey."""
    if mesh.colors is not None:
        c = np.einsum("pk,pkc->pc", bary, mesh.colors[mesh.faces[face]].astype(np.float64))
        return np.repeat(c[:, :1], 3, axis=1) if c.shape[1] <= 2 else c[:, :3]
    if mesh.texture is not None:
        uv = np.einsum("pk,pkc->pc", bary, mesh.uv[face])
        return _bilinear(mesh.texture, uv)
    return np.full((len(face), 3), _GREY)


def _bilinear(texture, uv):
    """Bilinear lookup of ``texture`` at ``uv``, as RGB.

    ``v`` points up (row 0 of the image is ``v = 1``). Coordinates outside [0, 1] repeat the
    texture; the four pixels of a lookup are clamped at the image's edges, so an atlas does
    not bleed from one side into the other.
    """
    image = texture if texture.ndim == 3 else texture[..., None]
    image = np.repeat(image[..., :1], 3, axis=2) if image.shape[2] <= 2 else image[..., :3]
    h, w = image.shape[:2]
    repeat = np.where((uv < 0) | (uv > 1), np.mod(uv, 1.0), uv)
    col = repeat[:, 0] * w - 0.5
    row = (1.0 - repeat[:, 1]) * h - 0.5
    c0, r0 = np.floor(col).astype(np.int64), np.floor(row).astype(np.int64)
    tc, tr = (col - c0)[:, None], (row - r0)[:, None]
    c0, c1 = np.clip(c0, 0, w - 1), np.clip(c0 + 1, 0, w - 1)
    r0, r1 = np.clip(r0, 0, h - 1), np.clip(r0 + 1, 0, h - 1)
    top = image[r0, c0] * (1 - tc) + image[r0, c1] * tc
    bottom = image[r1, c0] * (1 - tc) + image[r1, c1] * tc
    return (top * (1 - tr) + bottom * tr).astype(np.float64)


def _render_view(mesh, shape, azimuth, elevation, projection, light, ambient, background, cull):
    axes = _camera(azimuth, elevation)
    center = mesh.bounds.mean(axis=0)
    radius = max(float(np.linalg.norm(mesh.vertices - center, axis=1).max()), 1e-300)
    x, y, depth = _project(mesh.vertices, center, radius, axes, shape, projection)
    faces = np.arange(len(mesh.faces))
    if cull:  # a closed mesh hides the faces turned away from the camera: skip them
        to_camera = axes[2] if projection == "orthographic" else (
            center + axes[2] * radius / np.sin(_FIELD_OF_VIEW / 2) - mesh.vertices[mesh.faces[:, 0]])
        faces = np.flatnonzero(np.sum(mesh.face_normals * to_camera, axis=-1) > 0)
    face, bary = _rasterize(x, y, depth, mesh.faces[faces], shape, projection == "perspective")
    image = np.tile(background, (shape[0] * shape[1], 1))
    hit = np.flatnonzero(face >= 0)
    if len(hit):
        f = faces[face[hit]]
        normal = np.einsum("pk,pkc->pc", bary[hit], mesh.vertex_normals[mesh.faces[f]])
        normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
        # the light is given in camera coordinates; two-sided, so that the inside of an open mesh is lit too
        lambert = np.abs(normal @ (axes.T @ light))
        image[hit] = _albedo(mesh, f, bary[hit]) * (ambient + (1 - ambient) * lambert)[:, None]
    return image.reshape(shape[0], shape[1], 3)


def render_mesh(mesh, size=512, *, views=4, projection="perspective", light=(-0.4, 0.5, 1.0), ambient=0.3,
                background=1.0):
    """Render a mesh from a few viewpoints into one preview image.

    Examples
    --------
    >>> import texsynth
    >>> image = texsynth.render_mesh(texsynth.surface.sphere(162), 64, views=1)
    >>> image.shape, bool(image[32, 32].max() < 1 == image[0, 0].min())
    ((64, 64, 3), True)

    Parameters
    ----------
    mesh : Mesh, (vertices, faces) or path
        The mesh (checked with :func:`as_mesh`). Coloured by its vertex
        colours if it has them, else by its texture through its uv
        coordinates, else grey. z points up.
    size : int or (height, width)
        Size of the whole image; the views share it in a grid.
    views : int or list of (azimuth, elevation)
        A count ``n``: ``n`` views around the mesh, azimuths ``360 k / n``
        degrees at 20 degrees elevation, in a grid of ``ceil(sqrt(n))``
        columns (4 gives 2 x 2). Or a list of ``(azimuth, elevation)`` pairs
        in degrees: azimuth counter-clockwise about z from the +x axis,
        elevation above the xy plane (90 looks straight down).
    projection : {"perspective", "orthographic"}
        A pinhole camera with a 30-degree field of view, or a parallel
        projection; either is fitted to the mesh's bounding sphere.
    light : (x, y, z)
        Direction towards the light in camera coordinates (x right, y up, z
        towards the viewer); the default comes from the upper left front.
    ambient : float
        The share of light that reaches every point, in [0, 1]; the rest
        follows Lambert's cosine law on the smooth (interpolated) normal.
    background : float or (r, g, b)
        Colour of the pixels no face covers, in [0, 1].

    Returns
    -------
    numpy.ndarray
        ``(height, width, 3)`` float64 in [0, 1]; write it with
        :func:`texsynth.io.save_image`.

    Notes
    -----
    A z-buffer rasteriser vectorised over faces (see the module docstring).
    Faces turned away from the camera are skipped when the mesh is closed
    and consistently oriented; every face is lit on both sides. Pixels are sampled at their centres,
    without anti-aliasing.
    """
    mesh = as_mesh(mesh, "mesh")
    height, width = as_size(size, "size")
    pairs = _check_views(views)
    if projection not in PROJECTIONS:
        raise ValueError(f"projection must be one of {PROJECTIONS}, got {projection!r}")
    light = np.asarray(light, dtype=np.float64)
    if light.shape != (3,) or not np.all(np.isfinite(light)) or not np.any(light):
        raise ValueError(f"light must be a non-zero direction (x, y, z) in camera coordinates, got {light!r}")
    light = light / np.linalg.norm(light)
    ambient = check_in_range(ambient, "ambient", 0.0, 1.0)
    background = _check_color(background, "background")
    check_memory(height * width * _BYTES_PER_PIXEL + _BYTES_PER_CHUNK, (height, width), "size", "the preview")
    columns = math.ceil(math.sqrt(len(pairs)))
    rows = math.ceil(len(pairs) / columns)
    tile = (height // rows, width // columns)
    if min(tile) < 1:
        raise ValueError(f"size {(height, width)} is too small for {len(pairs)} views in a {rows} x {columns} grid; "
                         f"pass at least size={(rows, columns)}")
    cull = bool(np.all(mesh.face_adjacency >= 0) and not mesh._same_direction.any())  # closed, outside known
    image = np.tile(background, (height, width, 1))
    for k, (azimuth, elevation) in enumerate(pairs):
        r, c = divmod(k, columns)
        image[r * tile[0]:(r + 1) * tile[0], c * tile[1]:(c + 1) * tile[1]] = _render_view(
            mesh, tile, azimuth, elevation, projection, light, ambient, background, cull)
    return np.clip(image, 0.0, 1.0)
