"""The video methods on clips they were not developed on: the reporting half of the clips (issue 35's split).

The methods were developed and their defaults chosen on ``texsynth.data.clip("flame")`` and ``clip("waves")``
(the tuning half). This script reports them, at their defaults, on the other half: the simulated raindrops
(``clip("rain")``, 64 frames of 128²) and the one real clip (``benchmarks/clips/tree_foliage.npz``, 59
frames of 128², OpenCV's ``tree.avi``), each against a baseline computed in the same run:

- ``dynamic_texture``: the lag-1 temporal correlation of 256 synthesised frames (after 32 frames) against
  the clip's, and the clip's frames in random order (the baseline);
- ``video_texture``: a seamless loop of 48 frames: its worst jump over the clip's median step between
  consecutive frames, against a random jump's;
- ``graphcut_video``: the clip's first 32 frames extended to 64: the seams' cost against straight cuts of
  the same overlaps;
- ``stylize_video``: 12 frames (96², the first frame painted): flicker along the motion, against each frame
  painted on its own.

    python benchmarks/eval_video.py
"""

import time
from pathlib import Path

import numpy as np
from figure_jamriska import paint

import texsynth
from texsynth.metrics import flicker, temporal_correlation

CLIPS = Path(__file__).resolve().parent / "clips"


def reporting_clips():
    clips = {"rain (simulated)": texsynth.data.clip("rain", 64, 128, rng=1)}
    real = CLIPS / "tree_foliage.npz"
    if real.exists():
        clips["tree_foliage (real)"] = np.load(real)["frames"] / 255.0
    return clips


def main():
    rng = np.random.default_rng(0)
    print("| clip | method | result | baseline (same run) | seconds |")
    print("|---|---|---|---|---|")
    for name, clip in reporting_clips().items():
        start = time.perf_counter()
        video = texsynth.dynamic_texture(clip, 256, rng=0)
        seconds = time.perf_counter() - start
        shuffled = clip[rng.permutation(len(clip))]
        print(f"| {name} | dynamic_texture | lag-1 correlation {temporal_correlation(video[32:]):.3f} (clip "
              f"{temporal_correlation(clip):.3f}) | frames shuffled {temporal_correlation(shuffled):.3f} | "
              f"{seconds:.2f} |", flush=True)

        start = time.perf_counter()
        try:
            loop, info = texsynth.video_texture(clip, 48, loop=True, rng=0, return_info=True)
        except ValueError as error:  # the clip's good transitions cannot make this length
            print(f"| {name} | video_texture | no loop of 48 frames: {str(error)[:120]} | – | – |", flush=True)
        else:
            seconds = time.perf_counter() - start
            D, seq, T = info.distances, info.sequence, len(clip)
            steps = D[np.arange(T - 1), np.arange(1, T)]
            jumps = D[np.minimum(seq[info.jumps] + 1, T - 1), seq[(info.jumps + 1) % len(seq)]]
            random_jump = np.median(D[np.triu_indices(T, 2)])
            print(f"| {name} | video_texture | a 48-frame loop, worst jump {jumps.max() / np.median(steps):.2f}x the "
                  f"median step ({len(info.loops)} primitive loops) | a random jump {random_jump / np.median(steps):.2f}x "
                  f"| {seconds:.2f} |", flush=True)

        start = time.perf_counter()
        _, info = texsynth.graphcut_video(clip[:32], 64, rng=0, return_info=True)
        seconds = time.perf_counter() - start
        print(f"| {name} | graphcut_video | 32 -> 64 frames, seams cost {info.seam_cost:.0f} | straight cuts "
              f"{float(np.sum(info.baseline_costs)):.0f} | {seconds:.1f} |", flush=True)

        frames = clip[:12, :96, :96]
        start = time.perf_counter()
        styled, info = texsynth.stylize_video(frames, {0: paint(frames[0])}, rng=0, return_info=True)
        seconds = time.perf_counter() - start
        alone = texsynth.stylize_video(frames, {0: paint(frames[0])}, temporal_weight=0.0, flows=info.flows, rng=0)
        print(f"| {name} | stylize_video | flicker {flicker(styled, info.flows):.4f} (the clip itself "
              f"{flicker(frames, info.flows):.4f}) | each frame on its own {flicker(alone, info.flows):.4f} | "
              f"{seconds:.1f} |", flush=True)


if __name__ == "__main__":
    main()
