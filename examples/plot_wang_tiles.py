"""
Wang tiles: 8 tiles quilted from diamonds, tiled at random (Cohen et al. 2003)
==============================================================================

From a 256 x 256 exemplar, ``wang_tiles`` makes the paper's minimal complete set:
two colours per direction, 8 tiles of 128 x 128 pixels, each covered by the four
diamond-shaped samples of its edges' colours joined along minimum-error cuts
along its diagonals. ``wang_tiling`` then lays them at random in scanline order,
each tile's north and west colours matching its neighbours', into a 1024 x 1024
texture: 64 tiles, no two neighbours joined by anything but the exemplar itself.

Two exemplars: a brick wall (``skimage.data.brick()``, regular) and water caustics
(the bundled ``water``, stochastic). Writes the tile sets, the 1024 x 1024 tilings
and the figure ``wang_tiles.png`` to ``examples/output/``; ``python plot_wang_tiles.py
--docs`` in a checkout also refreshes the documentation's copy in ``docs/_static/``.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata

from texsynth import data
from texsynth.io import save_image
from texsynth.patch import wang_tiles, wang_tiling

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figure of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])

exemplars = {"brick": skdata.brick()[:256, :256] / 255.0, "water": data.load("water")[:256, :256]}


def sheet(tiles, gap=4):
    """The tiles in two rows of four, on white."""
    t = tiles.tiles if tiles.tiles.ndim == 4 else tiles.tiles[..., None]
    T = t.shape[1]
    out = np.ones((2 * T + gap, 4 * T + 3 * gap, t.shape[3]))
    for i in range(8):
        r, c = divmod(i, 4)
        out[r * (T + gap):r * (T + gap) + T, c * (T + gap):c * (T + gap) + T] = t[i]
    return out if tiles.tiles.ndim == 4 else out[..., 0]


fig, axes = plt.subplots(2, 3, figsize=(14.5, 7.4), gridspec_kw={"width_ratios": [1, 2, 1]})
for row, (name, ex) in enumerate(exemplars.items()):
    started = time.perf_counter()
    tiles, info = wang_tiles(ex, 128, rng=0, return_info=True)
    made = time.perf_counter() - started
    started = time.perf_counter()
    out, tiling = wang_tiling(tiles, 1024, rng=0, return_info=True)
    print(f"{name}: 8 tiles of 128 px in {made:.2f} s (cut errors {info.seam_costs.sum():.1f}); "
          f"1024 x 1024 tiling in {time.perf_counter() - started:.3f} s; edges {tiles.edges.tolist()}")
    save_image(OUT / f"wang_tiles_{name}_set.png", sheet(tiles), overwrite=True)
    save_image(OUT / f"wang_tiles_{name}_1024.png", out, overwrite=True)
    cmap = "gray" if ex.ndim == 2 else None
    for ax, image, title in zip(axes[row], (ex, sheet(tiles), out),
                                (f"exemplar ({name}, 256 px)", "8 Wang tiles of 128 px (N, E, S, W colours)",
                                 "a 1024 x 1024 tiling (64 tiles)")):
        ax.imshow(image, cmap=cmap, vmin=0, vmax=1)
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    for i, edge in enumerate(tiles.edges):
        r, c = divmod(i, 4)
        axes[row, 1].text(c * 132 + 64, r * 132 + 64, "".join(map(str, edge)), color="yellow", fontsize=7,
                          ha="center", va="center")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "wang_tiles.png", dpi=80)
