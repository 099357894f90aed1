"""
Patchwork joins: sharp, feathered and standard-deviation controlled (Harrison 2002, Figure 1)
=============================================================================================

Two patches of a real texture (the bundled ``water``) are joined three ways,
with the weights of eq. 1 (``w_i = d(x, p_i)^-f``, two points ``p_1`` left and
``p_2`` right, ``f = 2`` so the transition is wide enough to see):

(a) sharp transition: each pixel from the nearer patch - the seam is visible;
(b) feathered transition ``sum w_i I_i / sum w_i`` - the middle looks dull
    (its contrast drops: averaging two uncorrelated patches halves the variance);
(c) eq. 2: ``sum w_i (I_i - a) / sqrt(sum w_i^2) + a`` - the same blend with the
    standard deviation restored: the join disappears.

The bottom plot shows the standard deviation of each column across the rows,
averaged over 60 random pairs of patches: (b) dips in the middle, (c) stays flat. A second figure shows close-ups of
real joins in a synthesis at the paper's ``f = 6`` with the cell borders.
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

texture = data.load("water")  # 300 x 300 colour photograph of water
a = texture.reshape(-1, 3).mean(0)  # the average colour a of eq. 2
h, w = 160, 240
patch1 = texture[0:h, 0:w]  # two different parts of the photograph
patch2 = texture[140 : 140 + h, 60 : 60 + w]

# eq. 1 with two points on the middle row, one on each side of the join
rows, cols = np.mgrid[:h, :w]
f = 2.0
d1 = np.hypot(rows - h / 2 + 0.5, cols - 0.25 * w + 0.5)  # points on pixel corners: d > 0
d2 = np.hypot(rows - h / 2 + 0.5, cols - 0.75 * w + 0.5)
w1, w2 = d1 ** (-f), d2 ** (-f)
w1, w2 = w1[..., None], w2[..., None]

sharp = np.where(d1[..., None] < d2[..., None], patch1, patch2)
feathered = (w1 * patch1 + w2 * patch2) / (w1 + w2)
controlled = (w1 * (patch1 - a) + w2 * (patch2 - a)) / np.sqrt(w1**2 + w2**2) + a  # eq. 2
joins = {"(a) sharp transition": sharp, "(b) feathered transition": feathered,
         "(c) std-controlled (eq. 2)": np.clip(controlled, 0, 1)}


def profile(kind, pairs=60, seed=0):
    """Per-column std across rows, averaged over many random pairs of patches."""
    gen = np.random.default_rng(seed)
    acc = np.zeros(w)
    for _ in range(pairs):
        (y1, y2), (x1, x2) = gen.integers(0, texture.shape[0] - h, 2), gen.integers(0, texture.shape[1] - w, 2)
        i1, i2 = texture[y1 : y1 + h, x1 : x1 + w], texture[y2 : y2 + h, x2 : x2 + w]
        if kind == "sharp":
            out = np.where(d1[..., None] < d2[..., None], i1, i2)
        elif kind == "feathered":
            out = (w1 * i1 + w2 * i2) / (w1 + w2)
        else:
            out = (w1 * (i1 - a) + w2 * (i2 - a)) / np.sqrt(w1**2 + w2**2) + a
        acc += out.std(axis=0).mean(-1)
    return acc / pairs


fig = plt.figure(figsize=(13, 7))
for k, (title, image) in enumerate(joins.items()):
    ax = fig.add_subplot(2, 3, k + 1)
    ax.imshow(image)
    ax.set_title(title)
    ax.axis("off")
ax = fig.add_subplot(2, 1, 2)
for kind, colour in [("sharp", "tab:gray"), ("feathered", "tab:blue"), ("controlled", "tab:green")]:
    ax.plot(profile(kind), color=colour, label=kind)
ax.axhline(texture.std(axis=(0, 1)).mean(), color="tab:red", ls="--", label="input std")
ax.set_xlabel("column (join in the middle)")
ax.set_ylabel("std over rows, mean of 60 random pairs")
ax.legend()
fig.suptitle("Figure 1 on a real texture: the same two patches joined three ways (f = 2)")
fig.tight_layout()
fig.savefig(OUT / "patchwork_joins.png", dpi=90)
print("saved", OUT / "patchwork_joins.png")

# %%
# Close-ups of joins in a real synthesis at the paper's defaults (f = 6, grid 64):
# left the output with the Voronoi cell borders drawn, right the same crop without them.
for name, exemplar in [("water", data.load("water")), ("gravel", skdata.gravel() / 255.0)]:
    out, info = patchwork(exemplar, 256, grid_spacing=64, sharpness=6, rng=4, return_info=True)
    border = np.zeros(info.cells.shape, bool)
    border[:-1] |= info.cells[:-1] != info.cells[1:]
    border[:, :-1] |= info.cells[:, :-1] != info.cells[:, 1:]
    crop = (slice(64, 192), slice(64, 192))
    marked = np.array(out if out.ndim == 3 else np.repeat(out[..., None], 3, -1))
    marked[border] = (1.0, 0.1, 0.1)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.6))
    axes[0].imshow(marked, cmap="gray")
    axes[0].set_title(f"{name}: output, cell borders in red")
    axes[1].imshow(marked[crop], cmap="gray", interpolation="nearest")
    axes[1].set_title("close-up (2x), borders")
    axes[2].imshow(out[crop], cmap="gray", interpolation="nearest", vmin=0, vmax=1)
    axes[2].set_title("the same close-up: joins at f = 6")
    for ax in axes:
        ax.axis("off")
    fig.tight_layout()
    fig.savefig(OUT / f"patchwork_joins_closeup_{name}.png", dpi=90)
    print("saved", OUT / f"patchwork_joins_closeup_{name}.png")
