"""Make a photo tileable: texsynth.make_tileable on crops of benchmarks/photos, seam before and after.

Run: python benchmarks/bench_completion_tileable.py [--size 160] [--figure]   (from the repository root)

On the top-left ``size`` x ``size`` crop of each photograph, seed 0, band "auto" (an eighth of
the side): wall time, and the seam visibility of the image tiled 2x2 before and after: the
mean absolute difference across the tile seams (last row against first, last column against
first) over the same measure between neighbouring rows and columns inside the image (about 1:
no visible seam; a plain crop measures 1.6-7).

``--figure`` writes ``docs/_static/make_tileable.png``: per photograph the crop tiled 2x2 and
the result tiled 2x2, side by side.
"""

import argparse
import time
from pathlib import Path

import numpy as np

import texsynth
from texsynth.io import load_image, save_image

HERE = Path(__file__).resolve().parent
PHOTOS = ("bricks_1", "grass_1", "pebbles_1")


def seam_ratio(image):
    """Mean |difference| across the wrap-around seams over the mean |difference| inside the image."""
    t = np.tile(image, (2, 2, 1) if image.ndim == 3 else (2, 2))
    h, w = image.shape[:2]
    rows = np.abs(np.diff(t, axis=0)).mean(axis=tuple(range(1, t.ndim)))
    cols = np.abs(np.diff(t, axis=1)).mean(axis=tuple([0] + list(range(2, t.ndim))))
    seam = (rows[h - 1] + cols[w - 1]) / 2
    inside = (np.delete(rows, h - 1).mean() + np.delete(cols, w - 1).mean()) / 2
    return seam / inside


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=160)
    parser.add_argument("--figure", action="store_true")
    args = parser.parse_args()
    rows = []
    for name in PHOTOS:
        image = load_image(HERE / "photos" / f"{name}.png")[: args.size, : args.size]
        start = time.perf_counter()
        out = texsynth.make_tileable(image, rng=0)
        seconds = time.perf_counter() - start
        print(f"{name:10s} {args.size} px  {seconds:5.1f} s  seam before {seam_ratio(image):.2f}  "
              f"after {seam_ratio(out):.2f}")
        white = np.ones((2 * args.size, 8, 3))
        rows.append(np.concatenate([np.tile(image, (2, 2, 1)), white, np.tile(out, (2, 2, 1))], 1))
    if args.figure:
        gap = np.ones((8,) + rows[0].shape[1:])
        parts = [rows[0]]
        for row in rows[1:]:
            parts += [gap, row]
        save_image(HERE.parent / "docs" / "_static" / "make_tileable.png", np.concatenate(parts, 0), overwrite=True)


if __name__ == "__main__":
    main()
