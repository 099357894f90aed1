"""Orientation and scale fields (issue 18): controlled vs uncontrolled time, 128^2 -> 256^2.

Run: python benchmarks/bench_kwatra_fields.py [--repeats 2] [--texture PATH] [--figure]

Target: synthesis with an orientation field (a vortex around the centre) and a scale field (0.7 at
the left edge to 1.6 at the right) takes at most 3x the time of the same call without fields, for
texture optimization (optimize_texture, preset "default") and for Zhang et al.'s controlled pixel
synthesis (synthesize_controlled). Times are the best of --repeats runs with the same seed; the
exemplar is the top-left 256x256 of benchmarks/photos/bricks_1.png resized to 128x128. Also writes
the outputs as PNGs under benchmarks/output/fields/ to look at. --figure also writes
docs/_static/optimization_fields.png: for bricks_1 and pebbles_1 (top-left 256^2 resized to 128^2),
the exemplar and optimize_texture's outputs without fields, with the vortex, with the scale
gradient and with both (seed 0).
"""

import argparse
import time
from pathlib import Path

import numpy as np

from texsynth import optimize_texture, synthesize_controlled
from texsynth.optimization import Fields
from texsynth.io import load_image, save_image

PHOTOS = Path(__file__).resolve().parent / "photos"
TEXTURE = PHOTOS / "bricks_1.png"
FIGURE = Path(__file__).resolve().parent.parent / "docs" / "_static" / "optimization_fields.png"
OUT = Path(__file__).resolve().parent / "output" / "fields"
N = 256


def vortex(rows, cols):
    """Elements turned along circles around the centre: theta is the tangent's angle, counter-clockwise as
    shown (rows run down, hence the minus)."""
    return np.pi / 2 - np.arctan2(rows - N / 2, cols - N / 2)


def grow(rows, cols):
    """Scale 0.7 at the left edge to 1.6 at the right."""
    return 0.7 + 0.9 * cols / (N - 1)


def best_of(repeats, func):
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = func()
        times.append(time.perf_counter() - start)
    return min(times), out


def exemplar(path):
    """The top-left 256x256 of a photo, resized to 128x128, colour channels only."""
    from skimage.transform import resize

    image = load_image(path)
    image = image[..., :3] if image.ndim == 3 else image
    return resize(image[:256, :256], (128, 128), anti_aliasing=True).astype(np.float32)


def figure():
    """Rows of exemplar, no fields, vortex, magnification gradient, both (optimize_texture, seed 0)."""
    gap = 4
    rows = []
    for name in ("bricks_1", "pebbles_1"):
        ex = exemplar(PHOTOS / f"{name}.png")
        column = np.ones((N, 128, 3), np.float32)
        column[:128] = ex
        panels = [column] + [optimize_texture(ex, N, rng=0, fields=Fields(**kw)) for kw in (
            {}, {"orientation": vortex}, {"magnification": grow}, {"orientation": vortex, "magnification": grow})]
        row = panels[0]
        for panel in panels[1:]:
            row = np.concatenate([row, np.ones((N, gap, 3), np.float32), panel], 1)
        rows += [row, np.ones((gap, row.shape[1], 3), np.float32)]
    save_image(FIGURE, np.concatenate(rows[:-1], 0), overwrite=True)
    print(f"wrote {FIGURE}")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=2)
    parser.add_argument("--texture", default=TEXTURE)
    parser.add_argument("--figure", action="store_true")
    args = parser.parse_args()
    ex = exemplar(args.texture)
    OUT.mkdir(parents=True, exist_ok=True)
    methods = {
        "optimize_texture": lambda **kw: optimize_texture(ex, N, rng=0, fields=Fields(**kw)),
        "synthesize_controlled": lambda **kw: synthesize_controlled(ex, N, rng=0, **kw),
    }
    print(f"{'method':24s} {'plain s':>8s} {'fields s':>9s} {'ratio':>6s}")
    for name, run in methods.items():
        plain, a = best_of(args.repeats, run)
        fields, b = best_of(args.repeats, lambda: run(orientation=vortex, magnification=grow))
        save_image(OUT / f"{name}_plain.png", a, overwrite=True)
        save_image(OUT / f"{name}_vortex_grow.png", b, overwrite=True)
        print(f"{name:24s} {plain:8.2f} {fields:9.2f} {fields / plain:6.2f}")
    if args.figure:
        figure()


if __name__ == "__main__":
    main()
