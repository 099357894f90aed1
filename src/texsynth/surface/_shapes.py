"""Test surfaces: a geodesic sphere, a torus, a bumpy sphere, and a real scan (the Stanford bunny).

All are closed two-manifolds with faces counter-clockwise seen from outside,
so their face normals point outwards; they pass :func:`as_mesh`.
"""

from __future__ import annotations

import base64
import importlib.util
import re
import zlib
from pathlib import Path

import numpy as np

from ..core._extras import install_hint
from ..core._validate import as_rng, check_in_range, check_memory, check_positive_float, check_positive_int
from ._mesh import Mesh

__all__ = ["sphere", "torus", "bumpy", "scanned_mesh", "SCANNED_MESHES"]

# the 20 faces of the icosahedron on its 12 corners (0, +-1, +-phi) and cyclic permutations,
# counter-clockwise seen from outside
_PHI = (1 + np.sqrt(5)) / 2
_ICOSAHEDRON_VERTICES = np.array([[-1, _PHI, 0], [1, _PHI, 0], [-1, -_PHI, 0], [1, -_PHI, 0],
                                  [0, -1, _PHI], [0, 1, _PHI], [0, -1, -_PHI], [0, 1, -_PHI],
                                  [_PHI, 0, -1], [_PHI, 0, 1], [-_PHI, 0, -1], [-_PHI, 0, 1]])
_ICOSAHEDRON_FACES = np.array([[0, 11, 5], [0, 5, 1], [0, 1, 7], [0, 7, 10], [0, 10, 11],
                               [1, 5, 9], [5, 11, 4], [11, 10, 2], [10, 7, 6], [7, 1, 8],
                               [3, 9, 4], [3, 4, 2], [3, 2, 6], [3, 6, 8], [3, 8, 9],
                               [4, 9, 5], [2, 4, 11], [6, 2, 10], [8, 6, 7], [9, 8, 1]])

# scans shipped by other packages: name -> (package, file inside it, where the data come from)
SCANNED_MESHES = {
    "bunny": ("visvis", "visvisResources/bunny.ssdf",
              "the Stanford Bunny (Turk & Levoy 1994, Stanford 3D Scanning Repository), holes closed, as "
              "shipped in the visvis package"),
}

# the most memory a shape holds at once, per vertex: numpy's arrays and the Python objects of the
# subdivision, as tracemalloc counts them (about 450 bytes for the sphere, 220 for the torus), with a margin
_SPHERE_BYTES = 512
_TORUS_BYTES = 320
_WAVES = 32  # plane waves of bumpy's noise
_LENGTHS = (1e-75, 1e75)  # lengths whose fourth powers (squared areas) stay normal float64 numbers; frequencies too


def _check_length(value, name):
    """A radius or frequency in ``_LENGTHS``."""
    value = check_positive_float(value, name, maximum=_LENGTHS[1])
    if value < _LENGTHS[0]:
        raise ValueError(f"{name} must be at least {_LENGTHS[0]:g} (smaller, areas underflow), got {value:g}")
    return value


def _check_memory(n_vertices, vertices, per_vertex):
    """Refuse, before allocating, a shape of ``vertices`` vertices that cannot fit (``n_vertices`` asked)."""
    check_memory(float(vertices) * per_vertex, n_vertices, "n_vertices", "the mesh")


def _geodesic_frequency(n_vertices):
    """The subdivision frequency ``f`` whose geodesic sphere (``10 f**2 + 2`` vertices) is closest to ``n_vertices``."""
    return max(1, int(round(np.sqrt(max(n_vertices - 2, 10) / 10))))


def _unit_sphere(frequency):
    """Class I geodesic sphere: every icosahedron face cut into ``frequency**2`` triangles, projected out.

    A grid point of face ``(a, b, c)`` is ``(i * A + j * B + k * C) / f`` with ``i + j + k = f``; it is
    identified across faces by its integer weights on the 12 icosahedron corners, so shared edges and
    corners become one vertex exactly (no tolerance).
    """
    f = frequency
    j, k = np.nonzero(np.add.outer(np.arange(f + 1), np.arange(f + 1)) <= f)  # weights of corners b and c
    i = f - j - k
    local = {(jj, kk): n for n, (jj, kk) in enumerate(zip(j.tolist(), k.tolist()))}
    weights = np.zeros((20, len(i), 12), dtype=np.int64)
    rows = np.arange(20)[:, None]
    for corner, w in enumerate((i, j, k)):
        weights[rows, np.arange(len(i)), _ICOSAHEDRON_FACES[:, corner][:, None]] += w
    keys, index = np.unique(weights.reshape(-1, 12), axis=0, return_inverse=True)
    index = index.reshape(20, len(i))
    # small triangles of one face, on the local (j, k) grid: "up" (j, k), (j+1, k), (j, k+1) and
    # "down" (j+1, k), (j+1, k+1), (j, k+1); both keep the big face's orientation
    up = [(a, b) for a, b in local if a + b <= f - 1]
    down = [(a, b) for a, b in local if a + b <= f - 2]
    tri = np.array([[local[a, b], local[a + 1, b], local[a, b + 1]] for a, b in up]
                   + [[local[a + 1, b], local[a + 1, b + 1], local[a, b + 1]] for a, b in down])
    faces = index[:, tri].reshape(-1, 3)
    points = keys @ _ICOSAHEDRON_VERTICES / f
    return points / np.linalg.norm(points, axis=1, keepdims=True), faces


