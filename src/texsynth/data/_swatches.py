"""Swatches of separate geometry elements for mesh quilting, made on the fly as triangle meshes (no files).

A swatch is one triangle mesh whose connected components are the elements: closed, outward-oriented
solids standing on the base plane ``z = 0`` (every vertex has ``z >= 0``) over the square
``[0, size] x [0, size]``. Rivets stand in rows and columns, as on a riveted plate (a swatch with
order); pebbles and spikes are placed by dart throwing until no more fit, so that no two touch and
their spacing is more even than a random arrangement's (Zhou et al. 2006 quilt swatches of this
kind).
"""

from __future__ import annotations

import numpy as np

from ..core._validate import as_rng, check_choice, check_positive_float

__all__ = ["swatch", "swatch_names", "SWATCHES"]

#: The swatches :func:`swatch` makes, and what they hold.
SWATCHES = {
    "rivets": "flat domes of radius 0.45-0.6 and height 0.3-0.4, in rows and columns about 1.6 apart (jittered by "
              "up to 0.1)",
    "pebbles": "flattened ellipsoids of half-axes 0.4-0.8 (0.25-0.4 high), turned at random, at least 0.3 apart",
    "spikes": "cones of base radius 0.3-0.45 and height 1.0-1.6, at least 0.6 apart",
}

#: Elements tried per unit of swatch area by the dart throwing (it stops when they no longer fit).
_DARTS_PER_AREA = 40
#: Clearance between dart-thrown elements.
_GAPS = {"pebbles": 0.3, "spikes": 0.6}
#: The rivets' rows: about this far apart (the swatch's side divided evenly), each rivet moved by up to the jitter.
_PITCH, _JITTER = 1.6, 0.1
_SEGMENTS = 12  # vertices around each ring of a lathed element


def swatch_names():
    """Names of the swatches, sorted."""
    return tuple(sorted(SWATCHES))


def swatch(name, size=16.0, *, rng=1):
    """A swatch of separate elements over a plane, as ``(vertices, faces)`` (see :data:`SWATCHES`).

    Examples
    --------
    >>> from texsynth.data import swatch
    >>> vertices, faces = swatch("rivets", 8.0)
    >>> vertices.shape[1], faces.shape[1], bool(vertices[:, 2].min() >= 0)
    (3, 3, True)

    Parameters
    ----------
    name : str
        ``"rivets"``, ``"pebbles"`` or ``"spikes"``.
    size : float
        Side of the square base ``[0, size]^2`` in the swatch's units (elements are about 1 unit
        across), at least 4.
    rng : None, int or numpy.random.Generator
        Seed of the elements' places, sizes and turns.

    Returns
    -------
    vertices : numpy.ndarray
        float64 ``(N, 3)``, ``z >= 0``; element centres lie in the square, an element may reach a
        little past its side.
    faces : numpy.ndarray
        int64 ``(M, 3)``, counter-clockwise seen from outside; each element is one closed component.
    """
    name = check_choice(name, "name", swatch_names())
    size = check_positive_float(size, "size")
    if size < 4:
        raise ValueError(f"size must be at least 4 swatch units (elements are about 1 across), got {size}")
    gen = as_rng(rng)
    draw, build = _KINDS[name]
    if name == "rivets":  # rows and columns, as on a riveted plate
        n = max(1, int(size / _PITCH + 1e-9))
        ij = np.stack(np.meshgrid(np.arange(n), np.arange(n), indexing="ij"), -1).reshape(-1, 2)
        centres = (ij + 0.5) * (size / n) + gen.uniform(-_JITTER, _JITTER, ij.shape)
        params = [draw(gen) for _ in centres]
    else:
        centres, params = _darts(size, gen, draw, _GAPS[name])
    vertices, faces, start = [], [], 0
    for c, p in zip(centres, params):
        v, f = build(*p)
        vertices.append(v + np.r_[c, 0.0])
        faces.append(f + start)
        start += len(v)
    return np.concatenate(vertices), np.concatenate(faces).astype(np.int64)


def _darts(size, gen, draw, gap):
    """Dart throwing: random places and shapes, each kept if it stays ``gap`` clear of those kept before."""
    centres, radii, params = [], [], []
    for _ in range(int(_DARTS_PER_AREA * size * size)):  # sequential by nature
        c, p = gen.uniform(0, size, 2), draw(gen)
        r = p[0]  # every shape's first parameter is its largest radius in the plane
        if not centres or np.all(np.hypot(*(np.array(centres) - c).T) > np.array(radii) + r + gap):
            centres.append(c)
            radii.append(r)
            params.append(p)
    return np.array(centres), params


def _lathe(radii, heights, top):
    """A closed solid of revolution about z: rings of the given radii at the given heights, a pole at
    ``z = 0`` below the first ring and one at ``z = top`` above the last."""
    angles = np.linspace(0, 2 * np.pi, _SEGMENTS, endpoint=False)
    rings = np.stack([np.outer(radii, np.cos(angles)), np.outer(radii, np.sin(angles)),
                      np.repeat(np.asarray(heights, float)[:, None], _SEGMENTS, 1)], -1).reshape(-1, 3)
    n_rings = len(radii)
    bottom, last = n_rings * _SEGMENTS, (n_rings - 1) * _SEGMENTS
    vertices = np.vstack([rings, [[0.0, 0.0, 0.0], [0.0, 0.0, top]]])
    s = np.arange(_SEGMENTS)
    s1 = (s + 1) % _SEGMENTS
    faces = [np.stack([np.full(_SEGMENTS, bottom), s1, s], 1)]  # the bottom, seen from below
    for k in range(n_rings - 1):
        a, b = k * _SEGMENTS + s, k * _SEGMENTS + s1
        faces += [np.stack([a, b, b + _SEGMENTS], 1), np.stack([a, b + _SEGMENTS, a + _SEGMENTS], 1)]
    faces.append(np.stack([last + s, last + s1, np.full(_SEGMENTS, bottom + 1)], 1))
    return vertices, np.concatenate(faces)


def _rivet(radius, height):
    theta = np.linspace(0, np.pi / 2, 5)[:-1]  # from the rim up, the top pole closes the dome
    return _lathe(radius * np.cos(theta), height * np.sin(theta), height)


def _pebble(radius, minor, half_height, turn):
    theta = np.linspace(0, np.pi, 7)[1:-1]  # latitude rings of an ellipsoid resting on z = 0
    vertices, faces = _lathe(np.sin(theta), half_height * (1 - np.cos(theta)), 2 * half_height)
    vertices[:, 0] *= radius
    vertices[:, 1] *= minor
    rot = np.array([[np.cos(turn), -np.sin(turn)], [np.sin(turn), np.cos(turn)]])
    vertices[:, :2] = vertices[:, :2] @ rot.T
    return vertices, faces


def _spike(radius, height):
    return _lathe(np.array([radius, 0.5 * radius]), np.array([0.0, 0.5 * height]), height)


def _pebble_params(gen):
    a, b = np.sort(gen.uniform([0.4, 0.5], [0.6, 0.8]))  # half-axes, the larger first
    return b, a, gen.uniform(0.25, 0.4), gen.uniform(0, np.pi)


#: Per swatch: its parameters drawn (the first is the element's largest radius in the plane), its mesh made.
_KINDS = {
    "rivets": (lambda gen: (gen.uniform(0.45, 0.6), gen.uniform(0.3, 0.4)), _rivet),
    "pebbles": (_pebble_params, _pebble),
    "spikes": (lambda gen: (gen.uniform(0.3, 0.45), gen.uniform(1.0, 1.6)), _spike),
}
