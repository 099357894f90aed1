"""
Texture mixtures from two sources (Wei 2002, Figure 1)
======================================================

Each output pixel minimises eq. 1, ``sum_i w_i (||p - p_i||^2 + ||N_i(p) -
N_i(p_i)||^2)``, by Wei's alternation. Each row: the two inputs, the result
with equal weighting (a uniform mixture) and with ramp weighting (the left
source turning into the right one, left to right).

A second figure measures the ramp: per 8-column strip, the texture energy of
the strip against each source, and ``f = E_A / (E_A + E_B)`` (0: looks like A
only, 1: like B only). A hard switch (step weights: A on the left half, B on
the right) is shown dashed for comparison: a ramp should rise steadily where
the switch jumps. The script prints the profile as a table.

The pair: scikit-image's brick and gravel photographs (``skimage.data``, grey,
at a quarter of their size). ``plot_texton_control.py`` mixes two colour
samples (brick and bread) the same way.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata

from texsynth import data
from texsynth.metrics import texture_energy
from texsynth.pixel import Neighborhood, mix_textures

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
STRIP = 8  # columns per strip of the energy profile


def load(name, step):
    """64 x 64 pixels of a bundled sample or of a scikit-image photograph ("skimage.brick"), every step-th."""
    img = getattr(skdata, name[8:])() / 255.0 if name.startswith("skimage.") else data.load(name)
    return img[: 64 * step : step, : 64 * step : step]


def profile(img, a, b):
    """Per STRIP-column strip: texture energy (8x8 patches) against a and against b."""
    cols = range(0, img.shape[1], STRIP)
    ea = np.array([texture_energy(img[:, x : x + STRIP], a) for x in cols])
    eb = np.array([texture_energy(img[:, x : x + STRIP], b) for x in cols])
    return ea, eb


def smoothness(f):
    """Spearman correlation of f with the column, and the largest strip-to-strip step / range of f."""
    rank = np.argsort(np.argsort(f))
    rho = np.corrcoef(np.arange(len(f)), rank)[0, 1]
    return rho, np.abs(np.diff(f)).max() / (f.max() - f.min())


# A neighbourhood per source (Wei 2002: sources differ in texon size): bricks are large texons, 9x9;
# gravel keeps 5x5. Add pairs to compare, e.g. ("brick", "bread", 1, [9, 5]) (bundled, colour).
pairs = [
    ("skimage.brick", "skimage.gravel", 4, [9, 5]),
]
h, w = 128, 192
ramp = np.tile(np.linspace(0, 1, w), (h, 1))
step = np.tile((np.arange(w) >= w // 2).astype(float), (h, 1))
fig, axes = plt.subplots(len(pairs), 4, figsize=(14, 3.2 * len(pairs)), gridspec_kw={"width_ratios": [1, 1, 3, 3]},
                         squeeze=False)
pfig, paxes = plt.subplots(len(pairs), 2, figsize=(12, 3.4 * len(pairs)), squeeze=False)
for row, prow, (na, nb, sub, sizes) in zip(axes, paxes, pairs):
    a, b = load(na, sub), load(nb, sub)
    cmap = None if a.ndim == 3 else "gray"
    kw = dict(neighborhood=Neighborhood(neighborhood_size=sizes), rng=0)
    equal = mix_textures([a, b], (h, w), **kw)
    ramped = mix_textures([a, b], (h, w), weights=[1 - ramp, ramp], **kw)
    switched = mix_textures([a, b], (h, w), weights=[1 - step, step], **kw)
    titles = [f"source A ({sizes[0]}x{sizes[0]})", f"source B ({sizes[1]}x{sizes[1]})",
              "equal weighting", "ramp A -> B"]
    for ax, img, title in zip(row, [a, b, equal, ramped], titles):
        ax.imshow(img, cmap=cmap, vmin=0, vmax=1)
        ax.set_title(title)
        ax.axis("off")

    ea, eb = profile(ramped, a, b)
    sa, sb = profile(switched, a, b)
    f, fs = ea / (ea + eb), sa / (sa + sb)
    x = np.arange(0, w, STRIP) + STRIP / 2
    wb = ramp[0, np.arange(0, w, STRIP) + STRIP // 2]  # weight of B at the strip centre
    label_a, label_b = na.split(".")[-1], nb.split(".")[-1]
    prow[0].plot(x, ea, "o-", color="C0", label=f"ramp vs A ({label_a})")
    prow[0].plot(x, eb, "o-", color="C1", label=f"ramp vs B ({label_b})")
    prow[0].plot(x, sa, "--", color="C0", alpha=0.6, label="hard switch vs A")
    prow[0].plot(x, sb, "--", color="C1", alpha=0.6, label="hard switch vs B")
    prow[0].set(xlabel="column", ylabel="texture energy",
                title=f"{label_a} -> {label_b}: energy per {STRIP}-column strip")
    prow[0].legend(fontsize=7)
    rho, jump = smoothness(f)
    rho_s, jump_s = smoothness(fs)
    prow[1].plot(x, f, "o-", color="C2", label=f"ramp (Spearman {rho:.2f}, largest step {jump:.2f})")
    prow[1].plot(x, fs, "--", color="C3", label=f"hard switch (Spearman {rho_s:.2f}, largest step {jump_s:.2f})")
    prow[1].plot(x, wb, ":", color="k", label="weight of B")
    prow[1].set(xlabel="column", ylabel="f = E_A / (E_A + E_B)", ylim=(0, 1), title="0: like A only, 1: like B only")
    prow[1].legend(fontsize=7)

    print(f"\n{label_a} -> {label_b}, neighborhood_size={sizes}, {h}x{w} ramp, energy per {STRIP}-column strip "
          f"(Spearman {rho:.2f}, largest step {jump:.2f} of the range; hard switch {rho_s:.2f}, {jump_s:.2f})")
    print("| columns | w_B | E vs A | E vs B | f | hard switch f |")
    print("|---|---|---|---|---|---|")
    for i, x0 in enumerate(range(0, w, STRIP)):
        print(f"| {x0}-{x0 + STRIP - 1} | {wb[i]:.2f} | {ea[i]:.4f} | {eb[i]:.4f} | {f[i]:.2f} | {fs[i]:.2f} |")
fig.tight_layout()
fig.savefig(OUT / "texture_mixing.png", dpi=80)
pfig.tight_layout()
pfig.savefig(OUT / "texture_mixing_profile.png", dpi=80)
