"""
Reaction-diffusion: Turk's spots and stripes, and the Gray-Scott zoo
====================================================================

The slide "Reaction Diffusion Based Method" (Turk, SIGGRAPH 1991): two
chemicals a and b react and diffuse on a grid; from the uniform state
a = b = 4 with a slightly random substrate beta = 12 +- 0.1, the faster
diffusion of a lets small perturbations grow into spots of one size. The
second figure shows Turk's presets, his cascade (large spots, then the spots
frozen and the system run again with a larger reaction rate), the
two-chemical "stripes" preset and Turk's own stripes (Meinhardt's
five-chemical system, ``meinhardt_stripes``). The third sweeps the diffusion
ratio D_a / D_b of the two-chemical system: spots at Turk's ratio 4 (the
Turing threshold), worms at 6-8, labyrinths from 10 on. The last shows the
Gray-Scott presets (Pearson 1993).

Outputs (examples/output/): ``procedural_rd_forming.png`` (frames),
``procedural_rd_forming.gif`` (the animation, via texsynth.io.save_frames),
``procedural_rd_turk.png`` (presets, cascade, stripes),
``procedural_rd_ratio.png`` (the D_a / D_b sweep) and
``procedural_rd_gray_scott.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.io import save_frames
from texsynth.procedural import GRAY_SCOTT_PRESETS, TurkRates, apply_colormap, gray_scott, reaction_diffusion
from texsynth.procedural import RD_COLORS, meinhardt_stripes

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)


def save_grid(panels, name, rows=1, suptitle=None, size=(3.2, 3.6)):
    """Save (image, title) panels as a rows x n grid to examples/output/<name>."""
    cols = -(-len(panels) // rows)
    fig, axes = plt.subplots(rows, cols, figsize=(size[0] * cols, size[1] * rows))
    axes = np.atleast_1d(axes).ravel()
    for ax in axes:
        ax.axis("off")
    for ax, (img, title) in zip(axes, panels):
        ax.imshow(img)
        ax.set_title(title, fontsize=10)
    if suptitle:
        fig.suptitle(suptitle)
    fig.tight_layout()
    fig.savefig(OUT / name, dpi=80)


# %%
# Spots forming (Turk's spot parameters)
steps, every = 12000, 400
image, info = reaction_diffusion((128, 128), steps=steps, record_every=every, rng=1, return_info=True)
b = info.frames  # (T, H, W) concentration of b
lo, hi = 0.0, float(b.max())
frames = apply_colormap(1 - (b - lo) / (hi - lo), RD_COLORS)  # fixed scale: spots (low b) dark
save_frames(OUT / "procedural_rd_forming.gif", frames, fps=8, overwrite=True)
show = [0, 2, 5, 9, 14, len(b) - 1]
save_grid([(frames[t], f"step {(t + 1) * every}") for t in show], "procedural_rd_forming.png",
          suptitle="Turk's reaction-diffusion: spots forming (b, common colour scale)", size=(3, 3.3))

# %%
# Turk's presets and the cascade
panels = []
for pattern in ["spots", "small-spots", "large-spots", "irregular"]:
    panels.append((reaction_diffusion((128, 128), steps=12000, preset=pattern, rng=2), pattern))
panels.append((reaction_diffusion((128, 128), steps=12000, preset="large-spots", cascade=[(1 / 40, 6000)], rng=2),
               "cascade: large spots, then s=1/40"))
panels.append((reaction_diffusion((128, 128), steps=12000, preset="stripes", rng=2),
               "stripes (Da/Db = 15, s=1/200)"))
panels.append((meinhardt_stripes((128, 128), steps=4000, rng=2), "Turk's stripes:\nMeinhardt, 4000 steps"))
save_grid(panels, "procedural_rd_turk.png", rows=2)

# %%
# Spots to stripes: the ratio of the diffusion rates (D_b = 0.01, s = 0.01,
# Turk's start and beta = 12 +- 0.1, 8000 steps; the linear Turing threshold
# is D_a / D_b = 4)
save_grid([(reaction_diffusion((128, 128), steps=8000, rates=TurkRates(s=0.01, Da=0.01 * r, Db=0.01), rng=0), f"Da/Db = {r}")
           for r in [4, 6, 8, 10, 15]], "procedural_rd_ratio.png",
          suptitle="Turk's two-chemical system: spots near the Turing threshold, labyrinths far above it")

# %%
# Gray-Scott presets
save_grid([(gray_scott((128, 128), preset=name, steps=10000, rng=0), f"{name}\nF={p.feed}, k={p.kill}")
           for name, p in GRAY_SCOTT_PRESETS.items()], "procedural_rd_gray_scott.png", size=(3.2, 4.0))
print("wrote procedural_rd_*.png and procedural_rd_forming.gif")
