"""Example shapes for geometry synthesis, made on the fly as occupancy volumes (no files)."""

from __future__ import annotations

import numpy as np

from ..core._validate import as_rng, check_choice, check_positive_int

__all__ = ["volume", "volume_names"]

#: The shapes :func:`volume` makes, and what they hold.
VOLUMES = {
    "pebbles": "separate spheres of radii 3-5 voxels, at least 2 voxels apart (26 in 48^3): separate elements",
    "plate": "a slab 4 voxels thick with rivets (hemispheres), spikes (cones) and two grooves, a third as deep "
             "as it is wide: elements joined to a base",
    "cylinder": "a plain cylinder along the depth axis, radius 0.3 size, through the whole volume (the unfiltered "
                "example A of geometric texture analogies)",
    "grooved_cylinder": "the cylinder with 8 straight grooves along its axis, 0.09 size wide and 0.06 size deep",
    "pitted_cylinder": "the cylinder with staggered rows of hemispherical pits of radius 0.06 size",
    "spiked_cylinder": "the cylinder with staggered rows of cones 0.08 size high on bases of radius 0.05 size",
    "dilated_cylinder": "the cylinder grown by 0.05 size (radius 0.35 size)",
    "torus": "a torus about the depth axis, major radius 0.3 size and tube radius 0.13 size (a target shape)",
}

#: The cylinders' radius and the torus's radii, as fractions of ``size``.
CYLINDER_RADIUS = 0.3
TORUS_RADII = (0.3, 0.13)


def volume_names():
    """Names of the example shapes, sorted."""
    return tuple(sorted(VOLUMES))


def volume(name, size=48, *, rng=1):
    """An example shape as a boolean occupancy volume ``(D, H, W)`` (True inside; see :data:`VOLUMES`).

    Examples
    --------
    >>> from texsynth import data
    >>> pebbles = data.volume("pebbles")
    >>> pebbles.shape, pebbles.dtype
    ((48, 48, 48), dtype('bool'))

    Parameters
    ----------
    name : str
        A key of :data:`VOLUMES`.
    size : int
        Side in voxels, at least 16 (``"plate"``: ``(size // 3, size, size)``).
    rng : None, int or numpy.random.Generator
        Seed of the elements' places and sizes (the cylinders and the torus
        are the same for every seed).
    """
    name = check_choice(name, "name", volume_names())
    size = check_positive_int(size, "size", minimum=16)
    gen = as_rng(rng)
    if name == "pebbles":
        return _pebbles(size, gen)
    if name == "plate":
        return _plate(size, gen)
    if name == "torus":
        return _torus(size)
    return _cylinder(size, name.partition("_")[0] if "_" in name else "plain")


def _pebbles(n, gen):
    count = max(1, round(26 * (n / 48) ** 3))
    z, y, x = np.indices((n, n, n))
    occ = np.zeros((n, n, n), bool)
    centres, radii = [], []
    for _ in range(100 * count):  # rejection sampling: spheres at least 2 voxels apart
        if len(centres) == count:
            break
        c, r = gen.uniform(0, n, 3), gen.uniform(3, 5)
        if all(np.linalg.norm(c - c2) > r + r2 + 2 for c2, r2 in zip(centres, radii)):
            centres.append(c)
            radii.append(r)
            occ |= (z - c[0]) ** 2 + (y - c[1]) ** 2 + (x - c[2]) ** 2 < r * r
    return occ


def _plate(n, gen):
    z, y, x = np.indices((n // 3, n, n)).astype(float)
    occ = z < 4
    for _ in range(max(1, round(7 * (n / 48) ** 2))):
        cy, cx, r = gen.uniform(0, n), gen.uniform(0, n), gen.uniform(3, 4.5)
        occ |= (z - 4) ** 2 + (y - cy) ** 2 + (x - cx) ** 2 < r * r
    for _ in range(max(1, round(5 * (n / 48) ** 2))):
        cy, cx, h = gen.uniform(0, n), gen.uniform(0, n), gen.uniform(7, 10)
        occ |= (z >= 4) & (np.hypot(y - cy, x - cx) < 2.5 * (1 - (z - 4) / h))
    for gy in (n // 4, 3 * n // 4):
        occ &= ~((np.abs(y - gy) < 1.5) & (z >= 2))
    return occ


def _cylinder(n, relief):
    """A cylinder along axis 0 through the volume, with a relief carved in or added to its side."""
    z, y, x = np.indices((n, n, n)).astype(float)
    c = (n - 1) / 2
    r = np.hypot(y - c, x - c)
    radius = CYLINDER_RADIUS * n
    if relief == "dilated":
        return r < radius + 0.05 * n
    occ = r < radius
    if relief == "plain":
        return occ
    phi = np.arctan2(y - c, x - c)
    if relief == "grooved":  # 8 grooves along the axis: arc distance to the nearest groove's centre line
        arc = np.abs((phi * 8 / (2 * np.pi) + 0.5) % 1 - 0.5) * 2 * np.pi / 8 * radius
        return occ & ~((arc < 0.045 * n) & (r > radius - 0.06 * n))
    # staggered rows of bumps: 8 around, a row every 0.2 size, odd rows turned by half a step
    rows = 0.2 * n
    row = np.floor(z / rows)
    zc = (row + 0.5) * rows
    turn = phi * 8 / (2 * np.pi) - 0.5 * (row % 2)
    phic = (np.round(turn) + 0.5 * (row % 2)) * 2 * np.pi / 8
    centre = np.stack([zc, c + radius * np.sin(phic), c + radius * np.cos(phic)])
    d = np.sqrt(((np.stack([z, y, x]) - centre) ** 2).sum(0))
    if relief == "pitted":
        return occ & ~(d < 0.06 * n)
    height, base = 0.08 * n, 0.05 * n  # spikes: cones standing on the surface, pointing outwards
    outwards = r - radius
    lateral = np.sqrt(np.maximum(d ** 2 - outwards ** 2, 0))
    return occ | ((outwards >= 0) & (outwards < height) & (lateral < base * (1 - outwards / height)))


def _torus(n):
    z, y, x = np.indices((n, n, n)).astype(float)
    c = (n - 1) / 2
    major, minor = TORUS_RADII[0] * n, TORUS_RADII[1] * n
    return (np.hypot(y - c, x - c) - major) ** 2 + (z - c) ** 2 < minor ** 2
