"""The front door's cost: the analysis of a 512 px exemplar, and texsynth.synthesize against the method it
chose, called directly, in one run (issue 38's targets: at most 0.5 s of analysis for 512², and the
256² -> 1024² output within 1.2x the time of the chosen method).

    python benchmarks/bench_synthesize.py [--photos bricks_1 wood_1 moss_1] [--size 1024]
"""

import argparse
import time
from pathlib import Path

import texsynth
from texsynth._synthesize import METHODS
from texsynth.io import load_image

PHOTOS = Path(__file__).resolve().parent / "photos"


def _crop(image, side):
    h, w = image.shape[:2]
    side = min(side, h, w)
    top, left = (h - side) // 2, (w - side) // 2
    return image[top:top + side, left:left + side, :3] if image.ndim == 3 else image[top:top + side, left:left + side]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--photos", nargs="+", default=["bricks_1", "wood_1", "moss_1", "tiles_1"])
    parser.add_argument("--size", type=int, default=1024, help="output side for 256 px crops (default 1024)")
    args = parser.parse_args()
    warm = _crop(load_image(PHOTOS / f"{args.photos[0]}.png"), 64)
    for method in METHODS:  # imports and first-call costs out of the way
        try:
            getattr(texsynth, method)(warm, 64, rng=0)
        except ValueError:  # near-regular synthesis finds no grid in a small crop
            pass
    texsynth.synthesize(warm, 64, rng=0)
    print("| photo | kind | analysis of 512 px (s) | method | synthesize 256 -> size (s) | method directly (s) | ratio |")
    print("|---|---|---|---|---|---|---|")
    for name in args.photos:
        photo = load_image(PHOTOS / f"{name}.png")
        big = _crop(photo, 512)
        start = time.perf_counter()
        texsynth.analyze_exemplar(big)
        analysis = time.perf_counter() - start
        exemplar = _crop(photo, 256)
        method, options, _ = texsynth.choose_method(texsynth.analyze_exemplar(exemplar))
        start = time.perf_counter()
        getattr(texsynth, method)(exemplar, (args.size, args.size), rng=0, **options)
        direct = time.perf_counter() - start
        start = time.perf_counter()
        texsynth.synthesize(exemplar, args.size, rng=0)  # as the method is called: without its info
        front = time.perf_counter() - start
        kind = texsynth.analyze_exemplar(exemplar).kind
        print(f"| {name} | {kind} | {analysis:.3f} | {method} | {front:.2f} | {direct:.2f} | "
              f"{front / direct:.2f} |", flush=True)


if __name__ == "__main__":
    main()
