"""Wei-Levoy pixel synthesis with all candidates against k-coherent candidates (Ashikhmin, Tong et al.).

Run: python benchmarks/bench_kcoherent.py [--figure] [--mix] [--optimize PHOTO ...]   (from the repository root)

Targets: ``synthesize_pixels`` 128^2 -> 512^2 colour in at most 10 s with the elements of a brick
wall kept (issue 16); Ashikhmin / k-coherent 128^2 -> 512^2 colour in at most 5 s (issue 18).

Side by side, in the same run, on the top-left 128x128 of the colour photographs
``benchmarks/photos/bricks_1`` (a red brick wall), ``tiles_1`` (stone tiles) and ``roof_1``
(wooden shingles), seed 0, 3 levels, causal 5x5 neighbourhoods (the defaults):
``candidates="all"`` (Wei & Levoy: every exemplar neighbourhood, exact line-wise search) and
``candidates="k-coherent"`` with ``k=1`` (Ashikhmin's search) and ``k=2``. Each line: wall time
and, on the output's top-left 256x256, completeness and texture energy over a random-block
mosaic of the same size (below 1: better than the mosaic), and the largest verbatim copy as a
fraction of the exemplar.

``--figure`` also writes ``docs/_static/kcoherent.png``: per photograph the exemplar and the
three outputs' top-left 256x256, side by side. ``--mix`` also times Wei's mixture of
``bricks_1`` and ``cobblestones_2`` (128x128 crops) along a ramp at the same size, with all
candidates and with k-coherent ones. ``--optimize PHOTO ...`` instead times texture
optimization 256² -> 1024² of each photograph with its defaults (``candidates="all"``: PatchMatch
M-steps) and with ``candidates="k-coherent"``, ``k=1`` and ``k=4``, scored on a 512² part as
``bench_kwatra_quality.py`` scores (completeness over a random-block mosaic's, largest copy, large-scale
spectrum distance and the mosaic's); the outputs go to ``benchmarks/output/kcoherent_opt_*.png``, and
with ``--figure`` the middle 256² of each output of the photographs whose licence allows it
(``bench_kwatra_quality.FIGURE``) to ``docs/_static/kcoherent_optimize.png``, one row per photograph.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

from texsynth import metrics, mix_textures, synthesize_pixels
from texsynth.core.search import Search
from texsynth.io import load_image, save_image

HERE = Path(__file__).resolve().parent
PHOTOS = ("bricks_1", "tiles_1", "roof_1")
RUNS = (("all", {}), ("k-coherent k=1", dict(search=Search(candidates="k-coherent"))),
        ("k-coherent k=2", dict(search=Search(candidates="k-coherent", k=2))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=512)
    parser.add_argument("--figure", action="store_true")
    parser.add_argument("--mix", action="store_true", help="also time a two-photo mixture (all vs k-coherent)")
    parser.add_argument("--optimize", nargs="+", metavar="PHOTO",
                        help="texture optimization 256 -> 1024 of these photos instead (all vs k-coherent)")
    args = parser.parse_args()
    print(f"# {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    if args.optimize:
        return optimization(args.optimize, args.figure)
    print("| photo | candidates | seconds | completeness / mosaic | energy / mosaic | largest copy |")
    print("|---|---|---|---|---|---|")
    rows = []
    for photo in PHOTOS:
        exemplar = np.ascontiguousarray(load_image(HERE / "photos" / f"{photo}.png")[:128, :128, :3])
        mosaic = metrics.mosaic_baseline(exemplar, 256, rng=0)
        panels = [np.pad(exemplar, ((0, 128), (0, 128), (0, 0)), constant_values=1.0)]
        for label, options in RUNS:
            start = time.perf_counter()
            out = synthesize_pixels(exemplar, args.size, rng=0, **options)
            seconds = time.perf_counter() - start
            part = out[:256, :256]
            completeness = metrics.completeness(part, exemplar) / metrics.completeness(mosaic, exemplar)
            energy = metrics.texture_energy(part, exemplar) / metrics.texture_energy(mosaic, exemplar)
            copy = metrics.verbatim_copy(part, exemplar)
            print(f"| {photo} | {label} | {seconds:.1f} | {completeness:.2f} | {energy:.2f} | {copy:.2f} |", flush=True)
            panels.append(part)
        rows.append(np.concatenate([np.pad(p, ((4, 4), (4, 4), (0, 0)), constant_values=1.0) for p in panels], 1))
    if args.figure:
        save_image(HERE.parent / "docs" / "_static" / "kcoherent.png", np.concatenate(rows, 0), overwrite=True)
    if args.mix:
        mixture(args.size)


def optimization(photos, figure=False):
    """Texture optimization's M-step over all candidates (PatchMatch) against k-coherent ones."""
    import sys

    import texsynth

    sys.path.insert(0, str(HERE))
    from bench_kwatra_quality import FIGURE, load, scores

    rows = []
    texsynth.optimize_texture(load(photos[0], 64), 96, rng=0)  # warm-up: imports, caches
    print("| photo | candidates | seconds | completeness / mosaic | largest copy | large-scale | mosaic's |")
    print("|---|---|---|---|---|---|---|")
    for photo in photos:
        exemplar = load(photo, 256)
        panels = [exemplar]
        for label, options in (("all", {}), ("k-coherent k=1", dict(search=Search(candidates="k-coherent", k=1))),
                               ("k-coherent k=4", dict(search=Search(candidates="k-coherent", k=4)))):
            start = time.perf_counter()
            out = texsynth.optimize_texture(exemplar, 1024, rng=0, **options)
            seconds = time.perf_counter() - start
            r = scores(out, exemplar, 256)
            print(f"| {photo} | {label} | {seconds:.1f} | {r['complete']:.2f} | {r['copy']:.2f} | {r['large']:.3f} "
                  f"| {r['large_mosaic']:.3f} |", flush=True)
            (HERE / "output").mkdir(exist_ok=True)
            tag = label.replace(" ", "").replace("=", "")
            save_image(HERE / "output" / f"kcoherent_opt_{photo}_{tag}.png", np.clip(out, 0, 1), overwrite=True)
            panels.append(np.clip(out[384:640, 384:640], 0, 1))
        if photo in FIGURE:
            rows.append(np.concatenate([np.pad(p, ((4, 4), (4, 4), (0, 0)), constant_values=1.0) for p in panels], 1))
    if figure and rows:
        save_image(HERE.parent / "docs" / "_static" / "kcoherent_optimize.png", np.concatenate(rows, 0), overwrite=True)


def mixture(size):
    """Wei's mixture of the brick wall and a paving along a left-to-right ramp: all candidates, then
    k-coherent ones (issue 16); the outputs go to benchmarks/output/kcoherent_mix_*.png."""
    a, b = (np.ascontiguousarray(load_image(HERE / "photos" / f"{p}.png")[:128, :128, :3])
            for p in ("bricks_1", "cobblestones_2"))
    ramp = np.broadcast_to(np.linspace(0.0, 1.0, size), (size, size))
    for label, options in (("all", {}), ("k-coherent", dict(search=Search(candidates="k-coherent")))):
        start = time.perf_counter()
        out = mix_textures([a, b], size, weights=[1 - ramp, ramp], rng=0, **options)
        print(f"mixture bricks_1 + cobblestones_2 -> {size}², {label}: {time.perf_counter() - start:.1f} s", flush=True)
        (HERE / "output").mkdir(exist_ok=True)
        save_image(HERE / "output" / f"kcoherent_mix_{label}.png", np.clip(out, 0, 1), overwrite=True)


if __name__ == "__main__":
    main()
