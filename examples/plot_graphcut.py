"""
Graph-cut textures: seam refinement and interactive merging (Kwatra et al. 2003)
================================================================================

Two figures in the spirit of the paper's:

1. **Seam refinement.** Text (the bundled ``text``, a 128 px crop) synthesised to
   256 px: left, the output once it is covered (``refine=0``); right, the same
   run after four refinement passes (the same seed: the covering is identical,
   the passes then place patches over the costliest seams). The seams are drawn
   in red, brighter where they cost more, and the curve below is the total seam
   cost after every patch (``info.energy``): it rises while the output is
   covered and never rises during refinement.
2. **Interactive merging.** Grass and gravel (``skimage.data.grass()`` and
   ``skimage.data.gravel()``, photographs that ship with scikit-image) with
   a user's strokes: blue pixels must come from the grass, orange ones from the
   gravel. ``graphcut_merge`` finds the cheapest seam between the strokes,
   with the gradient-normalised cost ``M'`` (the seam hides along the blades
   and stones) and with the plain cost ``M``.

3. **Blocks or the whole input.** Gravel and text (128 px) to 256 px with the
   defaults (half-exemplar blocks) and with ``preset="paper"`` (the whole
   exemplar placed at output translations, as the paper does).

All are saved to ``examples/output/``; ``python plot_graphcut.py --docs`` in a
checkout also refreshes the documentation's copies in ``docs/_static/``.
"""

import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata

from texsynth import data
from texsynth.patch import graphcut_merge, graphcut_texture

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figures of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])


def seam_overlay(image, labels, strength):
    """The image in grey-scale colour with the seams between patches in red (brighter: dearer)."""
    rgb = np.repeat(image[..., None], 3, -1) if image.ndim == 2 else image.copy()
    rgb = 0.35 + 0.65 * rgb
    seam = np.zeros(labels.shape, bool)
    seam[:, :-1] |= labels[:, :-1] != labels[:, 1:]
    seam[:-1] |= labels[:-1] != labels[1:]
    rgb[seam] = np.stack([np.ones(seam.sum()), 0.6 * (1 - strength[seam]), 0.6 * (1 - strength[seam])], -1)
    return rgb


def seam_strength(image, labels):
    """Per pixel: the jump to the right and down neighbours where they come from another patch, scaled to 1."""
    o = image if image.ndim == 3 else image[..., None]
    jump = np.zeros(labels.shape)
    right = ((o[:, 1:] - o[:, :-1]) ** 2).sum(-1) * (labels[:, 1:] != labels[:, :-1])
    down = ((o[1:] - o[:-1]) ** 2).sum(-1) * (labels[1:] != labels[:-1])
    jump[:, :-1] = np.maximum(jump[:, :-1], right)
    jump[:-1] = np.maximum(jump[:-1], down)
    return np.clip(np.sqrt(jump) / 0.5, 0, 1)


# %%
# Figure 1: the covered output and the refined one
exemplar = data.load("text")[:128, :128]
before, info0 = graphcut_texture(exemplar, 256, block=64, refine=0, rng=3, return_info=True)
after, info = graphcut_texture(exemplar, 256, block=64, refine=4, rng=3, return_info=True)
print(f"seam cost after covering {info0.seam_cost:.1f}, after 4 refinement passes {info.seam_cost:.1f}")

fig = plt.figure(figsize=(12, 8.2))
grid = fig.add_gridspec(2, 3, height_ratios=[3, 1])
ax = fig.add_subplot(grid[0, 0])
ax.imshow(exemplar, cmap="gray", vmin=0, vmax=1)
ax.set_title("exemplar (128 px)")
for k, (title, image, inf) in enumerate([(f"covered (refine=0): seam cost {info0.seam_cost:.0f}", before, info0),
                                         (f"4 refinement passes: seam cost {info.seam_cost:.0f}", after, info)]):
    ax = fig.add_subplot(grid[0, k + 1])
    ax.imshow(seam_overlay(image, inf.labels, seam_strength(image, inf.labels)))
    ax.set_title(title)
