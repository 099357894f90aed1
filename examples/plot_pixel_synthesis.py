"""
Wei-Levoy pixel synthesis: scanline and order-independent
=========================================================

Wei & Levoy (SIGGRAPH 2000) grow a texture pixel by pixel from noise: each
pixel takes the exemplar pixel whose causal neighbourhood (plus the parent
level's neighbourhood) is nearest. The order-independent variant (Wei & Levoy
2002) updates every pixel of a level at once from the previous pass. Each
row: exemplar (a 64x64 crop of a bundled sample: nuts at half size, bread,
reptile skin), scanline result, order-independent result (128x128).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
from skimage.transform import rescale

from texsynth import data
from texsynth.metrics import texture_energy
from texsynth.pixel import Neighborhood, synthesize_pixels

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

exemplars = {"nuts": rescale(data.load("nuts"), 0.5, anti_aliasing=True)[:64, :64],
             "bread": data.load("bread")[:64, :64], "reptile": data.load("reptile")[:64, :64]}
fig, axes = plt.subplots(len(exemplars), 3, figsize=(9, 3 * len(exemplars)))
for row, (name, ex) in zip(axes, exemplars.items()):
    cmap = None if ex.ndim == 3 else "gray"
    row[0].imshow(ex, cmap=cmap, vmin=0, vmax=1)
    row[0].set_title(f"exemplar: {name}")
    for ax, order in zip(row[1:], ["scanline", "independent"]):
        out = synthesize_pixels(ex, 128, neighborhood=Neighborhood(neighborhood_size=7), order=order, rng=0)
        ax.imshow(out, cmap=cmap, vmin=0, vmax=1)
        ax.set_title(f"{order}, E={texture_energy(out, ex):.4f}")
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "pixel_synthesis.png", dpi=80)
