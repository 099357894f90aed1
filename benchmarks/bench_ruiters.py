"""Benchmark of Ruiters et al. 2010 patch-based texture interpolation (texsynth.interpolate_textures).

Targets (issue 8): one 256x256 intermediate texture from two 128x128 exemplars in at most
5 minutes on 2 cores, and a 512x128 transition strip in at most 10 minutes; the time of each
stage (correspondences, TPS-RPM, warping, synthesis, statistics), the iterations each stage ran
(a stage stops when its energy stops falling), the load average, and, as the quality next to the
speed, the texture energy of the alpha = 0.5 output against each input are printed. Side by side:
the plain linear blend (Figure 1a) and, as the reference for the paper's own figure, the
paper's 3.5 hours for a 1024x256 sequence on a 4-core Q6600.

With ``--caps``: what the cost caps cost in quality. The alpha = 0.5 256x256 run with the
defaults (``Correspondences(max_feature_points=24)``, ``NeighborhoodSet(max_neighborhoods=1024)``)
and with both doubled (48, 2048),
two seeds each: time, stage times, and texture energy against I1 and I2.

With ``--candidates``: the alpha = 0.5 run with the paper's correspondences (``Search(candidates="all")``,
every neighbourhood of the other texture) and with k-coherent ones, side by side: time, stage
times, texture energy against I1 and I2, and the mean weighted distance of each stage's
correspondences over exact search's. ``--candidates --photos A B --side N``: only the
correspondences, between the top-left N x N of two photographs of ``benchmarks/photos``.

With ``--save DIR`` the 256x256 texture and the strip are written there as PNG (to look at).

Run:  python benchmarks/bench_ruiters.py [--quick] [--caps] [--candidates [--photos A B --side N]] [--save DIR]
"""

import argparse
import os
import time

from dataclasses import replace
from pathlib import Path

import numpy as np

from texsynth.core.search import Search
from texsynth.optimization import (Correspondences, InterpolationSchedule, NeighborhoodSet, interpolate_textures,
                                   linear_blend, transition_alpha_map)
from texsynth.io import load_image, save_image
from texsynth.metrics import texture_energy

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def row(name, seconds, info=None, energies=None):
    stages = "" if info is None else "  ".join(f"{k}={v:.1f}s" for k, v in info.stage_seconds.items())
    if info is not None:
        stages += f"  iterations={np.bincount(info.stage).tolist()}"
    if energies is not None:
        stages += "  texture energy vs a {:.5f}, vs b {:.5f}".format(*energies)
    print(f"{name:<44s} {seconds:8.1f} s   {stages}")


def load():
    return os.getloadavg()[0]


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="64x64 exemplars, stages (2,17),(1,17), 3 iterations")
    parser.add_argument("--caps", action="store_true",
                        help="alpha = 0.5 with default and doubled max_feature_points / max_neighborhoods")
    parser.add_argument("--candidates", action="store_true",
                        help="alpha = 0.5 with the paper's correspondences and with k-coherent ones")
    parser.add_argument("--photos", nargs=2, help="--candidates: only the correspondences of these two photos")
    parser.add_argument("--side", type=int, default=256, help="--photos: the crops' side")
    parser.add_argument("--save", type=Path, help="folder for the outputs (PNG)")
    args = parser.parse_args()
    if args.caps:
        return caps(args.quick)
    if args.candidates:
        return candidates(args.quick, args.photos, args.side)
    n = 64 if args.quick else 128
    opts = _quick(args.quick)
    a = load_image(TEXTURES / "rohitrango" / "t1.png")[:n, :n, :3]
    b = load_image(TEXTURES / "rohitrango" / "t7.png")[:n, :n, :3]
    print(f"exemplars {n}x{n} brick <-> slate (rohitrango t1, t7); paper defaults unless noted; "
          f"load average {load():.2f}")
    t0 = time.perf_counter()
    linear_blend(a, b, 0.5)
    row("linear blend (Figure 1a)", time.perf_counter() - t0)
    t0 = time.perf_counter()
    mid, info = interpolate_textures(a, b, 0.5, size=2 * n, rng=0, return_info=True, **opts)
    seconds = time.perf_counter() - t0
    # quality next to the speed (untimed): Kwatra's texture energy (8 px patches) against each input
    row(f"interpolate_textures alpha=0.5 -> {2 * n}x{2 * n}", seconds, info,
        (texture_energy(mid, a), texture_energy(mid, b)))
    amap = transition_alpha_map((n, 4 * n))
    t0 = time.perf_counter()
    strip, info = interpolate_textures(a, b, amap, rng=0, return_info=True, **opts)
    row(f"transition strip {4 * n}x{n} (20 alphas)", time.perf_counter() - t0, info)
    if args.save is not None:
        args.save.mkdir(parents=True, exist_ok=True)
        save_image(args.save / "interpolation_mid.png", mid, overwrite=True)
        save_image(args.save / "interpolation_strip.png", strip, overwrite=True)
    print(f"load average at the end {load():.2f}")
    print("paper: 1024x256 sequence, 3.5 h on a 4-core Q6600 (20 min patch interpolation, C++)")


