"""
Patch-based interpolation vs linear blending on a second pair: pebbles and paving
=================================================================================

Ruiters et al. 2010, Figure 1: interpolating two textures by cross-fading the
images ghosts both sets of features on top of each other; interpolating their
neighbourhoods (warped into alignment by thin-plate splines) and synthesising
from them keeps one set of sharp features. The brick <-> slate pair is in
``plot_interpolation_sequence.py``; this is the README's pebbles <-> paving
pair (rohitrango t4 <-> t13): loose rounded pebbles against large polygonal
paving stones separated by thin dark cracks. Both are scaled to 96 px (the
paving by 1/2, so that a crop holds several stones; the method does not
compensate scale differences, paper Section 5). Top row: ours for alpha = 0,
0.25, 0.5, 0.75, 1 with the default feature maps (ridge/valley centre lines,
:func:`texsynth.optimization.ridge_feature_map`); middle row: the linear
blend; bottom row: the inputs and their feature maps. A second figure shows
alpha = 0.5 of both at 3x.

Run:  python examples/plot_interpolation_pairs.py
"""

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage.transform import resize

from texsynth.optimization import (InterpolationSchedule, NeighborhoodSet, interpolate_textures, linear_blend,
                                   ridge_feature_map)
from texsynth.io import load_image
from texsynth.metrics import texture_energy

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

a = resize(load_image(TEXTURES / "rohitrango" / "t4.png")[..., :3], (96, 96), anti_aliasing=True)  # pebbles
b = resize(load_image(TEXTURES / "rohitrango" / "t13.png")[..., :3], (96, 96), anti_aliasing=True)  # paving
features = (ridge_feature_map(a), ridge_feature_map(b))

alphas = [0.0, 0.25, 0.5, 0.75, 1.0]
opts = dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 17), (1, 9)), max_iterations=4),
            neighborhood_set=NeighborhoodSet(max_neighborhoods=400), rng=0)
ours = []
for al in alphas:
    t0 = time.perf_counter()
    ours.append(interpolate_textures(a, b, al, features=features, **opts))
    print(f"alpha {al}: {time.perf_counter() - t0:.1f} s, texture energy vs pebbles "
          f"{texture_energy(ours[-1], a):.5f}, vs paving {texture_energy(ours[-1], b):.5f}")
blends = [linear_blend(a, b, al) for al in alphas]
for al, img in zip(alphas, blends):
    print(f"linear blend alpha {al}: texture energy vs pebbles {texture_energy(img, a):.5f}, "
          f"vs paving {texture_energy(img, b):.5f}")

fig, axes = plt.subplots(3, 5, figsize=(12, 7.5))
for j, al in enumerate(alphas):
    axes[0, j].imshow(np.clip(ours[j], 0, 1))
    axes[0, j].set_title(f"ours, alpha = {al}", fontsize=9)
    axes[1, j].imshow(np.clip(blends[j], 0, 1))
    axes[1, j].set_title(f"linear blend, alpha = {al}", fontsize=9)
for j, (img, title) in enumerate([(a, "I1 pebbles"), (features[0], "F1 (ridges)"), (b, "I2 paving"),
                                  (features[1], "F2 (ridges)")]):
    axes[2, j].imshow(img, cmap="gray")
    axes[2, j].set_title(title, fontsize=9)
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_pairs.png", dpi=80)

fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
for ax, img, title in zip(axes, (ours[2], blends[2]), ("ours, alpha = 0.5", "linear blend, alpha = 0.5")):
    ax.imshow(np.clip(img, 0, 1), interpolation="nearest")
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_pairs_closeup.png", dpi=80)
print("saved", OUT / "interpolation_pairs.png", OUT / "interpolation_pairs_closeup.png")
