"""A mixture of two materials and its height channel through the map: writes ``docs/_static/pbr_mixture.png``.

Two materials (the bundled ``brick`` and ``bread`` albedos, each with a height made from its blurred,
inverted luminance) are mixed by ``mix_textures`` with ramp weights (brick at the left, bread at the
right); the heights are rendered through ``info.coordinates`` with one image per source
(``info.source_index``), and the rendered height is lit from the upper left. Top: the mixed albedo;
middle: the height through the map; bottom: the height lit. Prints the times and the share of pixels
that blend both sources.

    python benchmarks/figure_mix_channels.py
"""

import time
from pathlib import Path

import numpy as np
from scipy import ndimage

from texsynth import apply_coordinates, data, mix_textures
from texsynth.io import save_image

HERE = Path(__file__).resolve().parent


def height_of(albedo):
    return 1.0 - ndimage.gaussian_filter(albedo.mean(-1), 1.5)


def lit(height, strength=8.0, light=(-1.0, 1.0, 1.5)):
    gy, gx = np.gradient(height)
    n = np.stack([-strength * gx, strength * gy, np.ones_like(height)], -1)
    n /= np.linalg.norm(n, axis=-1, keepdims=True)
    return np.clip(n @ (np.array(light) / np.linalg.norm(light)), 0, 1)


def main():
    a, b = data.load("brick")[:64, :64], data.load("bread")[:64, :64]
    ramp = np.broadcast_to(np.linspace(0.0, 1.0, 256), (96, 256))
    t = time.perf_counter()
    mix, info = mix_textures([a, b], (96, 256), weights=[1 - ramp, ramp], rng=0, return_info=True)
    t_mix = time.perf_counter() - t
    t = time.perf_counter()
    height = apply_coordinates([height_of(a), height_of(b)], info)  # one image per source
    t_apply = time.perf_counter() - t
    print(f"mix_textures {t_mix:.1f} s, apply_coordinates {1000 * t_apply:.1f} ms, map {info.coordinates.shape}, "
          f"pixels blending both sources {np.mean(info.weights[..., 1] > 0):.0%}")
    grey = [np.repeat(x[..., None], 3, -1) for x in (height, lit(height))]
    gap = np.ones((6, 256, 3))
    figure = np.concatenate([mix, gap, grey[0], gap, grey[1]], 0)
    save_image(HERE.parent / "docs" / "_static" / "pbr_mixture.png",
               np.repeat(np.repeat(np.clip(figure, 0, 1), 2, 0), 2, 1), overwrite=True)


if __name__ == "__main__":
    main()
