"""
Texture interpolation sequence: patch-based vs linear blending
==============================================================

Ruiters et al. 2010 (Figure 1 and 4): an interpolation sequence between a
brick wall and a slate wall for alpha = 0, 0.25, 0.5, 0.75, 1, computed by
warping and blending neighbourhoods before texture optimization (top row),
next to the plain linear cross-fade of the two images (bottom row), which
ghosts the mortar lines of both walls on top of each other.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.interpolation import edge_feature_map, interpolate_textures, linear_blend
from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

a = load_image(TEXTURES / "rohitrango" / "t1.png")[:80, :80, :3]  # brick
b = load_image(TEXTURES / "rohitrango" / "t7.png")[:80, :80, :3]  # slate wall
features = (edge_feature_map(a, sigma=2.0), edge_feature_map(b, sigma=2.0))

alphas = [0.0, 0.25, 0.5, 0.75, 1.0]
ours = [interpolate_textures(a, b, al, features=features, stages=((2, 17), (1, 9)), iterations=3, max_neighborhoods=400,
                             rng=0) for al in alphas]
blend = [linear_blend(a, b, al) for al in alphas]

fig, axes = plt.subplots(3, 5, figsize=(12, 7.5))
for j, al in enumerate(alphas):
    axes[0, j].imshow(np.clip(ours[j], 0, 1))
    axes[0, j].set_title(f"ours, alpha={al}")
    axes[1, j].imshow(blend[j])
    axes[1, j].set_title(f"linear blend, alpha={al}")
axes[2, 0].imshow(a)
axes[2, 0].set_title("I1 (brick)")
axes[2, 1].imshow(features[0], cmap="gray")
axes[2, 1].set_title("F1 (Canny)")
axes[2, 3].imshow(b)
axes[2, 3].set_title("I2 (slate)")
axes[2, 4].imshow(features[1], cmap="gray")
axes[2, 4].set_title("F2 (Canny)")
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_sequence.png", dpi=80)
print("saved", OUT / "interpolation_sequence.png")
