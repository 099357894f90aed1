"""
Reaction-diffusion: Turk's spots forming, and the Gray-Scott zoo
================================================================

The slide "Reaction Diffusion Based Method" (Turk, SIGGRAPH 1991): two
chemicals a and b react and diffuse on a grid; from the uniform state
a = b = 4 with a slightly random substrate beta = 12 +- 0.1, the faster
diffusion of a lets small perturbations grow into spots of one size. The
second figure runs Turk's cascade (large spots, then the spots frozen and the
system run again with a larger reaction rate, filling the gaps with small
spots), the third the Gray-Scott presets (Pearson 1993).

Outputs (examples/output/): ``procedural_rd_forming.png`` (frames),
``procedural_rd_forming.gif`` (the animation, via texsynth.io.save_frames),
``procedural_rd_turk.png`` (presets and cascade) and
``procedural_rd_gray_scott.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.io import save_frames
from texsynth.procedural import GRAY_SCOTT_PRESETS, apply_colormap, gray_scott, reaction_diffusion
from texsynth.procedural.reaction_diffusion import RD_COLORS

OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

# %%
# Spots forming (Turk's spot parameters)
steps, every = 12000, 400
image, info = reaction_diffusion((128, 128), steps=steps, record_every=every, rng=1, return_info=True)
b = info.frames  # (T, H, W) concentration of b
lo, hi = 0.0, float(b.max())
frames = apply_colormap(1 - (b - lo) / (hi - lo), RD_COLORS)  # fixed scale: spots (low b) dark
save_frames(OUT / "procedural_rd_forming.gif", frames, fps=8, overwrite=True)
show = [0, 2, 5, 9, 14, len(b) - 1]
fig, axes = plt.subplots(1, len(show), figsize=(3 * len(show), 3.3))
for ax, t in zip(axes, show):
    ax.imshow(frames[t])
    ax.set_title(f"step {(t + 1) * every}", fontsize=10)
    ax.axis("off")
fig.suptitle("Turk's reaction-diffusion: spots forming (b, common colour scale)")
fig.tight_layout()
fig.savefig(OUT / "procedural_rd_forming.png", dpi=80)
plt.close(fig)

# %%
# Turk's presets and the cascade
panels = []
for pattern in ["spots", "small-spots", "large-spots", "irregular"]:
    panels.append((reaction_diffusion((128, 128), steps=12000, pattern=pattern, rng=2), pattern))
panels.append((reaction_diffusion((128, 128), steps=12000, pattern="large-spots", cascade=[(1 / 40, 6000)], rng=2),
               "cascade: large spots, then s=1/40"))
fig, axes = plt.subplots(1, len(panels), figsize=(3.2 * len(panels), 3.5))
for ax, (img, title) in zip(axes, panels):
    ax.imshow(img)
    ax.set_title(title, fontsize=10)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "procedural_rd_turk.png", dpi=80)
plt.close(fig)

# %%
# Gray-Scott presets
names = list(GRAY_SCOTT_PRESETS)
fig, axes = plt.subplots(1, len(names), figsize=(3.2 * len(names), 4.0))
for ax, name in zip(axes, names):
    img = gray_scott((128, 128), preset=name, steps=10000, rng=0)
    p = GRAY_SCOTT_PRESETS[name]
    ax.imshow(img)
    ax.set_title(f"{name}\nF={p['F']}, k={p['k']}", fontsize=10)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "procedural_rd_gray_scott.png", dpi=80)
plt.close(fig)
print("wrote procedural_rd_*.png and procedural_rd_forming.gif")
