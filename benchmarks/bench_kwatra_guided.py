"""Guided texture optimization: time of a 256x256 -> 512x512 colour synthesis against the unguided one.

Run: python benchmarks/bench_kwatra_guided.py [--seeds 0 1]

Target (issue 19): the guided ``optimize_texture`` takes at most 2x the unguided time. Exemplar:
grass | pebbles (the left 128 columns of ``grass_1`` and of ``pebbles_1`` in ``benchmarks/photos``,
256 rows) with its label map (0 grass, 1 pebbles); output guide: a disc of 1 (radius 150 px) in a
field of 0. Both runs use the defaults and the same seed, in one process after a warm-up; the
reference is the unguided run of the same exemplar. Quality: how much nearer each output region's
mean colour is to the pebbles' than to the grass's (RGB distance; + pebbles, - grass).
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from texsynth import optimize_texture
from texsynth.optimization import Guides
from texsynth.io import load_image

HERE = Path(__file__).resolve().parent
SIZE = 512


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0])
    args = parser.parse_args()
    grass = load_image(HERE / "photos" / "grass_1.png")[:256, :128, :3]
    pebbles = load_image(HERE / "photos" / "pebbles_1.png")[:256, :128, :3]
    ex = np.concatenate([grass, pebbles], axis=1)
    labels = np.zeros(ex.shape[:2])
    labels[:, 128:] = 1
    yy, xx = np.mgrid[:SIZE, :SIZE]
    disc = ((yy - (SIZE - 1) / 2) ** 2 + (xx - (SIZE - 1) / 2) ** 2 <= 150**2).astype(float)
    optimize_texture(ex[:64, :64], 96, rng=0)  # warm-up: imports, thread pools
    mg, mp = grass.reshape(-1, 3).mean(0), pebbles.reshape(-1, 3).mean(0)
    print(f"# {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"pure texture scores: +-{np.linalg.norm(mg - mp):.3f}")
    print("| seed | run | seconds | disc | outside |")
    print("|---|---|---|---|---|")
    for seed in args.seeds:
        times = {}
        for name, guides in (("unguided", Guides()), ("guided", Guides(exemplar_guide=labels, output_guide=disc))):
            t = time.perf_counter()
            out = optimize_texture(ex, SIZE, rng=seed, guides=guides)
            times[name] = time.perf_counter() - t
            scores = [np.linalg.norm(out[m].mean(0) - mg) - np.linalg.norm(out[m].mean(0) - mp)
                      for m in (disc > 0, disc == 0)]
            print(f"| {seed} | {name} | {times[name]:.2f} | {scores[0]:+.3f} | {scores[1]:+.3f} |", flush=True)
        print(f"| {seed} | guided / unguided | {times['guided'] / times['unguided']:.2f}x | | |")


if __name__ == "__main__":
    main()
