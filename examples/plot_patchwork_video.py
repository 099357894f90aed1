"""
Patchwork video textures (Harrison 2002, Section 4)
===================================================

There is no video texture in ``../shared/textures``, so the input videos are
made from real photographs: (1) a window sliding diagonally over the water
photograph (``embark/1.jpg``) by a few pixels per frame, and (2) the same
photograph with a slow "breathing" brightness wave, a stand-in for flicker.
Both are 32 frames, 160x160.

The output is a 64-frame loop of 192x192 frames: one fixed Voronoi
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

from texsynth.io import load_image, save_frames
from texsynth.patch import patchwork_video

HERE = Path(__file__).resolve().parent
TEXTURES = HERE.parents[1] / "shared" / "textures"
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

full = load_image(TEXTURES / "embark" / "1.jpg")  # 300 x 300
photo = full[:160, :160]
T = 32
# a 160x160 window sliding over the photograph (1 px down, 2 px right per frame): no wrap seam
drift = np.stack([full[t : t + 160, 2 * t : 2 * t + 160] for t in range(T)])
wave = np.linspace(0, 2 * np.pi, 160)
breathing = np.stack(
    [np.clip(photo * (0.85 + 0.15 * np.sin(wave[None, :, None] + 2 * np.pi * t / T)), 0, 1) for t in range(T)]
)

for name, clip in [("drift", drift), ("flicker", breathing)]:
    out, info = patchwork_video(clip, 192, 64, grid_spacing=48, rng=1, return_info=True)
    diffs = np.array([np.abs(out[(t + 1) % 64] - out[t]).mean() for t in range(64)])
    print(f"{name}: consecutive-frame mean |diff| {diffs[:-1].mean():.4f} (max {diffs[:-1].max():.4f}); "
          f"last -> first {diffs[-1]:.4f}; key frames per cell {info.frame_keys.shape[1]}")
    fig = plt.figure(figsize=(14, 7.6), layout="constrained")
    grid = fig.add_gridspec(2, 5)
    for k, t in enumerate([0, 16, 32, 48, 63]):
        ax = fig.add_subplot(grid[0, k])
        ax.imshow(out[t])
        ax.set_title(f"output frame {t}")
        ax.axis("off")
    ax = fig.add_subplot(grid[1, 0:2])
    ax.imshow(clip[:, 80])
    ax.set_title("input: row 80 over time (time down)")
    ax.set_aspect("auto")
    ax = fig.add_subplot(grid[1, 2:4])
    ax.imshow(np.concatenate([out[:, 96], out[:, 96]]))
    ax.axhline(63.5, color="w", ls=":", lw=1)
    ax.set_title("output: row 96 over two loops (wrap at the dotted line)")
    ax.set_aspect("auto")
    ax = fig.add_subplot(grid[1, 4])
    ax.plot(diffs[:-1], "k.-", ms=3, label="t -> t+1")
    ax.plot([63], [diffs[-1]], "ro", label="63 -> 0 (wrap)")
    ax.set_xlabel("output frame t")
    ax.set_ylabel("mean |frame difference|")
    ax.legend(fontsize=8)
    fig.suptitle(f"Video patchwork, input '{name}' (real photograph animated; no video texture available)")
    fig.savefig(OUT / f"patchwork_video_{name}.png", dpi=80)
    save_frames(OUT / f"patchwork_video_{name}.gif", out, overwrite=True)
    print("saved", OUT / f"patchwork_video_{name}.png")
