"""
Patchwork on real textures (Harrison 2002, Figure 4), tileable output and a failure case
========================================================================================

The bundled samples (``texsynth.data``) and scikit-image's gravel, grass and
brick photographs (``skimage.data``) synthesised at the paper's settings
(``f = 6``; grid 64 for the large inputs, smaller grids for the small ones so
a patch fits in the input). Stochastic textures (water, ink, gravel, grass,
bread, metal) come out without visible joins. A tileable output is tiled 2x2
to show that the wrap-around has no seam.

The paper's own failure cases are shown honestly: regular tiling patterns
(two brick walls) and large objects (nuts) - random patches break the
lattice and cut objects in half, and the blended joins show as ghosted,
half-transparent bricks or nuts.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata

from texsynth import data
from texsynth.patch import patchwork

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)


def load(name):
    """A bundled sample, or one of scikit-image's grey photographs ("skimage.gravel", ...)."""
    if name.startswith("skimage."):
        return getattr(skdata, name.split(".")[1])() / 255.0
    return data.load(name)


def show(ax, image, title):
    ax.imshow(image, cmap="gray", vmin=0, vmax=1)
    ax.set_title(title, fontsize=9)
    ax.axis("off")


good = [
    ("water", "water", 64),
    ("ink", "ink", 48),
    ("skimage.gravel", "gravel", 64),
    ("skimage.grass", "grass", 64),
    ("bread", "bread", 24),
    ("metal", "metal", 48),
]
fig, axes = plt.subplots(2, len(good), figsize=(3.1 * len(good), 6.6), layout="constrained")
for k, (file, name, grid) in enumerate(good):
    exemplar = load(file)
    out = patchwork(exemplar, 384, grid_spacing=grid, sharpness=6, rng=k)
    show(axes[0, k], exemplar, f"{name} input {exemplar.shape[0]}x{exemplar.shape[1]}")
    show(axes[1, k], out, f"patchwork 384x384, grid {grid}, f = 6")
fig.suptitle("Figure 4 on real textures: inputs (top, to scale of their own panel) and outputs (bottom)")
fig.savefig(OUT / "patchwork_gallery.png", dpi=80)
print("saved", OUT / "patchwork_gallery.png")

# %%
# Tileable output: the grid and the distance wrap around; tiled 2x2, the copies meet without a seam
# (the dashed lines mark where the copies meet).
fig, axes = plt.subplots(1, 3, figsize=(15, 5.4))
for ax, (file, name) in zip(axes, [("water", "water"), ("skimage.gravel", "gravel"), ("bread", "bread")]):
    exemplar = load(file)
    grid = 64 if min(exemplar.shape[:2]) >= 192 else 24
    tile = patchwork(exemplar, (200, 240), grid_spacing=grid, tileable=True, rng=3)
    tiled = np.tile(tile, (2, 2, 1) if tile.ndim == 3 else (2, 2))
    show(ax, tiled, f"{name}: a 200x240 tileable output, tiled 2x2")
    ax.axhline(199.5, color="w", ls=":", lw=0.8)
    ax.axvline(239.5, color="w", ls=":", lw=0.8)
fig.tight_layout()
fig.savefig(OUT / "patchwork_tileable.png", dpi=80)
print("saved", OUT / "patchwork_tileable.png")

# %%
# Where it fails (Section 3.1 and 6 of the paper): tiling patterns and large objects.
bad = [
    ("skimage.brick", "bricks (tiling pattern)", 64),
    ("brick", "red bricks (tiling pattern)", 16),
    ("nuts", "nuts (large objects)", 48),
]
fig, axes = plt.subplots(2, len(bad), figsize=(4.2 * len(bad), 8.4))
for k, (file, name, grid) in enumerate(bad):
    exemplar = load(file)
    out = patchwork(exemplar, 320, grid_spacing=grid, rng=k)
    show(axes[0, k], exemplar, f"{name}: input")
    show(axes[1, k], out, "patchwork: the lattice breaks, objects are cut and ghosted")
fig.tight_layout()
fig.savefig(OUT / "patchwork_failures.png", dpi=80)
print("saved", OUT / "patchwork_failures.png")
