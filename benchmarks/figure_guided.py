"""Texture by numbers with ``optimize_texture``: writes ``docs/_static/guided.png``.

Exemplar: grass | pebbles (``benchmarks/photos``, halved, 64 px crops) with its label map (0 grass,
1 pebbles); output guide: a disc of 1 in a field of 0 (96 x 96). The figure shows, left to right, the
exemplar over its label map, the output's label map, the guided result and the unguided result (same
seed), each enlarged 2x. Prints how much closer each region's mean colour is to the pebbles' than to
the grass's (RGB distance; + pebbles, - grass) and the times.

    python benchmarks/figure_guided.py
"""

import time
from pathlib import Path

import numpy as np

from texsynth import optimize_texture
from texsynth.optimization import Guides
from texsynth.io import load_image, save_image

HERE = Path(__file__).resolve().parent


def _half(a):
    return (a[0::2, 0::2] + a[1::2, 0::2] + a[0::2, 1::2] + a[1::2, 1::2]) / 4


def main():
    grass = _half(load_image(HERE / "photos" / "grass_1.png"))[:64, :64]
    pebbles = _half(load_image(HERE / "photos" / "pebbles_1.png"))[:64, :64]
    ex = np.concatenate([grass, pebbles], axis=1)
    labels = np.zeros((64, 128))
    labels[:, 64:] = 1
    yy, xx = np.mgrid[:96, :96]
    disc = ((yy - 47.5) ** 2 + (xx - 47.5) ** 2 <= 28**2).astype(float)
    t = time.perf_counter()
    guided = optimize_texture(ex, 96, guides=Guides(exemplar_guide=labels, output_guide=disc), rng=0)
    t_guided = time.perf_counter() - t
    t = time.perf_counter()
    plain = optimize_texture(ex, 96, rng=0)
    t_plain = time.perf_counter() - t
    mg, mp = grass.reshape(-1, 3).mean(0), pebbles.reshape(-1, 3).mean(0)
    for name, out in (("guided", guided), ("unguided", plain)):
        scores = [np.linalg.norm(out[m].mean(0) - mg) - np.linalg.norm(out[m].mean(0) - mp)
                  for m in (disc > 0, disc == 0)]
        print(f"{name}: inside {scores[0]:+.3f}, outside {scores[1]:+.3f} (pure texture: +-{np.linalg.norm(mg - mp):.3f})")
    print(f"seconds: guided {t_guided:.2f}, unguided {t_plain:.2f}")

    def big(a):
        a = np.repeat(np.repeat(a, 2, 0), 2, 1)
        return np.repeat(a[..., None], 3, -1) if a.ndim == 2 else a

    gap = np.ones((192, 8, 3))
    left = np.concatenate([ex, np.repeat(labels[..., None], 3, -1)], 0)  # 128 x 128: exemplar over labels
    left = np.repeat(np.repeat(left, 3, 0), 3, 1)[::2, ::2]  # 1.5x: 192 x 192
    fig = np.concatenate([left, gap, big(disc), gap, big(guided), gap, big(plain)], 1)
    save_image(HERE.parent / "docs" / "_static" / "guided.png", np.clip(fig, 0, 1), overwrite=True)


if __name__ == "__main__":
    main()
