"""
Texture interpolation sequence: patch-based vs linear blending
==============================================================

Ruiters et al. 2010 (Figure 1 and 4): an interpolation sequence between a
brick wall and wood grain (the bundled ``brick`` and ``wood``, 64 px crops)
for alpha = 0, 0.25, 0.5, 0.75, 1, computed by warping and blending
neighbourhoods before texture optimization (top row), next to the plain
linear cross-fade of the two images (middle row), which shows the mortar lines
on top of the grain. The bottom row compares two automatic feature maps: Canny
edges (:func:`texsynth.optimization.edge_feature_map`, the weaker kind of
detector the paper found "not very satisfactory") and ridge/valley centre
lines (:func:`texsynth.optimization.ridge_feature_map`, the default of
``interpolate_textures``, which the sequence uses). Canny finds no edge in the
wood's soft grain (its map F2 is empty: nothing to align the mortar with);
the ridge map marks the grain lines. The nuts <-> reptile skin pair is in
``plot_interpolation_pairs.py``.

The schedule is shortened to keep the example quick (two stages, 3
iterations, 200 neighbourhoods: about 3 s per image; three stages, 4
iterations and 400 neighbourhoods take about three times as long).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.optimization import (InterpolationSchedule, NeighborhoodSet, edge_feature_map, interpolate_textures,
                                   linear_blend, ridge_feature_map)

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

a = data.load("brick")[:64, :64]  # red bricks, light mortar
b = data.load("wood")[:64, :64]  # wood grain
canny = (edge_feature_map(a, sigma=2.0), edge_feature_map(b, sigma=2.0))
ridge = (ridge_feature_map(a), ridge_feature_map(b))

alphas = [0.0, 0.25, 0.5, 0.75, 1.0]
opts = dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 9)), max_iterations=3),
            neighborhood_set=NeighborhoodSet(max_neighborhoods=200), rng=0)
rows = {
    "ours (ridges)": [interpolate_textures(a, b, al, features=ridge, **opts) for al in alphas],
    "linear blend": [linear_blend(a, b, al) for al in alphas],
}

fig, axes = plt.subplots(3, 5, figsize=(12, 7.5))
for i, (name, images) in enumerate(rows.items()):
    for j, al in enumerate(alphas):
        axes[i, j].imshow(np.clip(images[j], 0, 1))
        axes[i, j].set_title(f"{name}, {al}", fontsize=9)
for j, (img, title) in enumerate([(a, "I1 (brick)"), (canny[0], "F1 Canny"), (ridge[0], "F1 ridges"),
                                  (canny[1], "F2 Canny"), (ridge[1], "F2 ridges")]):
    axes[2, j].imshow(img, cmap="gray")
    axes[2, j].set_title(title, fontsize=9)
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_sequence.png", dpi=80)
print("saved", OUT / "interpolation_sequence.png")