def sphere(n_vertices=2562, *, radius=1.0):
    """A geodesic sphere: the icosahedron subdivided and projected onto the sphere.

    Parameters
    ----------
    n_vertices : int
        About how many vertices: the sphere has ``10 f**2 + 2`` vertices and
        ``20 f**2`` faces for the subdivision frequency ``f`` that comes
        closest (12, 42, 92, 162, ..., 2562 for ``f = 16``, 10242 for 32).
    radius : float
        The sphere's radius.

    Returns
    -------
    Mesh
        Centred at the origin, closed (Euler characteristic 2), faces
        counter-clockwise seen from outside. Edge lengths vary by about 20 %
        between the icosahedron's corners and its face centres.

    Examples
    --------
    >>> sphere(100)
    Mesh(92 vertices, 180 faces)
    """
    n_vertices = check_positive_int(n_vertices, "n_vertices")
    radius = _check_length(radius, "radius")
    frequency = _geodesic_frequency(n_vertices)
    _check_memory(n_vertices, 10 * frequency**2 + 2, _SPHERE_BYTES)
    points, faces = _unit_sphere(frequency)
    return Mesh(radius * points, faces)


def torus(n_vertices=2500, *, major_radius=1.0, minor_radius=0.4):
    """A torus around the z axis, triangulated on a regular grid of its two angles.

    Parameters
    ----------
    n_vertices : int
        About how many vertices; the grid has about ``major_radius /
        minor_radius`` times more steps around the axis than around the tube,
        so that its cells are close to square (at least 3 each way).
    major_radius : float
        Distance from the z axis to the centre of the tube.
    minor_radius : float
        Radius of the tube; less than ``major_radius``.

    Returns
    -------
    Mesh
        Closed, genus one (Euler characteristic 0), faces counter-clockwise
        seen from outside.

    Examples
    --------
    >>> torus(100, major_radius=2.0, minor_radius=0.5)
    Mesh(100 vertices, 200 faces)
    """
    n_vertices = check_positive_int(n_vertices, "n_vertices")
    major_radius = _check_length(major_radius, "major_radius")
    minor_radius = _check_length(minor_radius, "minor_radius")
    if minor_radius >= major_radius:
        raise ValueError(f"minor_radius ({minor_radius}) must be less than major_radius ({major_radius}), or the "
                         "tube intersects itself")
    n_tube = max(3, int(round(np.sqrt(n_vertices * minor_radius / major_radius))))
    n_around = max(3, int(round(n_vertices / n_tube)))
    _check_memory(n_vertices, n_around * n_tube, _TORUS_BYTES)
    u, v = np.meshgrid(2 * np.pi * np.arange(n_around) / n_around, 2 * np.pi * np.arange(n_tube) / n_tube,
                       indexing="ij")
    ring = major_radius + minor_radius * np.cos(v)
    points = np.stack([ring * np.cos(u), ring * np.sin(u), minor_radius * np.sin(v)], axis=-1).reshape(-1, 3)
    a, b = np.meshgrid(np.arange(n_around), np.arange(n_tube), indexing="ij")
    corner = a * n_tube + b
    right = (a + 1) % n_around * n_tube + b  # one step around the axis
    up = a * n_tube + (b + 1) % n_tube  # one step around the tube
    diagonal = (a + 1) % n_around * n_tube + (b + 1) % n_tube
    faces = np.concatenate([np.stack([corner, right, diagonal], -1).reshape(-1, 3),
                            np.stack([corner, diagonal, up], -1).reshape(-1, 3)])
    return Mesh(points, faces)


