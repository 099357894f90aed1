"""
Random phase noise and ADSN: micro-textures in one FFT
======================================================

Galerne, Gousseau & Morel (IEEE TIP 2011) synthesise a *micro-texture* by
keeping the modulus of the exemplar's Fourier transform and replacing its
phase: random phase noise (RPN) adds a uniform random phase, asymptotic
discrete spot noise (ADSN) convolves the normalised exemplar with Gaussian
white noise. Both run on the periodic component of the exemplar (Moisan's
periodic-plus-smooth decomposition) and give outputs of any size.

The first figure shows RPN and ADSN, 3x the exemplar's area, on three
micro-textures (brushed metal, grass, wood grain) and where the model fails:
bricks, whose edges are carried by the phases that RPN throws away. The
second shows why the periodic component is used. Exemplars: the bundled metal
and wood samples (``texsynth.data``) and scikit-image's grass and brick
photographs (``skimage.data``). ``python plot_random_phase.py --docs`` in a
checkout also refreshes the documentation's copy of the first figure,
``docs/_static/random_phase.png``.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata

from texsynth import data
from texsynth.metrics import noise_baseline, spectrum_distance
from texsynth.statistical import random_phase_noise

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUTPUT = HERE / "output"
OUTPUT.mkdir(exist_ok=True)
# the figure of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUTPUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])

CASES = [  # (sample, crop, label)
    ("metal", 128, "micro-texture: works"),
    ("skimage.grass", 128, "grass: the grain, not the blades"),
    ("wood", None, "wood grain, colour: works"),
    ("skimage.brick", 128, "structured: fails"),
]


def load(name, crop):
    """A bundled sample, or a scikit-image photograph ("skimage.grass"), cropped to crop x crop."""
    image = getattr(skdata, name[8:])() / 255.0 if name.startswith("skimage.") else data.load(name)
    return image if crop is None else image[:crop, :crop]


def show(ax, image, title):
    ax.imshow(np.clip(image, 0, 1), cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1,
              interpolation="nearest")
    ax.set_title(title, fontsize=8)
    ax.axis("off")


fig, axes = plt.subplots(len(CASES), 3, figsize=(10, 3.3 * len(CASES)), gridspec_kw={"width_ratios": [1, 1.7, 1.7]})
for row, (name, crop, label) in zip(axes, CASES):
    exemplar = load(name, crop)
    size = (int(exemplar.shape[0] * 1.7), int(exemplar.shape[1] * 1.7))
    noise = noise_baseline(exemplar, size, rng=0)
    show(row[0], exemplar, f"{name} {exemplar.shape[0]}x{exemplar.shape[1]}\n({label})")
    for ax, process in zip(row[1:], ("rpn", "adsn")):
        start = time.perf_counter()
        out = random_phase_noise(exemplar, size, process=process, rng=0)
        seconds = time.perf_counter() - start
        show(ax, out, f"{process.upper()} {size[0]}x{size[1]} ({1000 * seconds:.0f} ms)\nspectrum distance "
             f"{spectrum_distance(out, exemplar):.2f} (noise {spectrum_distance(noise, exemplar):.2f})")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "random_phase.png", dpi=80)
print("saved", OUTPUT / "random_phase.png")

# The periodic component: the wood photograph's opposite borders do not match, so its Fourier modulus has a
# bright cross, which random phase noise turns into horizontal and vertical streaks.
exemplar = load("wood", None)
fig, axes = plt.subplots(1, 3, figsize=(11, 2.8))
show(axes[0], exemplar, "exemplar")
for ax, mode in zip(axes[1:], ("periodic+smooth", "none")):
    out = random_phase_noise(exemplar, (192, 280), periodic_exemplar=mode, rng=1)
    show(ax, out, f"periodic_exemplar={mode!r}")
fig.tight_layout()
fig.savefig(OUTPUT / "random_phase_periodic.png", dpi=80)
print("saved", OUTPUT / "random_phase_periodic.png")
