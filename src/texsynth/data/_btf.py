"""Example BTF samples, rendered on the fly from procedural height fields (no files)."""

from __future__ import annotations

import numpy as np

from ..core._validate import as_rng, check_choice, check_memory, check_positive_int

__all__ = ["btf", "btf_names"]

#: The samples :func:`btf` makes, and what they hold.
BTFS = {
    "stones": "rounded stones (ellipsoid domes, radii 5-9 pixels, 0.7 times as high) on a flat ground: "
              "separate elements that cast shadows on the ground",
    "bumps": "overlapping Gaussian bumps (sigma 3-10 pixels): a rolling surface whose bumps shadow each other",
}

_AZIMUTHS = 8                      # light directions per ring of equal elevation
_ELEVATIONS = (25.0, 75.0)         # degrees above the surface of the lowest and the highest ring
_AMBIENT = 0.1                     # light that reaches shadowed points


def btf_names():
    """Names of the example BTFs, sorted."""
    return tuple(sorted(BTFS))


def btf(name="stones", size=128, *, n_lights=64, rng=1):
    """An example BTF sample: a height field rendered under a grid of light directions (see :data:`BTFS`).

    Examples
    --------
    >>> from texsynth import data
    >>> sample = data.btf("stones", 32, n_lights=16)
    >>> sample.images.shape, sample.lights.shape
    ((16, 32, 32), (16, 3))

    Each image is the height field seen from straight above (one view
    direction, orthographic), lit by one distant light: Lambert shading of
    the height field's normals times the albedo, and black but for an
    ambient tenth where the light is blocked: a cast shadow, found by
    marching from each pixel towards the light over the (toroidal) height
    field. The lights lie on rings of 8 azimuths, 45 degrees apart (every
    other ring turned by 22.5), at ``n_lights / 8`` elevations evenly from 25
    to 75 degrees. The sample is periodic (it tiles).

    Parameters
    ----------
    name : str
        ``"stones"`` or ``"bumps"``.
    size : int
        Side in pixels, at least 16.
    n_lights : int
        Light directions, a multiple of 8 (default 64: 8 elevations).
    rng : None, int or numpy.random.Generator
        Seed of the height field.

    Returns
    -------
    texsynth.core.btf.BTF
        Images ``(n_lights, size, size)`` in [0, 1] with their light
        directions (x along the columns, y up the rows, z up).
    """
    from ..core.btf import BTF  # on first use: texsynth.data stays light to import

    name = check_choice(name, "name", btf_names())
    size = check_positive_int(size, "size", minimum=16)
    n_lights = check_positive_int(n_lights, "n_lights", minimum=_AZIMUTHS)
    if n_lights % _AZIMUTHS:
        raise ValueError(f"n_lights must be a multiple of {_AZIMUTHS} (rings of {_AZIMUTHS} azimuths), got "
                         f"{n_lights}; pass {_AZIMUTHS * max(1, round(n_lights / _AZIMUTHS))}")
    check_memory(8.0 * (n_lights + 6) * size * size, size, "size", "the BTF", also={"n_lights": n_lights})
    gen = as_rng(rng)
    height, albedo = (_stones if name == "stones" else _bumps)(size, gen)
    lights = _light_grid(n_lights // _AZIMUTHS)
    images = np.stack([_shade(height, albedo, light) for light in lights])
    return BTF(np.clip(images, 0.0, 1.0), lights)


def _light_grid(rings):
    elevation = np.radians(np.linspace(*_ELEVATIONS, rings) if rings > 1 else [np.mean(_ELEVATIONS)])
    lights = []
    for i, e in enumerate(elevation):
        azimuth = np.radians(np.arange(_AZIMUTHS) * 360.0 / _AZIMUTHS + (22.5 if i % 2 else 0.0))
        lights.append(np.stack([np.cos(e) * np.cos(azimuth), np.cos(e) * np.sin(azimuth),
                                np.full(_AZIMUTHS, np.sin(e))], axis=1))
    return np.concatenate(lights)


def _toroidal_offsets(size, center):
    """Signed distances of every row / column to ``center`` on a torus of ``size``."""
    d = np.arange(size) - center
    return (d + size / 2) % size - size / 2


def _stones(n, gen):
    height, albedo = np.zeros((n, n)), np.full((n, n), 0.45)
    count = max(3, round(0.4 * (n / 12.0) ** 2))
    for _ in range(count):
        r = gen.uniform(5.0, 9.0)
        cy, cx = gen.uniform(0, n, 2)
        dy, dx = _toroidal_offsets(n, cy)[:, None], _toroidal_offsets(n, cx)[None, :]
        dome = 0.7 * r * np.sqrt(np.clip(1 - (dy * dy + dx * dx) / (r * r), 0, None))
        higher = dome > height
        height[higher] = dome[higher]
        albedo[higher] = gen.uniform(0.7, 0.95)
    return height, albedo


def _bumps(n, gen):
    height = np.zeros((n, n))
    for _ in range(max(4, round((n / 10.0) ** 2))):
        r = gen.uniform(3.0, 10.0)
        cy, cx = gen.uniform(0, n, 2)
        dy, dx = _toroidal_offsets(n, cy)[:, None], _toroidal_offsets(n, cx)[None, :]
        height += 0.8 * r * np.exp(-(dy * dy + dx * dx) / (2 * r * r))
    return height, np.full((n, n), 0.85)


def _shade(height, albedo, light):
    """Lambert shading with cast shadows of a toroidal height field (in pixels) under a distant light."""
    n = height.shape[0]
    dx = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) / 2       # d height / d column
    dy = -(np.roll(height, -1, 0) - np.roll(height, 1, 0)) / 2      # d height / d up (towards row 0)
    lambert = np.clip((-dx * light[0] - dy * light[1] + light[2]) / np.sqrt(dx * dx + dy * dy + 1), 0, None)
    import scipy.ndimage as ndi  # on first use, as BTF above

    horizontal = np.hypot(light[0], light[1])
    lit = np.ones_like(height, dtype=bool)
    if horizontal > 1e-9:
        rise = light[2] / horizontal                                # height gained per pixel towards the light
        rows, cols = np.mgrid[0:n, 0:n].astype(np.float64)
        for s in np.arange(0.5, (height.max() - height.min()) / rise + 1.0, 0.5):
            ahead = ndi.map_coordinates(height, [rows - s * light[1] / horizontal, cols + s * light[0] / horizontal],
                                        order=1, mode="grid-wrap")
            lit &= ahead <= height + s * rise + 1e-9
    return albedo * (_AMBIENT + (1 - _AMBIENT) * lambert * lit)
