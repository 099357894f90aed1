"""
Wei-Levoy pixel synthesis: scanline and order-independent
=========================================================

Wei & Levoy (SIGGRAPH 2000) grow a texture pixel by pixel from noise: each
pixel takes the exemplar pixel whose causal neighbourhood (plus the parent
level's neighbourhood) is nearest. The order-independent variant (Wei & Levoy
2002) updates every pixel of a level at once from the previous pass. Each
row: exemplar (64x64), scanline result, order-independent result (200x200).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt

from texsynth.io import load_image
from texsynth.metrics import texture_energy
from texsynth.pixel import Neighborhood, synthesize_pixels

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

names = ["rohitrango/t4.png", "jcjohnson/bread.png", "lcv/reptil_skin.pgm"]
fig, axes = plt.subplots(len(names), 3, figsize=(9, 3 * len(names)))
for row, name in zip(axes, names):
    ex = load_image(TEXTURES / name)
    ex = (ex[..., :3] if ex.ndim == 3 else ex)[:64, :64]
    cmap = None if ex.ndim == 3 else "gray"
    row[0].imshow(ex, cmap=cmap, vmin=0, vmax=1)
    row[0].set_title(f"exemplar {name.split('/')[-1]}")
    for ax, order in zip(row[1:], ["scanline", "independent"]):
        out = synthesize_pixels(ex, 200, neighborhood=Neighborhood(neighborhood_size=7), order=order, rng=0)
        ax.imshow(out, cmap=cmap, vmin=0, vmax=1)
        ax.set_title(f"{order}, E={texture_energy(out, ex):.4f}")
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "pixel_synthesis.png", dpi=80)
