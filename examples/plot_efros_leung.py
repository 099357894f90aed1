"""
Efros-Leung: the window size, growing garbage and hole filling
==============================================================

Efros & Leung (ICCV 1999) grow a texture pixel by pixel from a 3x3 seed: each
pixel copies the centre of an exemplar window that matches the known part of
its own window (Gaussian-weighted SSD, a random pick among the windows within
10 % of the best).

1. The window size is the one parameter, "the randomness parameter" of the
   lecture (paper, Figure 2): 5, 11 and 23 on text (the bundled sample,
   ``texsynth.data``). Saves ``efros_leung_window_sizes.png``.
2. Growing garbage: on reptile skin (a lattice of cells) with a 7x7 window
   the growth slips into a region it cannot leave and fills part of the
   output with shapeless blobs; the maps of the error of each pixel's match
   and of where each pixel was copied from show it. A 13x13 window, wider
   than one cell, keeps the lattice (with this seed). Saves
   ``efros_leung_garbage.png``.
3. Hole filling (the paper's constrained synthesis): the hole of the bundled
   ``bricks_hole`` (its alpha channel; a 128 px crop around the hole) grown
   from its rim with the rest of the crop as the exemplar. Saves ``efros_leung_hole.png``.
4. Exact search against the PCA acceleration of the IPOL implementation
   (bread 64x64 -> 96x96). Saves ``efros_leung_pca.png``.

Pixel-by-pixel growth is slow in pure Python and numpy, so the exemplars are
small (64 px, the hole's crop 128 px) and the outputs 96 px: the whole script
takes about 20 s.
"""

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.core.search import Search
from texsynth.io import save_image
from texsynth.metrics import texture_report
from texsynth.pixel import efros_leung
from texsynth.testing import relative_scores

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)


def load(name, side):
    image = data.load(name)
    image = image[..., :3] if image.ndim == 3 else image
    return np.ascontiguousarray(image[:side, :side])


def show(ax, image, title):
    ax.imshow(image, cmap=None if image.ndim == 3 else "gray", vmin=0, vmax=1)
    ax.set_title(title, fontsize=9)
    ax.axis("off")


# 1. the window size ------------------------------------------------------------------------------
SIZE = 96  # output side
sizes = (5, 11, 23)
cases = [("text", 64, "text")]
fig, axes = plt.subplots(len(cases), len(sizes) + 1, figsize=(3 * (len(sizes) + 1), 3.5 * len(cases)),
                         squeeze=False)
for row, (name, side, label) in zip(axes, cases):
    ex = load(name, side).astype(np.float32)  # float32: the same picks up to rounding, twice as fast
    show(row[0], ex, f"exemplar: {label}, {side}x{side}")
    for ax, w in zip(row[1:], sizes):
        start = time.perf_counter()
        out = efros_leung(ex, SIZE, neighborhood_size=w, rng=0)
        save_image(OUT / f"efros_leung_{label.split()[0]}_w{w}.png", out, overwrite=True)
        print(f"{label}, w = {w}: {time.perf_counter() - start:.1f} s")
        show(ax, out, f"w = {w}")
fig.tight_layout()
fig.savefig(OUT / "efros_leung_window_sizes.png", dpi=80)

# 2. growing garbage ------------------------------------------------------------------------------
ex = load("reptile", 64)
fig, axes = plt.subplots(2, 4, figsize=(16, 8.4))
for row, w in zip(axes, (7, 13)):
    out, info = efros_leung(ex, SIZE, neighborhood_size=w, rng=0, return_info=True)
    src = info.source / np.array(ex.shape[:2])
    show(row[0], ex, "exemplar: reptile skin, 64x64")
    show(row[1], out, f"w = {w}")
    im = row[2].imshow(info.error, vmin=0, vmax=0.02)
    row[2].set_title("error d of each pixel's match", fontsize=9)
    row[2].axis("off")
    fig.colorbar(im, ax=row[2], fraction=0.046)
    show(row[3], np.dstack([src[..., 0], src[..., 1], np.full(src.shape[:2], 0.5)]),
         "source map: copied (row, col) as (red, green)")
fig.tight_layout()
fig.savefig(OUT / "efros_leung_garbage.png", dpi=70)

# 3. hole filling ---------------------------------------------------------------------------------
rgba = data.load("bricks_hole")[24:152, 24:152]  # (128, 128, 4): the alpha channel is 0 in the hole
known = rgba[..., 3] > 0.999
image = rgba[..., :3]
start = time.perf_counter()
filled, info = efros_leung(image, image.shape[:2], neighborhood_size=11, target=image, mask=known,
                           exemplar_mask=known, rng=0, return_info=True)
print(f"hole of {int((~known).sum())} px, w = 11: {time.perf_counter() - start:.1f} s, {info.passes} passes")
save_image(OUT / "efros_leung_hole_result.png", filled, overwrite=True)
shown = image.copy()
shown[~known] = [1.0, 0.0, 1.0]
rows, cols = np.nonzero(~known)
box = np.s_[rows.min() - 4:rows.max() + 5, cols.min() - 4:cols.max() + 5]
fig, axes = plt.subplots(1, 3, figsize=(13.5, 5))
show(axes[0], shown, "input (hole in magenta)")
show(axes[1], filled, "filled, w = 11")
show(axes[2], filled[box], "the hole and 4 px around it")
fig.tight_layout()
fig.savefig(OUT / "efros_leung_hole.png", dpi=90)

# 4. exact against PCA ----------------------------------------------------------------------------
ex = load("bread", 64)
fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
show(axes[0], ex, "exemplar 64x64")
for ax, method in zip(axes[1:], ("exact", "pca")):
    out, info = efros_leung(ex, SIZE, search=Search(method=method), rng=0, return_info=True)
    scores = relative_scores(texture_report(out, ex))
    title = f"{method}: {info.seconds:.1f} s, energy score {scores['energy']:.2f}"
    print(title, "PCA dimensions" if method == "pca" else "", info.n_components)
    show(ax, out, title)
fig.tight_layout()
fig.savefig(OUT / "efros_leung_pca.png", dpi=80)
