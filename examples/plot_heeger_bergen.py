"""
Heeger-Bergen pyramid-based texture synthesis: successes and failures
=====================================================================

Heeger & Bergen (SIGGRAPH 1995) describe a texture by the histograms of its
pixels and of the sub-bands of a steerable pyramid, and synthesise by matching
those histograms starting from noise. This reproduces the "Results" and
"Failures" of the paper: stochastic textures (metal, gravel, bread, water) are
reproduced convincingly, while textures whose look depends on aligned
structure (text, bricks) are not - their histograms match but the letters and
mortar lines dissolve into blobs.

Colour exemplars are decorrelated by PCA (Briand et al., IPOL 2014). The third
figure compares the three ways of treating the non-periodic exemplar border.
Outputs are 1.5x the exemplar's size (any size works) and tile seamlessly.

Exemplars: the bundled samples (``texsynth.data``) and scikit-image's gravel
and brick photographs (``skimage.data``).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata
from skimage.transform import resize

from texsynth import data
from texsynth.statistical import heeger_bergen
from texsynth.metrics import spectrum_distance

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUTPUT = HERE / "output"
OUTPUT.mkdir(exist_ok=True)

CASES = [  # (sample, exemplar side, expected behaviour)
    ("metal", 128, "stochastic: works"),
    ("gravel", 128, "stochastic: works"),
    ("bread", None, "stochastic colour: works"),
    ("water", 128, "water, colour: works"),
    ("text", 128, "structured: fails"),
    ("skimage brick", 128, "structured: fails"),
    ("brick", None, "structured colour: fails"),
]


def load(name, side):
    """A bundled sample, or scikit-image's gravel or (grey) brick photograph, resized to side x side."""
    if name == "gravel":
        image = skdata.gravel() / 255.0
    elif name == "skimage brick":
        image = skdata.brick() / 255.0
    else:
        image = data.load(name)
    if side is not None:
        image = resize(image, (side, side), anti_aliasing=True)
    return image


def show(ax, image, title):
    ax.imshow(np.clip(image, 0, 1), cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1)
    ax.set_title(title, fontsize=8)
    ax.axis("off")


fig, axes = plt.subplots(len(CASES), 3, figsize=(9, 3 * len(CASES)))
for row, (name, side, label) in zip(axes, CASES):
    exemplar = load(name, side)
    size = (int(exemplar.shape[0] * 1.5), int(exemplar.shape[1] * 1.5))
    scales = 4 if min(exemplar.shape[:2]) >= 64 else 3
    out = heeger_bergen(exemplar, size, scales=scales, rng=0)
    noise = np.random.default_rng(0).random(out.shape)
    show(row[0], exemplar, f"{name} {exemplar.shape[:2]}\n({label})")
    show(row[1], out, f"Heeger-Bergen {size}, 5 iterations\nspectrum distance {spectrum_distance(out, exemplar):.2f} "
         f"(noise {spectrum_distance(noise, exemplar):.2f})")
    show(row[2], np.tile(out, (2, 2) + (1,) * (out.ndim - 2)), "output tiled 2x2 (periodic)")
fig.tight_layout()
fig.savefig(OUTPUT / "heeger_bergen.png", dpi=90)
print("saved", OUTPUT / "heeger_bergen.png")

# Boundary treatment of the exemplar (Briand et al. 2014, sec. 2.4): the wood photograph's left and
# right edges do not match, so wrapped around it has a vertical seam that the FFT pyramid sees.
exemplar = load("wood", None)
fig, axes = plt.subplots(1, 4, figsize=(12, 3.4))
show(axes[0], exemplar, "exemplar")
for ax, mode in zip(axes[1:], ["periodic+smooth", "mirror", "none"]):
    out = heeger_bergen(exemplar, (144, 210), scales=4, periodic_exemplar=mode, rng=1)
    show(ax, out, f"periodic_exemplar={mode!r}\nspectrum distance {spectrum_distance(out, exemplar):.3f}")
fig.tight_layout()
fig.savefig(OUTPUT / "heeger_bergen_boundary.png", dpi=90)
print("saved", OUTPUT / "heeger_bergen_boundary.png")

# Convergence: histogram distance of every sub-band per iteration (metal).
exemplar = load("metal", 128)
_, info = heeger_bergen(exemplar, scales=4, iterations=8, rng=0, return_info=True)
fig, ax = plt.subplots(figsize=(6, 4))
ax.semilogy(info.band_distances, color="0.7", lw=0.8)
ax.semilogy(info.band_distances.mean(axis=1), color="k", lw=2, label="mean over sub-bands")
ax.set_xlabel("iteration (0 = histogram-matched noise)")
ax.set_ylabel("Wasserstein-1 / exemplar band std")
ax.set_title("Heeger-Bergen on metal: sub-band histogram distance")
ax.legend()
fig.tight_layout()
fig.savefig(OUTPUT / "heeger_bergen_convergence.png", dpi=90)
print("saved", OUTPUT / "heeger_bergen_convergence.png")
