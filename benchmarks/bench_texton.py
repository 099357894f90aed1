"""Zhang et al.'s controlled synthesis against uncontrolled k-coherent Wei-Levoy synthesis, in one run.

Run: python benchmarks/bench_texton.py [--repeat 3]   (from the repository root)

Target (issue 18): ``synthesize_controlled`` with orientation and scale fields, 128^2 -> 256^2
colour, at most 3x the time of the uncontrolled synthesis.

Side by side, in the same run, on the top-left 128x128 of the colour photographs
``benchmarks/photos/bricks_1`` (a red brick wall) and ``cobblestones_1``, seed 0, 3 levels, causal
5x5 neighbourhoods, k = 1 (the defaults of both): the reference
``synthesize_pixels(candidates="k-coherent")``, then ``synthesize_controlled`` without a texton
mask and fields, with the automatic texton mask, with a vortex orientation field and a
small-to-large scale gradient (0.6 -> 2.2 from left to right), and a progressive variation from
one photograph to the other along a left-to-right blend ramp. Each line: the best wall time of
``--repeat`` rounds (the runs interleaved) and its ratio to the reference.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from texsynth import synthesize_controlled, synthesize_pixels
from texsynth.core.search import Search
from texsynth.io import load_image

HERE = Path(__file__).resolve().parent
PHOTOS = ("bricks_1", "cobblestones_1")
SIZE = 256


def vortex(rows, cols):
    return np.arctan2(rows - SIZE / 2, cols - SIZE / 2) + np.pi / 2


def gradient(rows, cols):
    return 0.6 + 1.6 * cols / SIZE


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    print(f"# {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"# best of {args.repeat}, 128^2 -> {SIZE}^2, seed 0")
    print("| photo | run | seconds | / reference |")
    print("|---|---|---|---|")
    exemplars = {p: np.ascontiguousarray(load_image(HERE / "photos" / f"{p}.png")[:128, :128, :3]) for p in PHOTOS}
    for photo, exemplar in exemplars.items():
        other = exemplars[PHOTOS[1] if photo == PHOTOS[0] else PHOTOS[0]]
        runs = [
            ("synthesize_pixels(candidates='k-coherent') [reference]",
             lambda: synthesize_pixels(exemplar, SIZE, search=Search(candidates="k-coherent"), rng=0)),
            ("controlled, no mask, no fields", lambda: synthesize_controlled(exemplar, SIZE, texton_mask=None, rng=0)),
            ("controlled, texton mask", lambda: synthesize_controlled(exemplar, SIZE, rng=0)),
            ("controlled, texton mask + vortex orientation + scale gradient",
             lambda: synthesize_controlled(exemplar, SIZE, orientation=vortex, magnification=gradient, rng=0)),
            ("controlled, progressive variation to the other photo (blend ramp)",
             lambda: synthesize_controlled(exemplar, SIZE, exemplar_b=other, blend=lambda r, c: c / SIZE, rng=0)),
        ]
        best = [np.inf] * len(runs)
        for _ in range(args.repeat):  # interleaved, so a burst of load on the machine hits every run alike
            for i, (_, fn) in enumerate(runs):
                start = time.perf_counter()
                fn()
                best[i] = min(best[i], time.perf_counter() - start)
        for (label, _), seconds in zip(runs, best):
            print(f"| {photo} | {label} | {seconds:.2f} | {seconds / best[0]:.2f}x |", flush=True)


if __name__ == "__main__":
    main()