for ax in fig.axes:
    ax.axis("off")
ax = fig.add_subplot(grid[1, :])
steps = np.arange(1, len(info.energy) + 1)
for stage in np.unique(info.stage):
    part = info.stage == stage
    ax.plot(steps[part], info.energy[part], ".-", ms=3, label="covering" if stage == 0 else f"refinement pass {stage}")
ax.set_xlabel("patch")
ax.set_ylabel("total seam cost (M)")
ax.legend(ncol=5, fontsize=8)
fig.suptitle("Graph-cut textures: seams (red) before and after refinement, and the seam cost patch by patch")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "graphcut_refinement.png", dpi=80)
print("saved", OUT / "graphcut_refinement.png")

# %%
# Figure 2: interactive merging of two photographs with the user's strokes
grass = skdata.grass()[:192, :192] / 255.0
gravel = skdata.gravel()[:192, :192] / 255.0
rows, cols = np.mgrid[:192, :192]
from_a = (np.abs(cols - (50 + 20 * np.sin(rows / 25))) < 4) & (rows > 15) & (rows < 177)  # a wavy stroke on the left
from_b = (np.abs(cols - 150) < 4) & (rows > 30) & (rows < 160)  # a straight one on the right
from_b |= (np.abs(rows - 96) < 3) & (cols > 110) & (cols < 150)  # ... with a branch to the middle

merged, minfo = graphcut_merge(grass, gravel, from_a=from_a, from_b=from_b, return_info=True)
plain, pinfo = graphcut_merge(grass, gravel, from_a=from_a, from_b=from_b, edge_cost="plain", return_info=True)
strokes = 0.5 + 0.5 * np.where(rows % 2 == 0, grass, gravel)  # the two inputs interleaved, faded
strokes = np.repeat(strokes[..., None], 3, -1)
strokes[from_a] = (0.1, 0.3, 1.0)
strokes[from_b] = (1.0, 0.5, 0.0)

fig, axes = plt.subplots(1, 5, figsize=(16, 3.8))
panels = [(grass, "a: grass"), (gravel, "b: gravel"), (strokes, "strokes: blue from a, orange from b"),
          (seam_overlay(merged, minfo.labels.astype(int), np.ones(merged.shape)), "merged, M' (seam in red)"),
          (seam_overlay(plain, pinfo.labels.astype(int), np.ones(plain.shape)), "merged, plain M")]
for ax, (image, title) in zip(axes, panels):
    ax.imshow(image, cmap="gray", vmin=0, vmax=1)
    ax.set_title(title, fontsize=10)
    ax.axis("off")
fig.suptitle("Interactive merging: the cheapest seam between the user's strokes")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "graphcut_merge.png", dpi=80)
plt.imsave(OUT / "graphcut_merged.png", merged, cmap="gray", vmin=0, vmax=1)
print("saved", OUT / "graphcut_merge.png")

# %%
# Figure 3: the default blocks against the paper's whole-input patches
fig, axes = plt.subplots(2, 3, figsize=(12, 8.4))
for row, (name, image) in zip(axes, [("gravel", skdata.gravel() / 255.0), ("text", data.load("text"))]):
    exemplar = image[:128, :128]
    row[0].imshow(exemplar, cmap="gray", vmin=0, vmax=1)
    row[0].set_title(f"{name}, 128 px")
    for ax, preset in zip(row[1:], ("default", "paper")):
        out, inf = graphcut_texture(exemplar, 256, preset=preset, rng=1, return_info=True)
        ax.imshow(out, cmap="gray", vmin=0, vmax=1)
        ax.set_title(f'preset="{preset}": {len(inf.corners)} patches, seam cost {inf.seam_cost:.0f}', fontsize=10)
for ax in axes.ravel():
    ax.axis("off")
fig.suptitle("Half-exemplar blocks (default) and the whole exemplar as the patch (the paper's)")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "graphcut_presets.png", dpi=80)
print("saved", OUT / "graphcut_presets.png")
