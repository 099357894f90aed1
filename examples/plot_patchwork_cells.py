"""
Patchwork cell shapes for f = 2, 6 and 20 (Harrison 2002, Figure 2)
===================================================================

The same jittered grid of points ``p_i`` (grid spacing 32) with three border
sharpnesses ``f`` of eq. 1. Top row: each cell has a colour, and each pixel
mixes the colours in proportion to the share ``w_i^2 / sum_j w_j^2`` of its
variance that each patch contributes in eq. 2 - the patch shapes as eq. 2 sees
them; the points ``p_i`` in black. Bottom row: the largest normalised weight - 1 deep
inside a cell, about ``1/sqrt(2)`` on a join between two cells; the darker
band is the transition zone, wide for ``f = 2`` and a thin line for ``f = 20``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.patch import patchwork, voronoi_weights

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

size, spacing = 192, 32
palette = np.random.default_rng(1).random((64, 3)) * 0.8 + 0.2

fig, axes = plt.subplots(2, 3, figsize=(12, 8.6), layout="constrained")
for col, f in enumerate([2, 6, 20]):
    largest, cells = voronoi_weights(size, grid_spacing=spacing, sharpness=f, rng=0)
    # the same p_i as voronoi_weights (same seed and geometry), to mix the cell colours
    _, info = patchwork(np.zeros((size, size)), size, grid_spacing=spacing, sharpness=f, rng=0, return_info=True)
    r, c = np.mgrid[:size, :size]
    d2 = (r[..., None] - info.p[:, 0]) ** 2 + (c[..., None] - info.p[:, 1]) ** 2
    share = d2 ** (-f / 2 * 2)  # w_i^2 (eq. 1 squared): each patch's share of the variance in eq. 2
    colours = (share @ palette[: len(info.p)]) / share.sum(-1, keepdims=True)
    axes[0, col].imshow(colours)
    axes[0, col].plot(info.p[:, 1] - 0.5, info.p[:, 0] - 0.5, "k.", ms=4)
    axes[0, col].set_title(f"({'abc'[col]}) f = {f}: patch shapes")
    im = axes[1, col].imshow(largest, cmap="magma", vmin=0.5, vmax=1)
    axes[1, col].set_title(f"largest w_i / sqrt(sum w_j^2), f = {f}", fontsize=10)
    for ax in axes[:, col]:
        ax.set_xlim(-0.5, size - 0.5)
        ax.set_ylim(size - 0.5, -0.5)
        ax.axis("off")
    print(f"f = {f}: mean largest weight {largest.mean():.3f}, "
          f"share of pixels with largest < 0.9: {np.mean(largest < 0.9):.2f}")
fig.colorbar(im, ax=axes[1], shrink=0.7)
fig.suptitle("Figure 2: patch shapes about the points p_i for f = 2, 6, 20 (same points)")
fig.savefig(OUT / "patchwork_cells.png", dpi=90)
print("saved", OUT / "patchwork_cells.png")
