"""
Texture optimization gallery (Kwatra et al. 2005, Figures 4 and 5)
==================================================================

Synthesises stochastic, structured and text textures with
:func:`texsynth.optimize_texture` at the paper's defaults (3 levels,
neighbourhoods 32/16/8 on a w/4 grid, IRLS r = 0.8) and scores each output
against the exemplar with :mod:`texsynth.metrics`, next to the two
baselines: histogram-matched noise (worst coherence) and a random-block
mosaic (naive patch pasting).

A third column adds the two options against the weaknesses of eq. 1, which
rewards coherence only: ``completeness_weight=1`` (the completeness half of
Simakov et al.'s 2008 bidirectional similarity: every exemplar neighbourhood
must appear somewhere in the output) and ``copy_limit=0.2`` (breaks verbatim
copies larger than about a third of the exemplar, which the completeness
term alone would favour).

The exemplars are bundled grey samples (``texsynth.data``): nuts (large
objects, at half size) and text, 128 px each, with 128 px outputs to keep the
example quick (about 20 s). Saves ``examples/output/optimization_gallery.png`` (exemplar,
output with the defaults, output with the options; one row per texture) and
one PNG per output.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from skimage.transform import rescale  # noqa: E402

from texsynth import data, metrics  # noqa: E402
from texsynth.io import save_image  # noqa: E402
from texsynth.optimization import Terms, optimize_texture  # noqa: E402

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
SIZE = 128

# (sample, kind): exemplars of about 128 px, as in the paper
CASES = [
    ("nuts", "objects"),
    ("text", "text"),
]


def load(name):
    image = data.load(name)
    if name == "nuts":  # 256 px: at half size more nuts fit in the output
        return rescale(image, 0.5, anti_aliasing=True)
    return image[:128, :128]


OPTIONS = dict(terms=Terms(completeness_weight=1.0, copy_limit=0.2))
rows = []
fig, axes = plt.subplots(len(CASES), 3, figsize=(9, 3 * len(CASES)))
for k, (name, kind) in enumerate(CASES):
    ex = load(name)
    noise = metrics.noise_baseline(ex, SIZE, rng=0)
    mosaic = metrics.mosaic_baseline(ex, SIZE, rng=0)
    baselines = dict(energy_noise=metrics.texture_energy(noise, ex), energy_mosaic=metrics.texture_energy(mosaic, ex),
                     completeness_mosaic=metrics.completeness(mosaic, ex))
    cmap = "gray" if ex.ndim == 2 else None
    axes[k, 0].imshow(ex, cmap=cmap, vmin=0, vmax=1)
    axes[k, 0].set_title(f"{name} ({kind})", fontsize=8)
    for col, (label, options) in enumerate([("defaults", {}), ("options", OPTIONS)], start=1):
        out, info = optimize_texture(ex, SIZE, rng=1, return_info=True, **options)
        save_image(OUT / f"optimization_{name}{'' if not options else '_options'}.png", out, overwrite=True)
        row = dict(
            name=name, kind=kind, label=label, seconds=info.seconds,
            energy=metrics.texture_energy(out, ex), completeness=metrics.completeness(out, ex),
            copy=metrics.verbatim_copy(out, ex), **baselines,
        )
        rows.append(row)
        axes[k, col].imshow(out, cmap=cmap, vmin=0, vmax=1)
        axes[k, col].set_title(f"{label} {SIZE}x{SIZE}: copy {row['copy']:.2f}, "
                               f"C/mosaic {row['completeness'] / row['completeness_mosaic']:.2f}", fontsize=8)
    for a in axes[k]:
        a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "optimization_gallery.png", dpi=110)

print(f"options: {OPTIONS}")
print(f"{'texture':10s} {'kind':10s} {'run':8s} {'s':>5s} {'E out':>8s} {'E noise':>8s} {'E mosaic':>8s} "
      f"{'C out':>8s} {'C mosaic':>8s} {'copy':>5s}")
for r in rows:
    print(f"{r['name']:10s} {r['kind']:10s} {r['label']:8s} {r['seconds']:5.1f} {r['energy']:8.5f} "
          f"{r['energy_noise']:8.5f} {r['energy_mosaic']:8.5f} {r['completeness']:8.5f} "
          f"{r['completeness_mosaic']:8.5f} {r['copy']:5.2f}")
for label in ("defaults", "options"):
    sel = [r for r in rows if r["label"] == label]
    print(f"{label}: mean E out / E noise {np.mean([r['energy'] / r['energy_noise'] for r in sel]):.3f}, "
          f"E out / E mosaic {np.mean([r['energy'] / r['energy_mosaic'] for r in sel]):.3f}, "
          f"median C out / C mosaic {np.median([r['completeness'] / r['completeness_mosaic'] for r in sel]):.2f}, "
          f"largest copy {max(r['copy'] for r in sel):.2f}")
