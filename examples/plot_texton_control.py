"""
Texton masks, orientation and magnification fields, progressive variation
=========================================================================

Zhang et al. (SIGGRAPH 2003) keep texture elements whole by synthesising a
*texton mask* along with the colour, and turn and scale the texture with
fields over the output (the lecture's "vector field control" and "local size
control"). ``texsynth.synthesize_controlled`` is the 2-D form:

* top: the bundled brick wall turned along a vortex (77x107 -> 160x160), and
  nuts (the bundled sample at half size) growing from 0.6x at the left to
  2.2x at the right;
* middle: nuts turned by 0.6 rad with the texton mask (the gaps between the
  nuts, found by ``find_textons``) and without it, and the mask synthesised
  with the first;
* bottom: a progressive variation from the brick wall to bread crumb along a
  left-to-right ramp (whole bricks and whole pieces of crumb, in a share that
  follows the ramp), against Wei's mixture (``mix_textures``), which
  averages the two.

The results are saved to ``examples/output/`` with the figure
``texton_control.png``; ``python plot_texton_control.py --docs`` in a checkout
also refreshes the documentation's copy, ``docs/_static/texton.png``.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage.transform import rescale

from texsynth import data, find_textons, mix_textures, synthesize_controlled
from texsynth.io import save_image

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
DOCS = "--docs" in sys.argv  # also refresh the documentation's figure (never done by the docs build itself)
SIZE = 256 if DOCS else 160  # the documentation's figure at 256 px, the gallery's at 160 px (about 3x faster)


def vortex(rows, cols):
    """The texture turned along circles about the centre (radians, counter-clockwise)."""
    return np.arctan2(rows - SIZE / 2, cols - SIZE / 2) + np.pi / 2


def growing(rows, cols):
    """Elements 0.6x as large at the left edge, 2.2x at the right."""
    return 0.6 + 1.6 * cols / SIZE


bricks = data.load("brick")  # 77 x 107, colour
nuts = rescale(data.load("nuts"), 0.5, anti_aliasing=True)  # 128 x 128, grey
bread = data.load("bread")  # 99 x 108, colour
results = {}
start = time.perf_counter()
results["vortex"] = synthesize_controlled(bricks, SIZE, orientation=vortex, rng=0)
results["scale_gradient"] = synthesize_controlled(nuts, SIZE, magnification=growing, rng=0)
small = nuts[:96, :96]
results["mask_on"], info = synthesize_controlled(small, SIZE, orientation=0.6, rng=0, return_info=True)
results["mask_off"] = synthesize_controlled(small, SIZE, orientation=0.6, texton_mask=None, rng=0)
ramp = np.broadcast_to(np.linspace(0.0, 1.0, 2 * SIZE), (SIZE // 2, 2 * SIZE))
results["progressive"] = synthesize_controlled(bricks, (SIZE // 2, 2 * SIZE), exemplar_b=bread, blend=ramp, rng=0)
print(f"synthesize_controlled, 6 runs: {time.perf_counter() - start:.1f} s")
start = time.perf_counter()
results["mix_textures"] = mix_textures([bricks[:64, :64], bread[:64, :64]], (SIZE // 2, 2 * SIZE),
                                       weights=[1.0 - ramp, ramp], rng=0)
print(f"mix_textures (64x64 sources): {time.perf_counter() - start:.1f} s")
for name, image in results.items():
    save_image(OUT / f"texton_{name}.png", image, overwrite=True)
save_image(OUT / "texton_mask_on_mask.png", info.texton_mask, overwrite=True)

fig = plt.figure(figsize=(12, 10.5))
grid = fig.add_gridspec(4, 4, height_ratios=[1, 1, 0.55, 0.55])
panels = [
    (grid[0, 0], bricks, "exemplar (bricks)"), (grid[0, 1], results["vortex"], "vortex orientation field"),
    (grid[0, 2], nuts, "exemplar (nuts)"), (grid[0, 3], results["scale_gradient"], "magnification 0.6 -> 2.2"),
    (grid[1, 0], find_textons(small), "texton mask (find_textons)"),
    (grid[1, 1], results["mask_on"], "turned 0.6 rad, texton mask"),
    (grid[1, 2], results["mask_off"], "turned 0.6 rad, colour alone"),
    (grid[1, 3], info.texton_mask, "the synthesised texton mask"),
    (grid[2, :], results["progressive"], "progressive variation, blend 0 -> 1 (synthesize_controlled)"),
    (grid[3, :], results["mix_textures"], "Wei's mixture, weights 0 -> 1 (mix_textures)"),
]
for cell, image, title in panels:
    ax = fig.add_subplot(cell)
    ax.imshow(image, cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1, interpolation="nearest")
    ax.set_title(title, fontsize=9)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "texton_control.png", dpi=80)
if DOCS:
    fig.savefig(HERE.parent / "docs" / "_static" / "texton.png", dpi=80)
