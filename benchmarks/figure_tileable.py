"""Tileable outputs of Efros-Leung, Wang tiles and Wei-Levoy (scanline): writes ``docs/_static/tileable_methods.png``.

Each output tiled 2x2, plain (top row) and with ``tileable=True`` (bottom row), from a crop of
``benchmarks/photos/pebbles_1.png`` at quarter size, and prints the seam visibility of each (the mean
absolute difference across the wrap-around seams over the mean inside the image: about 1 when the
seam is as invisible as any other row and column; ``tests/test_tileable.py`` measures the same).

    python benchmarks/figure_tileable.py
"""

import time
from pathlib import Path

import numpy as np

from texsynth import efros_leung, synthesize_pixels, wang_texture
from texsynth.io import load_image, save_image

HERE = Path(__file__).resolve().parent


def seam_ratio(image):
    t = np.tile(image, (2, 2, 1))
    h, w = image.shape[:2]
    rows = np.abs(np.diff(t, axis=0)).mean(axis=(1, 2))
    cols = np.abs(np.diff(t, axis=1)).mean(axis=(0, 2))
    return ((rows[h - 1] + cols[w - 1]) / 2) / ((np.delete(rows, h - 1).mean() + np.delete(cols, w - 1).mean()) / 2)


def main():
    pebbles = load_image(HERE / "photos" / "pebbles_1.png")[::4, ::4]
    methods = {
        "efros_leung (w 9)": lambda t: efros_leung(pebbles[:48, :48], 96, neighborhood_size=9, tileable=t, rng=0),
        "wang_texture (tile 24)": lambda t: wang_texture(pebbles, 96, tile=24, tileable=t, rng=0),
        "synthesize_pixels (scanline)": lambda t: synthesize_pixels(pebbles[:64, :64], 96, tileable=t, rng=0),
    }
    columns = []
    for name, run in methods.items():
        pair = []
        for tileable in (False, True):
            t = time.perf_counter()
            out = run(tileable)
            print(f"{name:<30} tileable={tileable!s:<5} seam {seam_ratio(out):.2f}  {time.perf_counter() - t:.1f} s")
            pair.append(np.tile(out, (2, 2, 1)))
        columns.append(np.concatenate([pair[0], np.ones((8, 192, 3)), pair[1]], 0))
    gap = np.ones((columns[0].shape[0], 8, 3))
    figure = np.concatenate([c for column in columns for c in (column, gap)][:-1], 1)
    save_image(HERE.parent / "docs" / "_static" / "tileable_methods.png",
               np.repeat(np.repeat(np.clip(figure, 0, 1), 2, 0), 2, 1), overwrite=True)


if __name__ == "__main__":
    main()
