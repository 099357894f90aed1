"""
Perlin noise, turbulence and fBm
================================

The lecture slides "Perlin's Noise", "Turbulence Function" and "Synthesis of
Turbulence (1D/2D)": gradient noise on an integer lattice (zero at every
lattice point, band-limited around the lattice frequency), its tileable
variant, and the octave sums ``turbulence = sum |noise(2^i x)| / 2^i`` (truncated
at the pixel size) and fBm.

Figures (examples/output/):

- ``procedural_noise.png``: noise with the quintic and the cubic fade, a
  tileable tile repeated 2 x 2, turbulence, fBm, and the artefact the
  per-octave irrational shift removes (octaves aligned with the lattice are
  all zero on the coarse lattice points);
- ``procedural_turbulence_1d.png``: one row through the octaves and their
  sum, as the slide "Synthesis of Turbulence (1D)";
- ``procedural_spectra.png``: radially averaged power spectra: noise is a
  band around the lattice frequency, turbulence falls off with frequency.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.procedural import band_limit_octaves, fbm, perlin, turbulence

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
N, FREQ, SEED = 256, 8, 3

# %%
# Noise, tiling, turbulence, fBm
quintic = perlin((N, N), frequency=FREQ, rng=SEED)
cubic = perlin((N, N), frequency=FREQ, rng=SEED, fade="cubic")
tile = perlin((N // 2, N // 2), frequency=4, period=4, rng=SEED)
tiled = np.tile(tile, (2, 2))
turb = turbulence((N, N), frequency=FREQ, rng=SEED)
brown = fbm((N, N), frequency=FREQ, rng=SEED)
# the trap: octaves evaluated at exactly 2^i x share the coarse lattice's zeros
aligned = sum(np.abs(perlin((N, N), frequency=FREQ * 2**i, rng=SEED)) / 2**i
              for i in range(band_limit_octaves((N, N), FREQ)))

panels = [
    (quintic, "Perlin noise, quintic fade (2002)"),
    (cubic, "cubic Hermite fade (1985)"),
    (tiled, "period=4: one tile repeated 2x2"),
    (turb, f"turbulence, {band_limit_octaves((N, N), FREQ)} octaves (band limit)"),
    (brown, "fBm (signed sum)"),
    (aligned, "turbulence without octave shift:\nzeros on the coarse lattice"),
]
fig, axes = plt.subplots(2, 3, figsize=(12, 8.4))
for ax, (img, title) in zip(axes.ravel(), panels):
    ax.imshow(img, cmap="gray", interpolation="nearest")
    ax.set_title(title, fontsize=10)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "procedural_noise.png", dpi=90)

# %%
# Synthesis of turbulence in 1-D: one row through the octaves
row = 100
octaves = band_limit_octaves((N, N), FREQ)
fig, axes = plt.subplots(octaves + 1, 1, figsize=(9, 10), sharex=True)
total = np.zeros(N)
for i in range(octaves):
    shift = (i * (np.sqrt(5) - 1) / 2, i * (np.sqrt(2) - 1))  # the octave shift turbulence uses
    layer = np.abs(perlin((N, N), frequency=FREQ * 2**i, offset=shift, rng=SEED)[row]) / 2**i
    total += layer
    axes[i].plot(layer, lw=1)
    axes[i].set_ylabel(f"|n(2^{i}x)|/2^{i}", fontsize=8)
axes[-1].plot(total, color="k", lw=1.2)
axes[-1].set_ylabel("sum", fontsize=8)
axes[0].set_title("Synthesis of turbulence (1-D): octaves and their sum along one row")
fig.tight_layout()
fig.savefig(OUT / "procedural_turbulence_1d.png", dpi=80)


# %%
# Power spectra
def radial_spectrum(img):
    power = np.abs(np.fft.fftshift(np.fft.fft2(img - img.mean()))) ** 2
    k = np.arange(img.shape[0]) - img.shape[0] // 2
    r = np.hypot(k[:, None], k[None, :]).astype(int)
    return np.bincount(r.ravel(), power.ravel()) / np.maximum(np.bincount(r.ravel()), 1)


big = 512
fig, ax = plt.subplots(figsize=(7, 4.5))
for img, label in [(perlin((big, big), frequency=16, period=16, rng=1), "noise (16 cells)"),
                   (turbulence((big, big), frequency=16, period=16, rng=1), "turbulence"),
                   (fbm((big, big), frequency=16, period=16, rng=1), "fBm")]:
    spec = radial_spectrum(img)[1 : big // 2]
    ax.loglog(np.arange(1, big // 2), spec / spec.max(), label=label)
ax.axvline(16, color="gray", ls=":", label="lattice frequency")
ax.set_xlabel("frequency (cycles per image)")
ax.set_ylabel("normalised power")
ax.legend()
ax.set_title("Radially averaged power spectra")
fig.tight_layout()
fig.savefig(OUT / "procedural_spectra.png", dpi=90)
print("wrote", sorted(p.name for p in OUT.glob("procedural_*.png")))
