"""Quality of texture optimization's defaults at 4x and 8x enlargement, against the resynthesizer engine.

Issue 16's quality study, on the real photographs of ``benchmarks/photos``,
split in two: the *tuning* photographs are the ones the defaults were chosen on
(neighbourhood sizes, levels, copy limit, when the completeness term is on);
the *checking* photographs were never looked at while tuning, so their figures
say how the library does on textures nobody tuned it for.

For every photograph and enlargement (a 256-px crop to 1024², 4x; a 128-px
crop to 1024², 8x) it runs ``optimize_texture`` with its defaults and the
resynthesizer engine (PyPI ``resynthesizer``, GIMP's "Uncrop": the photograph
in a corner of the canvas, the rest synthesised), and scores the synthesised
part (the output without the rows and columns of the corner the engine keeps,
the same pixels for both) with the library's metrics:

- ``copy``: the largest region copied verbatim, as a fraction of the exemplar
  (:func:`texsynth.metrics.verbatim_copy`; the issue's bound: 1/3);
- ``complete``: :func:`texsynth.metrics.completeness` divided by that of a
  random-block mosaic of the same size (the bound: at most 1);
- ``large``: :func:`texsynth.metrics.spectrum_distance` over wavelengths above
  an eighth of the crop (the arrangement of the elements), next to the same for
  the mosaic and for histogram-matched noise;
- ``edge``: the mean of the output's outer 8 rows and columns minus the mean
  inside (the band of exemplar edge rows the paper's grid piles up there).

Usage::

    pip install -e .[bench]
    python benchmarks/bench_kwatra_quality.py [--scales 4 8] [--photos NAME ...] [--figure]
                                      [--seed N] [--option NAME=VALUE ...] [--no-peer]

Writes the outputs to ``benchmarks/output/quality_*.png``, prints a table per
split, and with ``--figure`` the side-by-side figure ``docs/_static/quality_4x.png``
(checking photographs under permissive licences only: see photos/README.md).
"""

from __future__ import annotations

import argparse
import ast
import os
import time
from pathlib import Path

import numpy as np

import texsynth
from texsynth import metrics
from texsynth.io import save_image
from texsynth.registry import group_options

from bench_kwatra_production import OUTPUT, load, resynthesize

#: Photographs the defaults were tuned on (docs/methods/kwatra.md says how).
TUNING = ["bricks_2", "cobblestones_1", "stonewall_2", "cracked_2", "moss_1"]
#: Photographs never looked at while tuning: bricks, tiles, slate, cracked ground, moss, bark, cells
#: (lava-like), concrete, grass, wood, stone.
CHECKING = ["bricks_1", "tiles_1", "tiles_2", "stonewall_1", "cracked_1", "cellular_1", "moss_2", "bark_1",
            "concrete_1", "grass_1", "wood_2", "cobblestones_2"]
#: Checking photographs whose licence lets their outputs appear in the docs (photos/README.md).
FIGURE = ["tiles_2", "cellular_1", "concrete_1", "wood_2", "cobblestones_2"]
SIZE = 1024


def scores(out, exemplar, side, seed=0):
    """The metrics of a 512² synthesised part of ``out`` (beside the corner the engine keeps)."""
    part = out[side : side + 512, side : side + 512]
    mosaic = metrics.mosaic_baseline(exemplar, part.shape[:2], rng=seed)
    noise = metrics.noise_baseline(exemplar, part.shape[:2], rng=seed)
    long = dict(min_wavelength=side / 8)
    kw = dict(stride=4, method="kdtree", rng=seed)
    inside = out[8:-8, 8:-8].mean()
    border = np.concatenate([out[:8].ravel(), out[-8:].ravel(), out[:, :8].ravel(), out[:, -8:].ravel()]).mean()
    return dict(
        copy=metrics.verbatim_copy(part, exemplar, **kw),
        complete=metrics.completeness(part, exemplar, **kw) / metrics.completeness(mosaic, exemplar, **kw),
        large=metrics.spectrum_distance(part, exemplar, **long),
        large_mosaic=metrics.spectrum_distance(mosaic, exemplar, **long),
        large_noise=metrics.spectrum_distance(noise, exemplar, **long),
        edge=float(border - inside),
    )


