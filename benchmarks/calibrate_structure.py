"""Calibration of texsynth.metrics' structure metrics: the tables and thresholds of docs/metrics.md ("Structure").

For each photograph the exemplar is a 128 px crop (96 x 128 for the wood, which is 96 px high) of the
photograph reduced ``level`` times by the Gaussian pyramid (so that a few elements or periods fit in it). At
twice its size we score

- the baselines: the tiled exemplar (``tiled``), a random-block mosaic (``mosaic``), histogram-matched noise
  (``noise``), and a mosaic turned by 45 degrees (``rotated``: the right elements at a wrong orientation);
- syntheses at their defaults: ``quilt``, ``graphcut`` (``graphcut_texture``), ``optimize``
  (``optimize_texture``);

over seeds 0-2 (the synthesis', the mosaic's and the noise's) with each structure metric; a cell is
``min-max`` over the seeds. Three sets of photographs:

- tuning (the developers' texture photographs): chose the metrics' options and thresholds;
- held-out (``benchmarks/photos``): scored once with the first version; that run showed two faults
  (orientations weighted by gradient energy let a tiling seam outweigh wood grain, now weighted by
  coherence; an exemplar correlated across its whole extent had no reference for ``induced_lattice``, now
  its correlation at its largest offsets). Both were fixed and the thresholds derived again from the tuning
  set's baselines alone, so this set is no clean test any more;
- fresh (eight other photos of ``benchmarks/photos``): scored once, with the final metrics and thresholds.

Below each table: the lattices found in the exemplars, then for each metric its threshold, the worst baseline
on each side of it (the margins, threshold minus worst on the passing side and worst minus threshold on the
failing side; negative: a baseline on the wrong side) and the syntheses it flags.

    python benchmarks/calibrate_structure.py                                 # all sets: about 10 min on 2 cores
    python benchmarks/calibrate_structure.py --set fresh --cache /tmp/structure   # keep the syntheses on disk
"""

import argparse
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

import texsynth
from texsynth import metrics
from texsynth.core.pyramid import downsample
from texsynth.io import load_image

ROOT = Path(__file__).resolve().parent
TEXTURES = ROOT.parents[1] / "shared" / "textures"
# (file, kind, pyramid reductions before the 128 px crop)
TUNING = [
    (TEXTURES / "jcjohnson/wood.png", "directional", 0),
    (TEXTURES / "skimage/brick.png", "directional", 1),
    (TEXTURES / "rohitrango/t2.png", "woven", 0),
    (TEXTURES / "rohitrango/t8.png", "regular", 0),
    (TEXTURES / "rohitrango/t9.png", "regular", 0),
    (TEXTURES / "rohitrango/t1.png", "regular", 0),
    (TEXTURES / "lcv/nuts.pgm", "elements", 0),
    (TEXTURES / "rohitrango/t19.png", "elements", 0),
    (TEXTURES / "skimage/gravel.png", "stochastic", 1),
]
HELD_OUT = [
    (ROOT / "photos/bark_1.png", "directional", 0),
    (ROOT / "photos/bricks_1.png", "regular", 1),
    (ROOT / "photos/tiles_1.png", "regular", 2),
    (ROOT / "photos/tiles_2.png", "regular", 2),
    (ROOT / "photos/moss_1.png", "elements", 0),
    (ROOT / "photos/cobblestones_1.png", "elements", 1),
    (ROOT / "photos/wood_1.png", "directional", 1),
    (ROOT / "photos/sand_1.png", "stochastic", 0),
]
FRESH = [
    (ROOT / "photos/bark_2.png", "directional", 0),
    (ROOT / "photos/wood_2.png", "directional", 1),
    (ROOT / "photos/roof_1.png", "regular", 1),
    (ROOT / "photos/fabric_1.png", "regular", 1),
    (ROOT / "photos/stonewall_1.png", "elements", 1),
    (ROOT / "photos/pebbles_1.png", "elements", 1),
    (ROOT / "photos/cracked_1.png", "elements", 1),
    (ROOT / "photos/grass_1.png", "stochastic", 0),
]
EXEMPLAR = 128
METHODS = {"quilt": texsynth.quilt, "graphcut": texsynth.graphcut_texture, "optimize": texsynth.optimize_texture}
ROWS = ["tiled", "mosaic", "noise", "rotated", *METHODS]
COLUMNS = {
    "orient": lambda out, ex: metrics.orientation_distance(out, ex),
    "induced": lambda out, ex: metrics.induced_lattice(out, ex),
    "kept": lambda out, ex: metrics.lattice_kept(out, ex),
    "elements": lambda out, ex: metrics.element_integrity(out, ex),
}


