"""
Tiling and blending: infinite by-example noise
==============================================

Heitz & Neyret (HPG 2018) cover the plane with a triangle grid, give every
vertex a random piece of the exemplar (from a hash of its lattice
coordinates) and blend the three pieces over each triangle with a
*histogram-preserving* operator: the exemplar is Gaussianised, the three
Gaussian values are blended with weights ``w_i / sqrt(sum w_i^2)`` (which keep
the variance), and the inverse transform gives the exemplar's histogram back.
The result is infinite, never repeats, and each pixel costs the same handful
of operations wherever it is.

The first figure makes 512 x 512 outputs (2048 x 2048 with ``--docs``) from
three stochastic exemplars (with a 256 x 256 crop at full resolution next to
each) and two structured ones, where the blend shows: bricks are ghosted where
two or three tiles overlap. The exemplars are scikit-image's gravel and brick
photographs (``skimage.data``) and the bundled bread, water and brick samples
(``texsynth.data``). ``python plot_tiling_blending.py --docs`` in a checkout
also refreshes the documentation's copy of the figure,
``docs/_static/tiling_blending.png``, at 2048 x 2048. The second figure shows
the point-evaluation form far from the origin.
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
from texsynth.statistical import tile_and_blend, tile_and_blend_at

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUTPUT = HERE / "output"
OUTPUT.mkdir(exist_ok=True)
DOCS = "--docs" in sys.argv  # the documentation's figure (never refreshed by the docs build itself)
FOLDERS = [OUTPUT] + ([HERE.parent / "docs" / "_static"] if DOCS else [])
SIZE = 2048 if DOCS else 512
CROP = 256

CASES = [  # (sample, crop of the exemplar, label)
    ("skimage.gravel", 256, "stochastic: works"),
    ("bread", None, "stochastic colour: works"),
    ("water", 128, "stochastic colour: works"),
    ("skimage.brick", 256, "structured: fails"),
    ("brick", None, "structured colour: fails"),
]


def load(name, crop):
    """A bundled sample, or a scikit-image photograph ("skimage.gravel"), cropped to crop x crop."""
    image = getattr(skdata, name[8:])() / 255.0 if name.startswith("skimage.") else data.load(name)
    return image if crop is None else image[:crop, :crop]


def show(ax, image, title):
    ax.imshow(np.clip(image, 0, 1), cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1,
              interpolation="antialiased")
    ax.set_title(title, fontsize=8)
    ax.axis("off")


fig, axes = plt.subplots(len(CASES), 3, figsize=(10.5, 3.6 * len(CASES)))
for row, (name, crop, label) in zip(axes, CASES):
    exemplar = load(name, crop)
    start = time.perf_counter()
    out, info = tile_and_blend(exemplar, SIZE, rng=0, return_info=True)
    seconds = time.perf_counter() - start
    save_image(OUTPUT / f"tiling_blending_{name.replace('.', '_')}.png", out, overwrite=True)
    show(row[0], exemplar, f"{name} {exemplar.shape[0]}x{exemplar.shape[1]}\n({label})")
    show(row[1], out, f"{SIZE}x{SIZE} in {seconds:.2f} s (triangle edge {info.edge:.0f} px)\n"
         f"the exemplar spans {SIZE / exemplar.shape[1]:.0f} times across")
    show(row[2], out[:CROP, :CROP], f"top-left {CROP}x{CROP} at full resolution")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "tiling_blending.png", dpi=80)
print("saved", OUTPUT / "tiling_blending.png")

# The same infinite texture evaluated around the point (10^9, -10^9): the point form gives any window, or any
# scattered set of pixels, at the same cost per pixel, with no table of the output.
exemplar = load("bread", None)
rows, cols = np.mgrid[10**9 : 10**9 + 256, -(10**9) : -(10**9) + 512]
far = tile_and_blend_at(exemplar, rows, cols, rng=0)
fig, axes = plt.subplots(1, 2, figsize=(10, 2.9), gridspec_kw={"width_ratios": [1, 2]})
show(axes[0], tile_and_blend(exemplar, 256, rng=0), "rows 0-255, cols 0-255")
show(axes[1], far, "rows 10^9 + 0-255, cols -10^9 + 0-511 (tile_and_blend_at)")
fig.tight_layout()
fig.savefig(OUTPUT / "tiling_blending_far.png", dpi=80)
print("saved", OUTPUT / "tiling_blending_far.png")