def study(photos, scales, seed=0, options=None, peer=True):
    """Scores of the defaults (with ``options``, named "options"; ``rng=seed``) and of resynthesizer."""
    rows = []
    label = "options" if options else "defaults"
    suffix = f"_seed{seed}" if seed else ""
    for photo in photos:
        for scale in scales:
            side = SIZE // scale
            exemplar = load(photo, side)
            for method in (label, "resynthesizer") if peer else (label,):
                start = time.perf_counter()
                if method == "resynthesizer":
                    out = resynthesize(exemplar, SIZE)
                else:
                    # flat options (a field of an option group, e.g. completeness_weight) into their groups
                    out = texsynth.optimize_texture(exemplar, SIZE, rng=seed,
                                                    **group_options(texsynth.optimize_texture, options or {}))
                seconds = time.perf_counter() - start
                OUTPUT.mkdir(exist_ok=True)
                save_image(OUTPUT / f"quality_{photo}_{scale}x_{method}{suffix}.png", np.clip(out, 0, 1),
                           overwrite=True)
                row = dict(photo=photo, scale=scale, method=method, seconds=seconds, **scores(out, exemplar, side))
                rows.append(row)
                print(" ".join(f"{k}={v:.3f}" if isinstance(v, float) else f"{k}={v}" for k, v in row.items()),
                      flush=True)
    return rows


def table(rows, title):
    print(f"\n### {title}\n")
    print("| photo | scale | method | copy | complete / mosaic | large (mosaic, noise) | edge | time |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['photo']} | {r['scale']}x | {r['method']} | {r['copy']:.2f} | {r['complete']:.2f} | "
              f"{r['large']:.2f} ({r['large_mosaic']:.2f}, {r['large_noise']:.2f}) | {r['edge']:+.3f} | "
              f"{r['seconds']:.0f} s |")
    for method in ("defaults", "options", "resynthesizer"):
        mine = [r for r in rows if r["method"] == method]
        if mine:
            print(f"\n{method}: copy <= 1/3 in {sum(r['copy'] <= 1 / 3 for r in mine)}/{len(mine)}, "
                  f"completeness <= mosaic in {sum(r['complete'] <= 1 for r in mine)}/{len(mine)}, "
                  f"large-scale distance below the mosaic's in "
                  f"{sum(r['large'] < r['large_mosaic'] for r in mine)}/{len(mine)}")


def figure(photos, scale=4):
    """Exemplar | defaults | resynthesizer, each output's central 512² shown at half size."""
    from texsynth.io import load_image

    side = SIZE // scale
    rows = []
    for photo in photos:
        ex = load(photo, side)
        outs = [load_image(OUTPUT / f"quality_{photo}_{scale}x_{m}.png")[..., :3] for m in ("defaults", "resynthesizer")]
        crops = [o[256:768, 256:768][::2, ::2] for o in outs]  # half size: the arrangement, not the pixels
        pad = np.ones((side, 8, 3), np.float32)
        rows.append(np.concatenate([ex, pad] + [np.concatenate([c, pad], 1) for c in crops], 1))
    gap = np.ones((8, rows[0].shape[1], 3), np.float32)
    image = np.concatenate(sum([[r, gap] for r in rows], [])[:-1], 0)
    path = Path(__file__).resolve().parents[1] / "docs" / "_static" / f"quality_{scale}x.png"
    save_image(path, image, overwrite=True)
    print(f"wrote {path}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--scales", type=int, nargs="+", default=[4, 8])
    parser.add_argument("--photos", nargs="+")
    parser.add_argument("--figure", action="store_true")
    parser.add_argument("--seed", type=int, default=0, help="rng of optimize_texture (the baselines keep seed 0)")
    parser.add_argument("--option", action="append", default=[], metavar="NAME=VALUE",
                        help="an optimize_texture option instead of its default, e.g. completeness_weight=0")
    parser.add_argument("--no-peer", dest="peer", action="store_false", help="leave out resynthesizer")
    args = parser.parse_args()
    options = {}
    for item in args.option:
        name, _, value = item.partition("=")
        options[name] = ast.literal_eval(value)
    run = dict(seed=args.seed, options=options, peer=args.peer)
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}, seed {args.seed}, "
          f"options {options or 'none'}", flush=True)
    if args.photos:
        table(study(args.photos, args.scales, **run), "chosen photographs")
    else:
        table(study(TUNING, args.scales, **run), "tuning photographs (the defaults were chosen on these)")
        table(study(CHECKING, args.scales, **run), "checking photographs (never looked at while tuning)")
    if args.figure:
        figure(FIGURE)


if __name__ == "__main__":
    main()