def exemplar(path, level):
    image = load_image(path)
    image = image[..., :3] if image.ndim == 3 and image.shape[-1] == 4 else image
    for _ in range(level):
        image = downsample(image)
    return np.ascontiguousarray(image[:EXEMPLAR, :EXEMPLAR])


def rotated(ex, size, seed):
    """A mosaic twice the output's size turned by 45 degrees, its centre cropped: the exemplar's elements at
    another orientation."""
    big = metrics.mosaic_baseline(ex, 2 * max(size), rng=seed)
    turned = ndimage.rotate(big, 45, axes=(0, 1), reshape=False, order=1, mode="reflect")
    top, left = (big.shape[0] - size[0]) // 2, (big.shape[1] - size[1]) // 2
    return np.clip(turned[top:top + size[0], left:left + size[1]], 0.0, 1.0)


def image_for(row, ex, seed, cache, key):
    size = (2 * ex.shape[0], 2 * ex.shape[1])
    if row == "tiled":
        return metrics.tiled_baseline(ex, size)
    if row == "mosaic":
        return metrics.mosaic_baseline(ex, size, rng=seed)
    if row == "noise":
        return metrics.noise_baseline(ex, size, rng=seed)
    if row == "rotated":
        return rotated(ex, size, seed)
    path = None if cache is None else cache / f"{key}-{row}-{seed}.npy"
    if path is not None and path.exists():
        return np.load(path)
    out = METHODS[row](ex, size, rng=seed)
    if path is not None:
        np.save(path, out)
    return out


def score(photos, seeds, cache):
    """``{(name, row): {column: [value per seed]}}``, printing a Markdown table as it goes."""
    print("| photo | kind | image | " + " | ".join(COLUMNS) + " |")
    print("|---|---|---|" + "---|" * len(COLUMNS))
    found = {}
    for path, kind, level in photos:
        ex = exemplar(path, level)
        name = path.stem if path.parent.name == "photos" else f"{path.parent.name}/{path.stem}"
        key = name.replace("/", "_")
        found[name, "lattice"] = metrics.lattice(ex)
        for row in ROWS:
            values = {c: [] for c in COLUMNS}
            for seed in seeds:
                out = image_for(row, ex, seed, cache, key)
                for column, metric in COLUMNS.items():
                    values[column].append(metric(out, ex))
            found[name, row] = values
            cells = [f"{min(v):.2f}-{max(v):.2f}" if len(v) > 1 else f"{v[0]:.2f}" for v in values.values()]
            print(f"| {name} | {kind} | {row} | " + " | ".join(cells) + " |", flush=True)
        found[name, "kind"] = kind
    return found


def lattices(found):
    print("\n| photo | lattice vectors (row, col) px | strengths | strongest peak beyond the lobe |")
    print("|---|---|---|---|")
    for (name, row), value in found.items():
        if row == "lattice":
            print(f"| {name} | {value.vectors.tolist()} | {np.round(value.strengths, 2).tolist()} | "
                  f"{value.peak:.2f} at {value.peak_offset} |")


