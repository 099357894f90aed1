"""
Patchwork texture transfer (Harrison 2002, Section 5, Figures 8-9)
==================================================================

A real texture rendered in the shape of a pattern image: the photograph
``skimage.data.camera()`` (the cameraman) and the word "texsynth" drawn with
matplotlib into an array. Each Voronoi cell (grid 16, ``f = 2``, the paper's
Figure 8 settings) copies the texture patch that best matches the pattern
around ``p_i`` (sum of squared differences over 64 random candidates), and the
cells are joined with eq. 7, which blends the local averages ``a_i``. The
pattern is first rescaled to the texture's mean colour and range (the paper's
pre-processing). Textures: the bundled pink ink (``ink``) and water
(``water``).

A second figure is a 3x close-up of two flat areas of the ink cameraman, with
ticks on the frame where each pixel's block of summed cells changes (every
16 pixels): at ``f = 2`` the plain truncation of eq. 7 to that block left
faint straight seams there; the weights now taper smoothly to zero at the
edge of each cell's reach, and the detail image (the crop minus its blur,
amplified) shows no straight lines along the ticks.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from scipy.ndimage import gaussian_filter
from skimage import data as skdata
from skimage.transform import resize

from texsynth import data
from texsynth.patch import patchwork_transfer

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)


def text_image(text, shape=(160, 576)):
    """Black text on white, rendered by matplotlib into a float array in [0, 1]."""
    fig = plt.figure(figsize=(shape[1] / 100, shape[0] / 100), dpi=100)
    fig.text(0.5, 0.5, text, ha="center", va="center", fontsize=84, weight="bold", family="DejaVu Sans")
    fig.canvas.draw()
    rgba = np.asarray(fig.canvas.buffer_rgba())[..., :3].mean(-1) / 255.0
    plt.close(fig)
    return rgba


photo = resize(skdata.camera(), (384, 384), anti_aliasing=True)
words = text_image("texsynth")
patterns = {"photograph": photo, "text": words}
textures = {"ink": data.load("ink"), "water": data.load("water")}

results = {}
fig, axes = plt.subplots(len(textures), 3, figsize=(16, 4.4 * len(textures)),
                         gridspec_kw={"width_ratios": [1, 1, 1.6]}, layout="constrained")
for row, (tname, texture) in enumerate(textures.items()):
    axes[row, 0].imshow(texture)
    axes[row, 0].set_title(f"texture: {tname}")
    for col, (pname, pattern) in enumerate(patterns.items(), start=1):
        rgb = np.repeat(pattern[..., None], 3, axis=-1)  # same channels as the texture
        out, info = patchwork_transfer(texture, rgb, grid_spacing=16, sharpness=2, n_candidates=64, rng=0,
                                       return_info=True)
        results[tname, pname] = out, info
        axes[row, col].imshow(out)
        axes[row, col].set_title(f"{tname} onto the {pname} ({info.p.shape[0]} cells, grid 16, f = 2)")
        print(f"{tname} -> {pname}: {out.shape}, clipped {info.clipped:.3f}")
for ax in axes.ravel():
    ax.axis("off")
fig.savefig(OUT / "patchwork_transfer.png", dpi=80)
print("saved", OUT / "patchwork_transfer.png")

fig, axes = plt.subplots(1, 2, figsize=(12, 4.4), gridspec_kw={"width_ratios": [1, 1.6]}, layout="constrained")
axes[0].imshow(photo, cmap="gray")
axes[0].set_title("pattern: skimage.data.camera()")
axes[1].imshow(words, cmap="gray")
axes[1].set_title("pattern: text rendered with matplotlib")
for ax in axes:
    ax.axis("off")
fig.savefig(OUT / "patchwork_transfer_patterns.png", dpi=80)


def seam_ratio(image, spacing, m):
    """Mean |neighbour difference| across the rows/columns where the block of summed cells changes,
    divided by that of all other rows/columns (no seams: about 0.85-1.0; the plain truncation: 1.2-1.3)."""
    across, other = [], []
    for axis in (0, 1):
        d = np.abs(np.diff(image, axis=axis)).mean(axis=(1, 2) if axis == 0 else (0, 2))
        k0 = np.floor(np.arange(image.shape[axis]) / spacing - m / 2 + 0.5)
        across.append(d[k0[1:] != k0[:-1]])
        other.append(d[k0[1:] == k0[:-1]])
    return np.concatenate(across).mean() / np.concatenate(other).mean()


out, info = results["ink", "photograph"]
s, m = info.spacing[0], info.neighbors
ratio = seam_ratio(out, s, m)
print(f"ink -> photograph: seam ratio at the block boundaries {ratio:.2f}")
zoom = 3
fig, axes = plt.subplots(2, 2, figsize=(9, 9.4), layout="constrained")
for row, (y, x, what) in enumerate([(270, 0, "a flat red area"), (150, 288, "a flat light area")]):
    crop = out[y : y + 96, x : x + 96]
    grey = crop.mean(-1)
    detail = np.clip(0.5 + 5 * (grey - gaussian_filter(grey, 3)), 0, 1)  # a step in the blend shows as a line
    for col, (image, title) in enumerate([(crop, f"{what}, 3x"), (detail, "detail (crop minus blur, x5)")]):
        ax = axes[row, col]
        ax.imshow(image.repeat(zoom, axis=0).repeat(zoom, axis=1), cmap="gray", vmin=0, vmax=1,
                  interpolation="nearest")
        ax.set_title(title)
        ax.set_xticks([]), ax.set_yticks([])
        for axis, start in ((0, y), (1, x)):  # ticks where the summed block of cells changes
            r = np.arange(start, start + 96)
            k0 = np.floor(r / s - m / 2 + 0.5)
            at = (np.flatnonzero(k0[1:] != k0[:-1]) + 1) * zoom - 0.5
            (ax.set_yticks if axis == 0 else ax.set_xticks)(at)
        ax.tick_params(length=8, labelleft=False, labelbottom=False)
fig.suptitle(f"ink onto the cameraman (grid 16, f = 2): ticks mark block boundaries; seam ratio {ratio:.2f}")
fig.savefig(OUT / "patchwork_transfer_closeup.png", dpi=80)
print("saved", OUT / "patchwork_transfer_closeup.png")
