"""Near-regular texture synthesis on the lattice beside the general patch methods, on photographs of grids.

Run: nice -n 10 python benchmarks/bench_near_regular.py [--photos tiles_1 bricks_1] [--size 1024] [--figure]
(from the repository root; graph cuts take about 70 s at 1024 px)

Issue 38: on a photograph of square stone tiles in a grid (benchmarks/photos/tiles_1.png, its centred 256 px
crop: 2 x 2 tiles) every method broke the grid at 4x. One run, the same exemplar and size for each method,
seed 0, each method's defaults:

- ``near_regular_texture`` (texsynth.patch._near_regular), ``quilt``, ``patch_sampling``, ``graphcut_texture``;
- seconds (one call each, wall time), and the structure metrics of texsynth.metrics: ``lattice_kept`` (the
  exemplar's period vectors kept; 1.0 when texsynth.metrics.lattice finds none in the exemplar, as on the
  tiles_1 crop, whose four tiles differ too much for its autocorrelation), ``induced_lattice`` (a repetition
  the exemplar lacks; above 0.3 visible) and ``element_integrity`` (texton-mask components whole);
- ``grid``: this benchmark's own check of the grid, the one the photograph needs: per axis (rows / columns),
  the near-regular method's line detector run on the output's profile, and the share of the lines it predicts
  that are there; "-" when it finds no lines of the exemplar's polarity at the exemplar's period within 5 %
  (at least 75 % of the predicted lines are needed to find a period at all).

``--figure`` writes docs/_static/near_regular_tiles.png (at most 250 KB): tiles_1's exemplar at the outputs'
scale and the whole outputs of near_regular_texture, quilt and graph cuts, reduced; below, bricks_1's exemplar
and the outputs' top-left corners at full resolution.
"""

import argparse
import platform
import time
from datetime import date
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PHOTOS = ROOT / "benchmarks" / "photos"
FIGURE = ROOT / "docs" / "_static" / "near_regular_tiles.png"


def crop(name, side=256):
    from texsynth.io import load_image

    image = load_image(PHOTOS / f"{name}.png")[..., :3]
    top, left = (image.shape[0] - side) // 2, (image.shape[1] - side) // 2
    return np.ascontiguousarray(image[top:top + side, left:left + side])


def methods():
    import texsynth

    return {
        "near_regular_texture": lambda ex, size: texsynth.near_regular_texture(ex, size, rng=0),
        "quilt": lambda ex, size: texsynth.quilt(ex, size, rng=0),
        "patch_sampling": lambda ex, size: texsynth.patch_sampling(ex, size, rng=0),
        "graphcut_texture": lambda ex, size: texsynth.graphcut_texture(ex, size, rng=0),
    }


def grid_kept(out, lattice, found_by):
    """Per axis (rows, columns): the share of the lines the exemplar's lattice predicts that the output shows,
    found by the near-regular method's own line detector (lines of the exemplar's polarity at its period within
    5 %), or None where it finds none."""
    from texsynth.patch._near_regular import axis_lattice, luminance

    grey = luminance(out)
    sign = 1 if found_by == "dark lines" else -1
    shares = []
    for axis, period in ((1, lattice[0]), (0, lattice[1])):
        found = axis_lattice(grey.mean(axis=axis), sign, 3)
        shares.append(found[2] if found is not None and abs(found[0] - period) <= 0.05 * period else None)
    return shares


def run(photos, size, figure):
    import texsynth
    from texsynth.metrics import element_integrity, induced_lattice, lattice, lattice_kept

    print(f"# {platform.node()} ({platform.machine()}), {date.today()}, "
          f"`nice -n 10 python benchmarks/bench_near_regular.py --size {size}`")
    outputs = {}
    for name in photos:
        ex = crop(name)
        try:
            _, info = texsynth.near_regular_texture(ex, 64, rng=0, return_info=True)
            found = f"lattice {tuple(round(v, 1) for v in info.lattice)} ({info.found_by}), augment {info.augment}"
        except ValueError as error:
            print(f"\n## {name} 256 -> {size}: {error}")
            continue
        vectors = lattice(ex).vectors.tolist()
        print(f"\n## {name} 256 -> {size}: {found}; texsynth.metrics.lattice: {vectors or 'none'}\n")
        print("| method | seconds | lattice_kept | induced_lattice | element_integrity | grid (rows / cols) |")
        print("|---|---|---|---|---|---|")
        for method, call in methods().items():
            start = time.perf_counter()
            out = call(ex, size)
            seconds = time.perf_counter() - start
            grid = " / ".join("-" if k is None else f"{k:.2f}" for k in grid_kept(out, info.lattice, info.found_by))
            print(f"| {method} | {seconds:.1f} | {lattice_kept(out, ex):.2f} | {induced_lattice(out, ex):.2f} | "
                  f"{element_integrity(out, ex):.2f} | {grid} |", flush=True)
            outputs[name, method] = out
        outputs[name, "exemplar"] = ex
    if figure and ("tiles_1", "graphcut_texture") in outputs:
        save_figure(outputs)


def save_figure(outputs, limit=250 * 1024):
    """tiles_1 (top): the exemplar at the outputs' scale, then near_regular_texture, quilt and graph cuts, whole
    and reduced; bricks_1 (below, if its lattice was found): the exemplar and the three outputs' top-left
    corners at full resolution, half as tall. The largest panels that keep the file (a 256-colour PNG) under
    ``limit`` bytes."""
    import io

    from PIL import Image
    from skimage.transform import resize

    methods = ("near_regular_texture", "quilt", "graphcut_texture")
    size = outputs["tiles_1", "quilt"].shape[0]

    def row(panels, height):
        padded = [np.pad(p, ((0, height - p.shape[0]), (0, 0), (0, 0)), constant_values=1.0) for p in panels]
        return np.concatenate([q for p in padded for q in (p, np.ones((height, 6, 3)))][:-1], axis=1)

    for side in (384, 352, 320, 288, 256, 224, 192):
        ex = resize(outputs["tiles_1", "exemplar"], (side * 256 // size,) * 2, anti_aliasing=True)
        rows = [row([ex] + [resize(outputs["tiles_1", m], (side, side), anti_aliasing=True) for m in methods], side)]
        if ("bricks_1", "graphcut_texture") in outputs:
            strip = side // 2
            bricks = outputs["bricks_1", "exemplar"][:strip, :strip]
            rows.append(row([bricks] + [outputs["bricks_1", m][:strip, :side] for m in methods], strip))
        width = max(r.shape[1] for r in rows)
        rows = [np.pad(r, ((0, 0), (0, width - r.shape[1]), (0, 0)), constant_values=1.0) for r in rows]
        sheet = np.concatenate([q for r in rows for q in (r, np.ones((6, width, 3)))][:-1], axis=0)
        image = Image.fromarray((np.clip(sheet, 0, 1) * 255).round().astype(np.uint8)).quantize(256)
        buffer = io.BytesIO()
        image.save(buffer, format="PNG", optimize=True)
        if buffer.tell() <= limit:
            break
    FIGURE.write_bytes(buffer.getvalue())
    print(f"\nwrote {FIGURE.relative_to(ROOT)}: tiles_1 outputs reduced to {side} px, bricks_1 corners of "
          f"{side // 2} px at full resolution; {len(buffer.getvalue()) // 1024} KB")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--photos", nargs="+", default=["tiles_1", "bricks_1", "tiles_2"])
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--figure", action="store_true")
    args = parser.parse_args()
    run(args.photos, args.size, args.figure)
