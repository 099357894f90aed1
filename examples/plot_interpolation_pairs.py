"""
Patch-based interpolation vs linear blending on a second pair: nuts and reptile skin
====================================================================================

Ruiters et al. 2010, Figure 1: interpolating two textures by cross-fading the
images ghosts both sets of features on top of each other; interpolating their
neighbourhoods (warped into alignment by thin-plate splines) and synthesising
from them keeps one set of sharp features. The brick <-> wood pair is in
``plot_interpolation_sequence.py``; this pair is grey: the bundled ``nuts``
(large rounded objects with dark gaps) and ``reptile`` (a lattice of small
dark cells with light rims): 128 px crops of the 256 px photographs, scaled
to 64 px so that each holds several elements (the method does not compensate
scale differences, paper Section 5). Top row: the nuts (alpha = 0), ours for
alpha = 0.25, 0.5, 0.75 with the default feature maps (ridge/valley centre
lines, :func:`texsynth.optimization.ridge_feature_map`) and the nuts' map;
bottom row: the reptile skin (alpha = 1), the linear blend at the same alphas
and the reptile skin's map. A second figure shows
alpha = 0.5 of both at 3x: the blend shows the nuts and the lattice at once,
each at half contrast; ours puts pieces of nuts and pieces of lattice side by
side, busier than either input. The schedule is shortened to keep the example
quick (two stages, 3 iterations, 200 neighbourhoods).

Run:  python examples/plot_interpolation_pairs.py
"""

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage.transform import resize

from texsynth import data
from texsynth.optimization import (InterpolationSchedule, NeighborhoodSet, interpolate_textures, linear_blend,
                                   ridge_feature_map)
from texsynth.metrics import texture_energy

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

a = resize(data.load("nuts")[:128, :128], (64, 64), anti_aliasing=True)
b = resize(data.load("reptile")[:128, :128], (64, 64), anti_aliasing=True)
features = (ridge_feature_map(a), ridge_feature_map(b))

alphas = [0.25, 0.5, 0.75]  # the ends are the inputs, shown in the first column
opts = dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 9)), max_iterations=3),
            neighborhood_set=NeighborhoodSet(max_neighborhoods=200), rng=0)
ours = []
for al in alphas:
    t0 = time.perf_counter()
    ours.append(interpolate_textures(a, b, al, features=features, **opts))
    print(f"alpha {al}: {time.perf_counter() - t0:.1f} s, texture energy vs nuts "
          f"{texture_energy(ours[-1], a):.5f}, vs reptile {texture_energy(ours[-1], b):.5f}")
blends = [linear_blend(a, b, al) for al in alphas]
for al, img in zip(alphas, blends):
    print(f"linear blend alpha {al}: texture energy vs nuts {texture_energy(img, a):.5f}, "
          f"vs reptile {texture_energy(img, b):.5f}")

fig, axes = plt.subplots(2, 5, figsize=(12, 5.2))
for i, (img, feature, title) in enumerate([(a, features[0], "I1 nuts (alpha = 0)"),
                                           (b, features[1], "I2 reptile skin (alpha = 1)")]):
    axes[i, 0].imshow(img, cmap="gray", vmin=0, vmax=1)
    axes[i, 0].set_title(title, fontsize=9)
    axes[i, 4].imshow(feature, cmap="gray")
    axes[i, 4].set_title(f"F{i + 1} (ridges)", fontsize=9)
for j, al in enumerate(alphas, start=1):
    axes[0, j].imshow(np.clip(ours[j - 1], 0, 1), cmap="gray", vmin=0, vmax=1)
    axes[0, j].set_title(f"ours, alpha = {al}", fontsize=9)
    axes[1, j].imshow(np.clip(blends[j - 1], 0, 1), cmap="gray", vmin=0, vmax=1)
    axes[1, j].set_title(f"linear blend, alpha = {al}", fontsize=9)
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_pairs.png", dpi=80)

fig, axes = plt.subplots(1, 2, figsize=(9, 4.6))
for ax, img, title in zip(axes, (ours[1], blends[1]), ("ours, alpha = 0.5", "linear blend, alpha = 0.5")):
    ax.imshow(np.clip(img, 0, 1), cmap="gray", vmin=0, vmax=1, interpolation="nearest")
    ax.set_title(title)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_pairs_closeup.png", dpi=80)
print("saved", OUT / "interpolation_pairs.png", OUT / "interpolation_pairs_closeup.png")
