"""Graph-cut video: a 32-frame 128x128 colour clip extended to 64 frames in at most 60 s.

Run: python benchmarks/bench_graphcut_video.py [--repeat 1]

The clips are ``texsynth.data.clip("flame" | "waves" | "rain", 32, 128, rng=0)`` (simulated, RGB, float64),
extended with the defaults (16-frame blocks of whole frames, 8-frame overlaps, seed 0). Timed without
``return_info`` (the best of ``--repeat`` runs); then once more with ``return_info=True``, which also prices
the straight cut of every overlap (a plane between its middle frames) for the seam-cost comparison.
Side by side in the same run, the naive reference: the clip played twice (``np.concatenate``), a hard cut
at frame 32. "Largest step" is the largest mean absolute difference between consecutive output frames, in
units of the clip's own largest one (a hard cut between unrelated frames is about 2 on the waves).
"""

import argparse
import time

import numpy as np

from texsynth import data
from texsynth.video._graphcut_video import graphcut_video

TARGET = 60.0  # seconds for 32 -> 64 frames at 128 x 128


def largest_step(video, clip):
    return float(np.abs(np.diff(video, axis=0)).mean(axis=(1, 2, 3)).max()
                 / np.abs(np.diff(clip, axis=0)).mean(axis=(1, 2, 3)).max())


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    args = parser.parse_args()
    graphcut_video(data.clip("waves", 8, 32), 12, rng=0)  # warm-up: imports
    print(f"{'clip':6} {'graphcut_video':>15} {'target':>7} {'naive':>9} {'seam cost (cut / straight)':>28} "
          f"{'largest step (gc / naive)':>26}")
    for name in ("flame", "waves", "rain"):
        clip = data.clip(name, 32, 128, rng=0)
        times = []
        for _ in range(args.repeat):
            t = time.perf_counter()
            graphcut_video(clip, 64, rng=0)
            times.append(time.perf_counter() - t)
        t = time.perf_counter()
        naive = np.concatenate([clip, clip])
        naive_seconds = time.perf_counter() - t
        out, info = graphcut_video(clip, 64, rng=0, return_info=True)
        best = min(times)
        cut, straight = info.seam_costs.sum(), info.baseline_costs.sum()
        print(f"{name:6} {best:14.1f}s {'ok' if best <= TARGET else 'MISS':>7} {naive_seconds * 1e3:7.1f}ms "
              f"{cut:12.0f} / {straight:6.0f} ({100 * (1 - cut / straight):3.0f} % lower) "
              f"{largest_step(out, clip):14.2f} / {largest_step(naive, clip):4.2f}")
        print(f"       {len(info.corners)} blocks {info.block}, overlap {info.overlap}; cuts {info.cut_seconds:.1f} s "
              f"of {info.seconds:.1f} s with info (straight cuts priced in {info.baseline_seconds:.1f} s)")


if __name__ == "__main__":
    main()
