"""
Texture mixtures from two sources (Wei 2002, Figure 1)
======================================================

Each output pixel minimises eq. 1, ``sum_i w_i (||p - p_i||^2 + ||N_i(p) -
N_i(p_i)||^2)``, by Wei's alternation. Each row: the two inputs, the result
with equal weighting (a uniform mixture) and with ramp weighting (the left
source turning into the right one, left to right).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.io import load_image
from texsynth.metrics import texture_energy
from texsynth.multisource import mix_textures

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)


def load(name, step):
    img = load_image(TEXTURES / name)
    img = img[..., :3] if img.ndim == 3 else img
    return img[: 64 * step : step, : 64 * step : step]


pairs = [
    ("skimage/brick.png", "skimage/gravel.png", 4),
    ("rohitrango/t2.png", "rohitrango/t14.png", 2),
]
h, w = 128, 192
ramp = np.tile(np.linspace(0, 1, w), (h, 1))
fig, axes = plt.subplots(len(pairs), 4, figsize=(14, 3.2 * len(pairs)), gridspec_kw={"width_ratios": [1, 1, 3, 3]})
for row, (na, nb, step) in zip(axes, pairs):
    a, b = load(na, step), load(nb, step)
    cmap = None if a.ndim == 3 else "gray"
    equal = mix_textures([a, b], (h, w), rng=0)
    ramped = mix_textures([a, b], (h, w), weights=[1 - ramp, ramp], rng=0)
    for ax, img, title in zip(row, [a, b, equal, ramped], ["source A", "source B", "equal weighting", "ramp A -> B"]):
        ax.imshow(img, cmap=cmap, vmin=0, vmax=1)
        ax.set_title(title)
        ax.axis("off")
    cols = [(x, texture_energy(ramped[:, x : x + 32], a), texture_energy(ramped[:, x : x + 32], b)) for x in range(0, w, 32)]
    print(na, nb, "ramp energy per 32-column strip (vs A, vs B):", [(x, round(ea, 4), round(eb, 4)) for x, ea, eb in cols])
fig.tight_layout()
fig.savefig(OUT / "texture_mixing.png", dpi=80)