def summary(found):
    """Per metric, the threshold, the worst baseline on each side of it (the margins the comments at the
    thresholds in texsynth/metrics/_structure.py state) and the syntheses it flags."""
    names = [name for name, row in found if row == "kind"]
    regular = [n for n in names if len(found[n, "lattice"].vectors)]
    directional = [n for n in names if found[n, "kind"] == "directional"]
    elements = [n for n in names if found[n, "kind"] in ("regular", "elements")]

    def values(rows, column, among):
        return [v for n in among for r in rows for v in found[n, r][column]]

    checks = [  # metric, threshold, the side that passes, (baselines, photos) passing, (baselines, photos) failing
        ("orient", metrics.ORIENTATION_THRESHOLD, "below", (["tiled", "mosaic"], names),
         (["noise", "rotated"], directional)),
        ("induced", metrics.INDUCED_LATTICE_THRESHOLD, "below", (["mosaic", "noise"], names),
         (["tiled"], [n for n in names if n not in regular])),
        ("kept", metrics.LATTICE_KEPT_THRESHOLD, "above", (["tiled"], regular), (["mosaic", "noise"], regular)),
        ("elements", metrics.ELEMENT_INTEGRITY_THRESHOLD, "above", (["tiled"], elements), (["noise"], elements)),
    ]
    print("\n| metric | threshold | passing baselines: worst | failing baselines: worst | margins | "
          "syntheses that fail (of 3 seeds) |")
    print("|---|---|---|---|---|---|")
    for column, threshold, side, (good_rows, good_among), (bad_rows, bad_among) in checks:
        good, bad = values(good_rows, column, good_among), values(bad_rows, column, bad_among)
        if not good or not bad:
            print(f"| {column} | {side} {threshold} | no photo to judge on | | | |")
            continue
        sign = 1 if side == "below" else -1  # fails: sign * value > sign * threshold
        worst_good, worst_bad = sign * max(sign * v for v in good), sign * min(sign * v for v in bad)
        margins = f"{sign * (threshold - worst_good):+.2f}, {sign * (worst_bad - threshold):+.2f}"
        among = regular if column == "kept" else names
        counts = {(n, r): sum(sign * v > sign * threshold for v in found[n, r][column]) for n in among for r in METHODS}
        failing = [f"{n} {r} {k}" for (n, r), k in counts.items() if k]
        print(f"| {column} | {side} {threshold} | {'/'.join(good_rows)} on {len(good_among)} photos: "
              f"{worst_good:.2f} | {'/'.join(bad_rows)} on {len(bad_among)} photos: {worst_bad:.2f} | {margins} | "
              f"{', '.join(failing) or 'none'} |")
    others = [n for n in names if n not in directional]
    if others:
        noise = values(["noise"], "orient", others)
        print(f"\norientation of noise on the other photos: {min(noise):.1f}-{max(noise):.1f} degrees")
    if elements:
        print("element integrity on the photos of elements: " + ", ".join(
            f"{row} {min(values([row], 'elements', elements)):.2f}-{max(values([row], 'elements', elements)):.2f}"
            for row in ("mosaic", *METHODS)))
        mosaic, methods = values(["mosaic"], "elements", names), values(list(METHODS), "elements", names)
        print(f"element integrity, median over all photos and seeds: mosaic {np.median(mosaic):.2f}, "
              f"syntheses {np.median(methods):.2f}")
        median = {(n, r): np.median(found[n, r]["elements"]) for n in names for r in ("noise", "mosaic", *METHODS)}
        lowest = sum(median[n, "noise"] < min(median[n, r] for r in ("mosaic", *METHODS)) for n in names)
        best = sum(max(median[n, r] for r in METHODS) > median[n, "mosaic"] for n in names)
        above = sum(median[n, r] > median[n, "mosaic"] for n in names for r in METHODS)
        print(f"element integrity, medians over the seeds: noise lowest on {lowest} of {len(names)} photos; the best "
              f"synthesis above the mosaic on {best}; the syntheses above the mosaic {above} of {3 * len(names)} times")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=["tuning", "held-out", "fresh", "all"], default="all")
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1, 2])
    parser.add_argument("--cache", type=Path, help="a folder that keeps the syntheses between runs")
    args = parser.parse_args()
    if args.cache is not None:
        args.cache.mkdir(parents=True, exist_ok=True)
    start = time.perf_counter()
    for label, photos in (("tuning", TUNING), ("held-out", HELD_OUT), ("fresh", FRESH)):
        if args.set in (label, "all"):
            print(f"\n## {label}: {EXEMPLAR} px exemplars, outputs of twice their size, seeds {args.seeds}\n")
            found = score(photos, args.seeds, args.cache)
            lattices(found)
            summary(found)
    print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
