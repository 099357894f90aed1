"""Simulated clips for the video methods: made on the fly, deterministic for a seed, no files.

No photographed clip with a licence that allows bundling was found among the packages texsynth can
draw on (benchmarks/clips/README.md lists what was searched and the two real clips kept there for
benchmarks), so the examples, the demo and the docs use these simulations.
"""

from __future__ import annotations

import numpy as np

from ..core._validate import as_rng, check_choice, check_positive_int

__all__ = ["clip", "clip_names"]

#: The clips :func:`clip` makes, and what they show.
CLIPS = {
    "flame": "a candle flame that sways, stretches and flickers with three incommensurate periods "
             "(41, 17.3 and 9.7 frames) while turbulence rises through it",
    "rain": "a water surface hit by sparse raindrops: rings spreading and fading (a damped wave equation)",
    "waves": "choppy water: a damped wave equation stirred by dense random drops, shaded by its slope",
}


def clip_names():
    """Names of the simulated clips, sorted."""
    return tuple(sorted(CLIPS))


def clip(name, n_frames=64, size=128, *, rng=0):
    """A simulated clip ``(n_frames, size, size, 3)`` in [0, 1] (see :data:`CLIPS`).

    Examples
    --------
    >>> from texsynth import data
    >>> data.clip("waves", n_frames=8, size=32).shape
    (8, 32, 32, 3)

    Parameters
    ----------
    name : str
        ``"flame"``, ``"rain"`` or ``"waves"``.
    n_frames : int
        Frames, at least 2.
    size : int
        Side of the square frames in pixels, at least 16.
    rng : None, int or numpy.random.Generator
        Seed of the drops (``"rain"``, ``"waves"``) or of the flame's turbulence.
    """
    name = check_choice(name, "name", clip_names())
    n_frames = check_positive_int(n_frames, "n_frames", minimum=2)
    size = check_positive_int(size, "size", minimum=16)
    gen = as_rng(rng)
    if name == "flame":
        return _flame(n_frames, size, gen)
    return _water(n_frames, size, gen, drops=1.5 if name == "waves" else 0.3)


def _water(n_frames, size, gen, *, drops, warmup=300):
    """A shaded water surface: the height ``h`` follows ``h_tt = c^2 laplacian(h) - damping h_t`` on a
    periodic grid (two explicit steps per frame); each step adds Poisson(``drops``) Gaussian dents (width
    about 5 px) at random places. Frames are shaded by the slope towards the upper left, deep to light blue.
    """
    h = np.zeros((size, size))
    v = np.zeros_like(h)
    axis = np.arange(size)
    frames = []
    for step in range(warmup + n_frames):
        for _ in range(2):
            for _ in range(gen.poisson(drops)):
                r, c = gen.integers(size, size=2)
                dy = np.minimum(np.abs(axis - r), size - np.abs(axis - r))
                dx = np.minimum(np.abs(axis - c), size - np.abs(axis - c))
                h -= np.exp(-(dy[:, None] ** 2 + dx[None, :] ** 2) / 12.0)
            lap = np.roll(h, 1, 0) + np.roll(h, -1, 0) + np.roll(h, 1, 1) + np.roll(h, -1, 1) - 4 * h
            v += 0.25 * lap - 0.02 * v
            h += v
        if step >= warmup:
            frames.append(h.copy())
    height = np.stack(frames)
    slope = (np.roll(height, -1, 1) - np.roll(height, 1, 1)) + (np.roll(height, -1, 2) - np.roll(height, 1, 2))
    shade = 0.5 + 0.5 * np.tanh(0.7 * slope / (2 * slope.std() / 0.7 + 1e-12))
    deep, light = np.array([0.10, 0.35, 0.55]), np.array([0.85, 0.95, 1.0])
    return np.clip(deep + 0.9 * shade[..., None] * (light - deep), 0, 1)


def _hot(v):
    """Black - red - yellow - white."""
    v = np.clip(v, 0, 1)[..., None]
    return np.clip(np.concatenate([3 * v, 3 * v - 1, 3 * v - 2], -1), 0, 1)


def _flame(n_frames, size, gen):
    """A candle in a dark room: the flame sways, stretches and flickers with periods of 41, 17.3 and 9.7
    frames, and a smooth turbulent pattern rises through it by 2 px a frame (periodic over ``size / 2``
    frames), so no frame comes back exactly."""
    t = np.arange(n_frames, dtype=float)[:, None, None]
    yy, xx = np.mgrid[:size, :size].astype(float)
    s = size / 128
    base, cx = 92 * s, 64 * s
    sway = 5 * np.sin(2 * np.pi * t / 41) + 2.5 * np.sin(2 * np.pi * t / 17.3 + 1.0)  # pixels, at the tip
    height = (46 + 5 * np.sin(2 * np.pi * t / 9.7) + 3 * np.sin(2 * np.pi * t / 41 + 2.0)) * s
    u = (base - yy) / height  # 0 at the wick, 1 at the tip
    centre = cx + s * sway * np.clip(u, 0, None) ** 2
    width = 10 * s * np.sqrt(np.clip(u + 0.08, 0, None)) * np.clip(1.05 - u, 0, None) ** 0.7 + 1e-3
    body = np.exp(-(((xx - centre) / width) ** 2)) * (u > -0.08) * np.clip(1.1 - u, 0, 1)
    field = gen.standard_normal((size, size))
    k = np.fft.fftfreq(size)
    smooth = np.real(np.fft.ifft2(np.fft.fft2(field) * np.exp(-(k[:, None] ** 2 + k[None, :] ** 2) / (2 * 0.04**2))))
    smooth /= smooth.std()
    rows = (yy[None].astype(int) + 2 * np.arange(n_frames)[:, None, None]) % size
    turbulence = smooth[rows, xx[None].astype(int)]
    flicker = 1 + 0.06 * np.sin(2 * np.pi * t / 9.7 + 0.5)
    heat = body * (0.8 + 0.2 * turbulence) * flicker
    frame = _hot(1.15 * heat - 0.15 * np.clip(u, 0, 1) * body)
    light = np.exp(-((xx - cx) ** 2 + (yy - base + 20 * s) ** 2) / (2 * (40 * s) ** 2))
    glow = 0.10 * flicker[..., None] * light[..., None]
    room = np.array([0.04, 0.035, 0.05]) + glow * np.array([1.0, 0.6, 0.3])
    candle = ((np.abs(xx - cx) < 11 * s) & (yy > base + 3 * s))[..., None]
    wax = np.array([0.82, 0.78, 0.70]) * (0.75 + 2.5 * glow)
    scene = np.where(candle, wax, room)
    wick = ((np.abs(xx - cx) < 1.2 * s) & (yy > base - 2 * s) & (yy <= base + 3 * s))[..., None]
    scene = np.where(wick, 0.05, scene)
    return np.clip(1 - (1 - scene) * (1 - frame), 0, 1)  # the flame screened over the scene
