"""
Texture interpolation sequence: patch-based vs linear blending
==============================================================

Ruiters et al. 2010 (Figure 1 and 4): an interpolation sequence between a
brick wall and a slate wall for alpha = 0, 0.25, 0.5, 0.75, 1, computed by
warping and blending neighbourhoods before texture optimization (top row),
next to the plain linear cross-fade of the two images (bottom row), which
ghosts the mortar lines of both walls on top of each other. Two automatic
feature maps are compared: Canny edges (:func:`texsynth.optimization.edge_feature_map`,
the weaker kind of detector the paper found "not very satisfactory") and
ridge/valley centre lines (:func:`texsynth.optimization.ridge_feature_map`,
the default of ``interpolate_textures``). The pebbles <-> paving pair is in
``plot_interpolation_pairs.py``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.optimization import (InterpolationSchedule, NeighborhoodSet, edge_feature_map, interpolate_textures,
                                   linear_blend, ridge_feature_map)
from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

a = load_image(TEXTURES / "rohitrango" / "t1.png")[:80, :80, :3]  # brick
b = load_image(TEXTURES / "rohitrango" / "t7.png")[:80, :80, :3]  # slate wall
canny = (edge_feature_map(a, sigma=2.0), edge_feature_map(b, sigma=2.0))
ridge = (ridge_feature_map(a), ridge_feature_map(b))

alphas = [0.0, 0.25, 0.5, 0.75, 1.0]
opts = dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 17), (1, 9)), max_iterations=4),
            neighborhood_set=NeighborhoodSet(max_neighborhoods=400), rng=0)
rows = {
    "ours (Canny)": [interpolate_textures(a, b, al, features=canny, **opts) for al in alphas],
    "ours (ridges)": [interpolate_textures(a, b, al, features=ridge, **opts) for al in alphas],
    "linear blend": [linear_blend(a, b, al) for al in alphas],
}

fig, axes = plt.subplots(4, 5, figsize=(12, 10))
for i, (name, images) in enumerate(rows.items()):
    for j, al in enumerate(alphas):
        axes[i, j].imshow(np.clip(images[j], 0, 1))
        axes[i, j].set_title(f"{name}, {al}", fontsize=9)
for j, (img, title) in enumerate([(a, "I1 (brick)"), (canny[0], "F1 Canny"), (ridge[0], "F1 ridges"),
                                  (canny[1], "F2 Canny"), (ridge[1], "F2 ridges")]):
    axes[3, j].imshow(img, cmap="gray")
    axes[3, j].set_title(title, fontsize=9)
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_sequence.png", dpi=80)
print("saved", OUT / "interpolation_sequence.png")
