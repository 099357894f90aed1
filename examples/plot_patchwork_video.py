"""
Patchwork video textures (Harrison 2002, Section 4)
===================================================

texsynth ships no video, so the input videos are made from a real
photograph: (1) a window sliding diagonally over the bundled water photograph
(``texsynth.data.load("water")``) by a few pixels per frame, and (2) the same
photograph with a slow "breathing" brightness wave, a stand-in for flicker.
Both are 16 frames, 128x128.

The output is a 24-frame loop of 128x128 frames: one fixed Voronoi
arrangement in space, and per cell an intermediate sequence of input clips
joined by cosine transitions (eqs. 3-6). The figure shows output frames, and
space-time slices (a row of pixels over time, time downwards: the paper's
Figure 5b "video cube" view) of the input and of the output repeated twice,
so the wrap from the last frame to the first is in the middle of the slice.
The loop is also saved as a GIF.

A steadily translating input is a hard case for this method: a loop cannot keep
moving one way, so each cell drifts for one interval and then cross-fades to an
earlier source frame; in the space-time slice this shows as a sawtooth of short
diagonal streaks, and in the animation as a gentle pulsing of the cells.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.io import save_frames
from texsynth.patch import patchwork_video

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

full = data.load("water")  # 300 x 300
T, SIDE = 16, 128  # input frames and their side
OUT_T, OUT_SIDE, GRID = 24, 128, 30  # the output loop: frames, side, grid spacing (at most a quarter of SIDE)
photo = full[:SIDE, :SIDE]
# a SIDE x SIDE window sliding over the photograph (1 px down, 2 px right per frame): no wrap seam
drift = np.stack([full[t : t + SIDE, 2 * t : 2 * t + SIDE] for t in range(T)])
wave = np.linspace(0, 2 * np.pi, SIDE)
breathing = np.stack(
    [np.clip(photo * (0.85 + 0.15 * np.sin(wave[None, :, None] + 2 * np.pi * t / T)), 0, 1) for t in range(T)]
)

for name, clip in [("drift", drift), ("flicker", breathing)]:
    out, info = patchwork_video(clip, OUT_SIDE, OUT_T, grid_spacing=GRID, rng=1, return_info=True)
    diffs = np.array([np.abs(out[(t + 1) % OUT_T] - out[t]).mean() for t in range(OUT_T)])
    print(f"{name}: consecutive-frame mean |diff| {diffs[:-1].mean():.4f} (max {diffs[:-1].max():.4f}); "
          f"last -> first {diffs[-1]:.4f}; key frames per cell {info.frame_keys.shape[1]}")
    fig = plt.figure(figsize=(14, 7.6), layout="constrained")
    grid = fig.add_gridspec(2, 5)
    for k, t in enumerate(np.linspace(0, OUT_T - 1, 5).round().astype(int)):
        ax = fig.add_subplot(grid[0, k])
        ax.imshow(out[t])
        ax.set_title(f"output frame {t}")
        ax.axis("off")
    ax = fig.add_subplot(grid[1, 0:2])
    ax.imshow(clip[:, SIDE // 2])
    ax.set_title(f"input: row {SIDE // 2} over time (time down)")
    ax.set_aspect("auto")
    ax = fig.add_subplot(grid[1, 2:4])
    ax.imshow(np.concatenate([out[:, OUT_SIDE // 2], out[:, OUT_SIDE // 2]]))
    ax.axhline(OUT_T - 0.5, color="w", ls=":", lw=1)
    ax.set_title(f"output: row {OUT_SIDE // 2} over two loops (wrap at the dotted line)")
    ax.set_aspect("auto")
    ax = fig.add_subplot(grid[1, 4])
    ax.plot(diffs[:-1], "k.-", ms=3, label="t -> t+1")
    ax.plot([OUT_T - 1], [diffs[-1]], "ro", label=f"{OUT_T - 1} -> 0 (wrap)")
    ax.set_xlabel("output frame t")
    ax.set_ylabel("mean |frame difference|")
    ax.legend(fontsize=8)
    fig.suptitle(f"Video patchwork, input '{name}' (real photograph animated; no video texture available)")
    fig.savefig(OUT / f"patchwork_video_{name}.png", dpi=80)
    save_frames(OUT / f"patchwork_video_{name}.gif", out, overwrite=True)
    print("saved", OUT / f"patchwork_video_{name}.png")
