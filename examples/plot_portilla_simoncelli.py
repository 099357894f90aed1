"""
Portilla-Simoncelli synthesis: the paper's classic cases, convergence, colour
=============================================================================

Portilla & Simoncelli (IJCV 2000) describe a texture by joint statistics of a
complex steerable pyramid (marginals, autocorrelations of low-pass images and
of band magnitudes, cross-orientation and cross-scale magnitude correlations,
cross-scale phase statistics) and synthesise by iterated projections from
noise. The first figure puts the authors' own samples (text, reptile skin,
metal, nuts; 128x128 crops of the 256x256 images to keep the example quick -
set ``SIDE = 256`` for the paper's size, about three times as long -, 4
scales, 4 orientations, 7x7 neighbourhood, 50 iterations) next to
Heeger-Bergen, which only matches sub-band histograms.
The second shows the convergence (signal-to-noise ratio of each group of
statistics per iteration, the MATLAB code's ``snrP``). The third shows colour
(principal components plus cross-channel correlations per band, as Ruiters
et al. 2010 extend it) and output sizes different from the exemplar's. The
fourth synthesises from the linear interpolation of two textures' statistics
(``portilla_simoncelli(interpolate_statistics(a, b, alpha), size)``), the
fifth imposes statistics on a region of an image only (``ps_step(...,
mask=region)``), the rest of the image untouched. Every exemplar is a bundled
sample (``texsynth.data``).
"""

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.statistical import SNR_GROUPS, interpolate_statistics, portilla_simoncelli, ps_statistics, ps_step

try:
    from texsynth.statistical import heeger_bergen
except ImportError:  # pragma: no cover - the Heeger-Bergen module is optional here
    heeger_bergen = None

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUTPUT = HERE / "output"
OUTPUT.mkdir(exist_ok=True)


def show(ax, image, title):
    ax.imshow(np.clip(image, 0, 1), cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1,
              interpolation="nearest")
    ax.set_title(title, fontsize=8)
    ax.axis("off")


# %%
# The classic cases, next to Heeger-Bergen
# ----------------------------------------
CLASSIC = ["text", "reptile", "metal", "nuts"]
SIDE = 128  # crop of the 256 px samples
columns = 3 if heeger_bergen is not None else 2
fig, axes = plt.subplots(len(CLASSIC), columns, figsize=(3.2 * columns, 3.3 * len(CLASSIC)))
infos = {}
for row, name in zip(axes, CLASSIC):
    exemplar = data.load(name)[:SIDE, :SIDE]
    show(row[0], exemplar, f"exemplar {name} {exemplar.shape[0]}x{exemplar.shape[1]}")
    if heeger_bergen is not None:
        show(row[1], heeger_bergen(exemplar, rng=1), "Heeger-Bergen (5 iterations)")
    start = time.perf_counter()
    out, info = portilla_simoncelli(exemplar, rng=1, return_info=True)
    infos[name] = info
    seconds = time.perf_counter() - start
    show(row[-1], out, f"Portilla-Simoncelli (50 iterations, {seconds:.1f} s)")
    print(f"{name}: {seconds:.1f} s, final SNR "
          + ", ".join(f"{g} {info.snr[g][-1]:.1f}" for g in SNR_GROUPS if np.isfinite(info.snr[g][-1])))
fig.tight_layout()
fig.savefig(OUTPUT / "portilla_simoncelli_classic.png", dpi=110)

# %%
# Convergence: SNR of every group of statistics per iteration
# -----------------------------------------------------------
fig, axes = plt.subplots(1, len(CLASSIC), figsize=(4.2 * len(CLASSIC), 3.6), sharey=True)
for ax, name in zip(axes, CLASSIC):
    for group in SNR_GROUPS:
        values = infos[name].snr[group]
        if np.all(np.isnan(values)):
            continue
        ax.plot(np.arange(1, len(values) + 1), values, label=group)
    ax.set_title(name, fontsize=9)
    ax.set_xlabel("iteration")
    ax.grid(alpha=0.3)
axes[0].set_ylabel("SNR before the projection (dB)")
axes[-1].legend(fontsize=6, loc="lower right")
fig.tight_layout()
fig.savefig(OUTPUT / "portilla_simoncelli_convergence.png", dpi=110)

# %%
# Colour, and outputs of another size than the exemplar's
# -------------------------------------------------------
COLOUR = [("bread", None, (128, 160))]
fig, axes = plt.subplots(len(COLOUR), 2, figsize=(7, 3.2 * len(COLOUR)), squeeze=False)
for row, (name, side, size) in zip(axes, COLOUR):
    exemplar = data.load(name)
    if side is not None:
        exemplar = exemplar[:side, :side]
    scales = 4 if min(exemplar.shape[:2]) >= 64 else 3
    out = portilla_simoncelli(exemplar, size, scales=scales, rng=2)
    show(row[0], exemplar, f"exemplar {name} {exemplar.shape[0]}x{exemplar.shape[1]}")
    show(row[1], out, f"Portilla-Simoncelli {size[0]}x{size[1]}, {scales} scales")
fig.tight_layout()
fig.savefig(OUTPUT / "portilla_simoncelli_colour.png", dpi=110)

# %%
# Synthesis from interpolated statistics (the paper's sec. 6; what Ruiters et al. build on)
# -----------------------------------------------------------------------------------------
a = data.load("metal")[:128, :128]
b = data.load("reptile")[:128, :128]
stats_a, stats_b = ps_statistics(a), ps_statistics(b)
alphas = [0.0, 0.25, 0.5, 0.75, 1.0]
fig, axes = plt.subplots(1, len(alphas), figsize=(3 * len(alphas), 3.2))
for ax, alpha in zip(axes, alphas):
    target = interpolate_statistics(stats_a, stats_b, alpha)
    show(ax, portilla_simoncelli(target, (128, 128), rng=3), f"alpha = {alpha}")
fig.suptitle("metal (alpha 0) to reptile skin (alpha 1): synthesis from interpolated statistics, 50 iterations",
             fontsize=9)
fig.tight_layout()
fig.savefig(OUTPUT / "portilla_simoncelli_interpolation.png", dpi=110)

# %%
# Statistics imposed on a region only
# -----------------------------------
# ``ps_step(image, stats, mask=disk)`` measures every statistic on the disk, computes the correction
# from it and keeps the pixels outside; 30 steps turn the disk of a metal photograph into reptile skin.
# Pasting whole-image steps into the disk instead fits the statistics to disk and surroundings together.
base = data.load("metal")[:192, :192]
target = ps_statistics(data.load("reptile"))
yy, xx = np.mgrid[:192, :192]
disk = np.hypot(yy - 96, xx - 96) < 64
masked, pasted = base, base
for _ in range(30):
    masked = ps_step(masked, target, mask=disk)
    pasted = np.where(disk, ps_step(pasted, target), pasted)
fig, axes = plt.subplots(1, 3, figsize=(9.6, 3.4))
show(axes[0], base, "metal 192x192 (start)")
show(axes[1], masked, "ps_step(..., mask=disk) x30: reptile skin in the disk")
show(axes[2], pasted, "whole-image ps_step pasted into the disk x30")
fig.tight_layout()
fig.savefig(OUTPUT / "portilla_simoncelli_mask.png", dpi=110)
print("saved", sorted(p.name for p in OUTPUT.glob("portilla_simoncelli_*.png")))
