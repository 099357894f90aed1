"""Speed and memory of texture optimization (Kwatra et al. 2005), side by side.

Run: python benchmarks/bench_optimization.py [--methods auto,exact,kdtree,tsvq] [--seed 0]

Prints one table: 128x128 colour exemplar -> 256x256 output with the
defaults (3 levels, 32/16/8, w/4 grid, r = 0.8, at most 5 iterations per
stage) for each nearest-neighbour backend: wall time (untraced), time per level, share
in nearest-neighbour search, peak memory (tracemalloc, a second one-iteration run), the final texture
energy (texsynth.metrics.texture_energy, exact), its cost and the speed-up
against the exact backend ("auto" is the default: exact search for small
exemplar sets, kd-tree above 5000 neighbourhoods); then flow-guided 256x256 frames (4 frames after
a given first one, rotation 0.05 rad per frame: seconds of the first, which builds the sequence's
indexes, and mean of the next ones; texture energy of the last frame; flicker = mean absolute
change against the warped previous frame). Reference: the paper's
MATLAB code took 7-10 min for a 256x256 texture and 20-60 s per flow-guided
frame (2.4 GHz dual processor, 2005). Targets here: <= 10 s, < 1 GiB,
<= 2 s per frame.
"""

import argparse
import os
import platform
import resource
import time
import tracemalloc
from pathlib import Path

import numpy as np

from texsynth import flows
from texsynth.io import load_image
from texsynth.metrics import texture_energy
from texsynth.optimization import animate_texture, optimize_texture

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def load():
    return "%.1f %.1f %.1f" % os.getloadavg()


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--methods", default="auto,exact,kdtree,tsvq")
    parser.add_argument("--texture", default="rohitrango/t4.png")
    parser.add_argument("--seed", type=int, default=0)
    args = parser.parse_args()
    ex = load_image(TEXTURES / args.texture)[..., :3][:128, :128]
    print(f"# texture optimization benchmark: {args.texture} {ex.shape} -> 256x256; "
          f"python {platform.python_version()}, {platform.machine()}, load {load()}")
    print(f"{'method':8s} {'total s':>8s} {'lvl2 s':>7s} {'lvl1 s':>7s} {'lvl0 s':>7s} {'NN %':>5s} "
          f"{'peak MiB':>9s} {'energy':>8s} {'vs exact':>8s} {'speed-up':>8s} {'iters':>6s}")
    rows = []
    for method in args.methods.split(","):
        # timed without tracemalloc (it slows allocation-heavy code); peak memory in a second run
        t0 = time.perf_counter()
        out, info = optimize_texture(ex, 256, method=method, rng=args.seed, return_info=True)
        seconds = time.perf_counter() - t0
        tracemalloc.start()
        optimize_texture(ex, 256, method=method, rng=args.seed, max_iterations=1)
        peak = tracemalloc.get_traced_memory()[1] / 2**20
        tracemalloc.stop()
        rows.append((method, seconds, info, peak, texture_energy(out, ex)))
    # energy cost and speed-up of each backend against exact search (same seed, same schedule)
    ref = {m: (s, e) for m, s, _, _, e in rows}.get("exact", (rows[0][1], rows[0][4]))
    for method, seconds, info, peak, energy in rows:
        lv = info.level_seconds
        print(f"{method:8s} {seconds:8.1f} {lv.get(2, 0):7.1f} {lv.get(1, 0):7.1f} {lv.get(0, 0):7.1f} "
              f"{100 * info.nn_share:5.0f} {peak:9.0f} {energy:8.5f} {energy / ref[1]:8.3f} {ref[0] / seconds:8.2f} "
              f"{sum(s.iterations for s in info.stages):6d}")
    # flow-guided 256x256 frames (frame 1 given: only the constrained re-synthesis is timed);
    # the first timed frame includes the one-off index builds of the sequence
    first = optimize_texture(ex, 256, neighborhood_sizes=(8,), levels=1, max_iterations=1, rng=0)
    rot = flows.rotation((256, 256), 0.05)
    print(f"{'flow frames 256x256':24s} {'first s':>8s} {'next s':>7s} {'energy':>8s} {'flicker':>8s}  (load {load()})")
    for method in args.methods.split(","):
        video, ainfo = animate_texture(ex, rot, frames=5, first_frame=first, method=method, rng=0, return_info=True)
        flicker = np.mean([np.mean(np.abs(video[i + 1] - flows.warp(video[i], rot, mode="nearest", order=3)))
                           for i in range(len(video) - 1)])
        print(f"{method:24s} {ainfo.frame_seconds[0]:8.2f} {ainfo.frame_seconds[1:].mean():7.2f} "
              f"{texture_energy(video[-1], ex):8.5f} {flicker:8.4f}")
    print(f"max RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")
    print("paper (MATLAB, 2005): 7-10 min per 256x256 texture, 20-60 s per flow-guided frame")


if __name__ == "__main__":
    main()
