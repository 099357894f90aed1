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
}


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
        ``"pebbles"`` or ``"plate"``.
    size : int
        Side in voxels, at least 16 (``"plate"``: ``(size // 3, size, size)``).
    rng : None, int or numpy.random.Generator
        Seed of the elements' places and sizes.
    """
    name = check_choice(name, "name", volume_names())
    size = check_positive_int(size, "size", minimum=16)
    gen = as_rng(rng)
    return _pebbles(size, gen) if name == "pebbles" else _plate(size, gen)


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