def bumpy(n_vertices=10242, *, radius=1.0, amplitude=0.15, frequency=2.0, rng=None):
    """A sphere displaced along its normals by smooth random noise.

    The noise is a sum of 32 plane waves ``cos(2 pi frequency d . x + phase)``
    with random unit directions ``d`` and phases, scaled so that its largest
    absolute value over the vertices is 1; vertex ``x`` of the unit sphere
    moves to ``radius * (1 + amplitude * noise(x)) * x``. The surface stays
    star-shaped about the origin, so it cannot intersect itself.

    Parameters
    ----------
    n_vertices : int
        About how many vertices, as in :func:`sphere`.
    radius : float
        Radius of the undisplaced sphere.
    amplitude : float
        Largest displacement as a fraction of ``radius``, in [0, 1).
    frequency : float
        Waves per unit length on the unit sphere: about ``frequency`` bumps
        across a diameter.
    rng : None, int or numpy.random.Generator
        Seed of the directions and phases; the same seed gives the same shape.

    Returns
    -------
    Mesh
        Closed (Euler characteristic 2), faces counter-clockwise seen from outside.

    Examples
    --------
    >>> bool(np.all(bumpy(642, rng=0).vertices == bumpy(642, rng=0).vertices))
    True
    """
    n_vertices = check_positive_int(n_vertices, "n_vertices")
    radius = _check_length(radius, "radius")
    amplitude = check_in_range(amplitude, "amplitude", 0.0, 1.0, high_open=True)
    frequency = _check_length(frequency, "frequency")
    rng = as_rng(rng)
    sphere_frequency = _geodesic_frequency(n_vertices)
    # the sphere's, or its mesh (72 bytes per vertex) and three (N, 32) float64 arrays of the waves
    _check_memory(n_vertices, 10 * sphere_frequency**2 + 2, max(_SPHERE_BYTES, 72 + 3 * 8 * _WAVES))
    points, faces = _unit_sphere(sphere_frequency)
    directions = rng.normal(size=(_WAVES, 3))
    directions /= np.linalg.norm(directions, axis=1, keepdims=True)
    phases = rng.uniform(0, 2 * np.pi, size=_WAVES)
    noise = np.cos(2 * np.pi * frequency * points @ directions.T + phases).sum(axis=1)
    noise /= np.abs(noise).max()
    return Mesh(radius * (1 + amplitude * noise)[:, None] * points, faces)


def _read_ssdf_arrays(path):
    """The arrays of a visvis SSDF text file: lines ``name = array SHAPE DTYPE base64(zlib(bytes))``."""
    arrays = {}
    for line in Path(path).read_text(encoding="utf-8").splitlines():
        found = re.match(r"(\w+) = array ([\dx]+) (\w+) (\S+)$", line)
        if found:
            name, shape, dtype, data = found.groups()
            values = np.frombuffer(zlib.decompress(base64.b64decode(data)), dtype=np.dtype(dtype).newbyteorder("<"))
            arrays[name] = values.reshape(tuple(int(s) for s in shape.split("x")))
    return arrays


def scanned_mesh(name="bunny"):
    """A real 3-D scan, read from the package that ships it (the ``mesh`` extra).

    Parameters
    ----------
    name : str
        ``"bunny"``: the Stanford Bunny (Turk & Levoy 1994), 34,835 vertices
        and 69,666 faces, the holes of the original scan closed, as shipped
        in the visvis package (BSD licence; the data are the Stanford 3D
        Scanning Repository's, which asks, as its terms are commonly quoted,
        that the Stanford Computer Graphics Laboratory be credited and that the
        model not be used commercially without its permission). See
        :data:`SCANNED_MESHES`.

    Returns
    -------
    Mesh
        Centred on its bounding box and scaled so that the farthest vertex is
        at distance 1 from the centre; z points up.

    Raises
    ------
    ModuleNotFoundError
        If the package that ships the scan is not installed: ``pip install '.[mesh]'``
        in a checkout.
    """
    if not isinstance(name, str) or name not in SCANNED_MESHES:
        raise ValueError(f"name must be one of {sorted(SCANNED_MESHES)}, got {name!r}")
    package, inside, _ = SCANNED_MESHES[name]
    spec = importlib.util.find_spec(package)  # locates the package without importing it (visvis imports OpenGL)
    if spec is None or not spec.submodule_search_locations:
        raise ModuleNotFoundError(f"scanned_mesh({name!r}) reads the scan shipped by the {package} package, which "
                                  f"is not installed; {install_hint('mesh')}")
    arrays = _read_ssdf_arrays(Path(spec.submodule_search_locations[0]) / inside)
    vertices = arrays["vertices"].astype(np.float64)
    vertices -= vertices.min(axis=0) / 2 + vertices.max(axis=0) / 2
    vertices /= np.linalg.norm(vertices, axis=1).max()
    return Mesh(vertices, arrays["faces"].reshape(-1, 3).astype(np.int64))
