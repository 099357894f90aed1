"""Graph-cut video (Kwatra et al. 2003, Section 5) on simulated clips: writes ``docs/_static/graphcut_video_*``.

The clips are ``texsynth.data.clip("flame" | "waves", 32, 128)`` (simulated; no video is bundled), each
extended from 32 to 64 frames with the defaults (16-frame blocks of whole frames, 8-frame overlaps),
seed 0. Writes

- ``graphcut_video_strip.png``: per clip, output frames 12 to 23 (the second block's overlap is frames
  16-23), every second one;
- ``graphcut_video_slices.png``: time slices: the pixels of row 64 of every frame, one frame per line, time
  running down (so a seam in time shows as a horizontal break), for (1) the clip played twice (a hard cut
  at frame 32), (2) the graph-cut extension with the seams between its blocks in red (right half only, so the
  texture shows on the left), (3) the same without marks, (4) a 48-frame loop (``loop=True``) played twice,
  its wrap in the middle;
- ``graphcut_video_loop.gif``: the 48-frame loops of both clips side by side, at 15 fps (it wraps seamlessly);
- ``graphcut_video_space.png``: the waves extended in space and time, 128 -> 192 px and 32 frames (the default
  blocks, 16 x 64 x 64), frames 10, 20 and 30, each beside itself with the seams of that frame in red;

and prints the seam costs against the straight-cut baseline.

    python benchmarks/figure_graphcut_video.py
"""

from pathlib import Path

import numpy as np

from texsynth import data
from texsynth.io import save_frames, save_image
from texsynth.video._graphcut_video import graphcut_video

HERE = Path(__file__).resolve().parent
STATIC = HERE.parent / "docs" / "_static"
ROW = 64
RED = np.array([1.0, 0.1, 0.1])


def gap(h, w=4):
    return np.ones((h, w, 3))


def hstack(parts, w=4):
    out = []
    for p in parts:
        out += [p, gap(p.shape[0], w)]
    return np.concatenate(out[:-1], 1)


def seams_in_time(labels, row):
    """Where, on one row of every frame, a pixel's block differs from its block in the next frame or next pixel."""
    lab = labels[:, row, :]
    edge = np.zeros(lab.shape, bool)
    edge[:-1] |= lab[:-1] != lab[1:]
    edge[:, :-1] |= lab[:, :-1] != lab[:, 1:]
    return edge


def time_slice(video, row, scale=2):
    return np.repeat(video[:, row, :], scale, 0)


def main():
    STATIC.mkdir(parents=True, exist_ok=True)
    strips, slices, loops = [], [], []
    for name in ("flame", "waves"):
        clip = data.clip(name, 32, 128, rng=0)
        out, info = graphcut_video(clip, 64, rng=0, return_info=True)
        loop, linfo = graphcut_video(clip, 48, loop=True, rng=0, return_info=True)
        print(f"{name}: offsets {(info.corners - info.sources)[:, 0].tolist()}, seam cost per block "
              f"{np.round(info.seam_costs, 1).tolist()} against straight cuts "
              f"{np.round(info.baseline_costs, 1).tolist()}: total {info.seam_costs.sum():.0f} vs "
              f"{info.baseline_costs.sum():.0f} ({100 * (1 - info.seam_costs.sum() / info.baseline_costs.sum()):.0f} % "
              f"lower); loop {linfo.seam_costs.sum():.0f} vs {linfo.baseline_costs.sum():.0f}")
        steps = np.abs(np.diff(loop, axis=0)).mean(axis=(1, 2, 3))
        wrap = np.abs(loop[0] - loop[-1]).mean()
        print(f"  loop: mean |frame t+1 - frame t| {steps.mean():.4f} (max {steps.max():.4f}), wrap {wrap:.4f}")
        strips.append(hstack([out[t] for t in range(12, 24, 2)]))
        marked = out[:, ROW, :].copy()
        edge = seams_in_time(info.labels, ROW)
        edge[:, :64] = False
        marked[edge] = RED
        twice = np.concatenate([clip, clip])
        slices.append(hstack([time_slice(twice, ROW), np.repeat(marked, 2, 0), time_slice(out, ROW),
                              time_slice(np.concatenate([loop, loop])[24:24 + 64], ROW)], 8))
        loops.append(loop)
    strip = np.concatenate([strips[0], np.ones((8, strips[0].shape[1], 3)), strips[1]], 0)
    save_image(STATIC / "graphcut_video_strip.png", strip, overwrite=True)
    sl = hstack(slices, 16)
    save_image(STATIC / "graphcut_video_slices.png", sl, overwrite=True)
    both = np.concatenate([loops[0], np.ones((48, 128, 4, 3)), loops[1]], 2)
    save_frames(STATIC / "graphcut_video_loop.gif", both, fps=15, loop=True, overwrite=True)
    clip = data.clip("waves", 32, 128, rng=0)
    wide, winfo = graphcut_video(clip, 32, size=192, rng=0, return_info=True)
    print(f"waves 128 -> 192 px: {len(winfo.corners)} blocks {winfo.block}, seam cost {winfo.seam_costs.sum():.0f} "
          f"against straight cuts {winfo.baseline_costs.sum():.0f}, {winfo.seconds:.0f} s")
    panels = []
    for t in (10, 20, 30):
        lab, marked = winfo.labels[t], wide[t].copy()
        edge = np.zeros(lab.shape, bool)
        edge[:, :-1] |= lab[:, :-1] != lab[:, 1:]
        edge[:-1] |= lab[:-1] != lab[1:]
        marked[edge] = RED
        panels.append(hstack([wide[t], marked]))
    save_image(STATIC / "graphcut_video_space.png", hstack(panels, 12), overwrite=True)
    print("wrote", *(p.name for p in sorted(STATIC.glob("graphcut_video_*"))),
          f"({(STATIC / 'graphcut_video_loop.gif').stat().st_size / 1e6:.2f} MB GIF)")


if __name__ == "__main__":
    main()