def _quick(quick):
    """The options of --quick: stages (2, 17), (1, 17), 3 iterations (the paper's schedule without it)."""
    return dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 17)), max_iterations=3)) if quick else {}


def caps(quick):
    """Default vs doubled caps (max_feature_points, max_neighborhoods), two seeds each."""
    n = 64 if quick else 128
    opts = _quick(quick)
    a = load_image(TEXTURES / "rohitrango" / "t1.png")[:n, :n, :3]
    b = load_image(TEXTURES / "rohitrango" / "t7.png")[:n, :n, :3]
    print(f"caps: exemplars {n}x{n} brick <-> slate, alpha = 0.5 -> {2 * n}x{2 * n}; load average {load():.2f}")
    for points, hoods in ((24, 1024), (48, 2048)):
        for seed in (0, 1):
            t0 = time.perf_counter()
            mid, info = interpolate_textures(a, b, 0.5, size=2 * n, rng=seed, return_info=True,
                                             correspondences=Correspondences(max_feature_points=points),
                                             neighborhood_set=NeighborhoodSet(max_neighborhoods=hoods), **opts)
            seconds = time.perf_counter() - t0
            row(f"points={points} neighborhoods={hoods} seed={seed}", seconds, info,
                (texture_energy(mid, a), texture_energy(mid, b)))
            print(f"    pairs per stage {info.pairs}, N' per stage {info.kept}, load average {load():.2f}")


def candidates(quick, photos=None, side=256):
    """The paper's correspondences against k-coherent ones: the whole interpolation, then each stage's pairs
    (``photos``: only the pairs, between two photographs of benchmarks/photos)."""
    import warnings

    from texsynth.core.neighborhood import all_patches
    from texsynth.optimization._ruiters_neighborhoods import _correspondences, check_inputs, stage_textures

    n = 64 if quick else 128
    opts = _quick(quick)
    a = load_image(TEXTURES / "rohitrango" / "t1.png")[:n, :n, :3]
    b = load_image(TEXTURES / "rohitrango" / "t7.png")[:n, :n, :3]
    if photos:
        here = Path(__file__).resolve().parent / "photos"
        a, b = (load_image(here / f"{p}.png")[:side, :side, :3] for p in photos)
        print(f"candidates: correspondences {photos[0]} <-> {photos[1]}, {side}x{side}; load average {load():.2f}")
    else:
        print(f"candidates: exemplars {n}x{n} brick <-> slate, alpha = 0.5 -> {2 * n}x{2 * n}; load average "
              f"{load():.2f}")
    for label in ("all", "k-coherent") if not photos else ():
        t0 = time.perf_counter()
        mid, info = interpolate_textures(a, b, 0.5, size=2 * n, rng=0, return_info=True,
                                         search=Search(candidates=label), **opts)
        row(f"candidates={label}", time.perf_counter() - t0, info, (texture_energy(mid, a), texture_energy(mid, b)))
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # no feature maps given: colour-only pairs
        p = check_inputs(a, b, None, Correspondences(), NeighborhoodSet(), Search())
    for r, s in opts.get("schedule", InterpolationSchedule()).stages:
        t1, t2 = stage_textures(p, r, s)
        v1, v2 = all_patches(t1.image, s), all_patches(t2.image, s)
        found = {}
        for label in ("all", "k-coherent"):
            t0 = time.perf_counter()
            c1, c2 = _correspondences(t1, t2, s, replace(p, method="exact", candidates=label),
                                      np.random.default_rng(0))
            seconds = time.perf_counter() - t0
            d = (((v1[c1[:, 0], c1[:, 1]] - v2[c2[:, 0], c2[:, 1]]) ** 2) * p.channel_weights).sum((1, 2, 3))
            found[label] = (seconds, float(d.mean()))
        print(f"    stage (r={r}, s={s}): exact search {found['all'][0]:.2f} s, k-coherent {found['k-coherent'][0]:.2f} s, "
              f"mean distance {found['k-coherent'][1] / found['all'][1]:.3f}x exact's")


if __name__ == "__main__":
    main()
