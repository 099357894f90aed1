"""Speed of keyframe-guided stylisation (texsynth.stylize_video), beside the per-frame reference.

Target: 30 frames of 256x256 from 2 keyframes (frames 0 and 29) in at most 3 minutes. The reference,
in the same run, stylises every frame on its own (``temporal_weight=0``: no temporal guide, no warm
start from the previous frame, two pyramid levels), on the same flows. Both print wall time, CPU time,
flicker along the motion and the texture energy against keyframe 0.

    python benchmarks/bench_jamriska.py [--frames 30] [--size 256] [--clip waves]
"""

from __future__ import annotations

import argparse
import platform
import resource
import time

import numpy as np

import texsynth
from texsynth.core.flows import estimate_flows
from texsynth.video import stylize_video

from figure_jamriska import paint
from texsynth.metrics import flicker


def run(label, call):
    t0, c0 = time.perf_counter(), time.process_time()
    out = call()
    return label, out, time.perf_counter() - t0, time.process_time() - c0


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=30)
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--clip", default="waves")
    parser.add_argument("--no-reference", action="store_true")
    args = parser.parse_args(argv)
    frames = texsynth.data.clip(args.clip, args.frames, args.size, rng=0)
    last = args.frames - 1
    keys = {0: paint(frames[0]), last: paint(frames[last])}
    print(f"{platform.node()} {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load "
          f"{open('/proc/loadavg').read().split()[0]}; {args.clip} {args.frames} x {args.size}^2, keyframes 0, {last}")
    t0 = time.perf_counter()
    flows = estimate_flows(frames)
    t_flow = time.perf_counter() - t0
    rows = []
    print(f"optical flow (TV-L1) alone: {t_flow:.1f} s for {args.frames - 1} pairs", flush=True)
    rows.append(run("temporal guide (default), flows estimated inside",
                lambda: stylize_video(frames, keys, rng=0, return_info=True)))
    print(f"{rows[-1][0]}: {rows[-1][2]:.1f} s", flush=True)
    if not args.no_reference:
        rows.append(run("each frame on its own (temporal_weight=0)",
                        lambda: (stylize_video(frames, keys, temporal_weight=0.0, flows=flows, rng=0), None)))
        print(f"{rows[-1][0]}: {rows[-1][2]:.1f} s", flush=True)
    print("| run | wall | CPU | syntheses | per synthesis | flicker | texture energy vs key 0 (frames 1-5, kd-tree) "
          "| target |")
    print("|---|---|---|---|---|---|---|---|")
    for label, (video, info), wall, cpu in rows:
        n = info.syntheses if info is not None else 2 * (args.frames - 2)
        synth = wall - (info.stage_seconds["flows"] if info is not None else 0.0)
        energy = np.mean([texsynth.metrics.texture_energy(f, keys[0], method="kdtree", rng=0) for f in video[1:6]])
        verdict = "met" if wall <= 180 else "missed"
        print(f"| {label} | {wall:.1f} s | {cpu:.1f} s | {n} | {synth / n:.2f} s | {flicker(video, flows):.4f} | "
              f"{energy:.5f} | {verdict if 'default' in label else '-'} |")
    print(f"the clip itself: flicker {flicker(frames, flows):.4f}; max RSS "
          f"{resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB")


if __name__ == "__main__":
    main()
