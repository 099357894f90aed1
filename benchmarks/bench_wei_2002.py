"""Speed of Wei's mixtures and solid textures: exact, kd-tree, TSVQ and k-coherent search (prints a table).

Targets (issue 7): two-source mixture 128x128 <= 15 s; solid 64^3 from a 64x64 exemplar <= 60 s.
Also the speed-up of approximate (kd-tree, TSVQ) and k-coherent candidates (mixture, issue 16)
over exact search and its effect on texture energy: "vs exact" is the exact row's time over this
row's (same case, order and size), "E/exact" this row's energy over the exact row's.

Run: python benchmarks/bench_wei_2002.py [--quick] [--solid]
(--quick: smaller outputs; --solid: only the solid-texture rows.)
"""

import os
import sys

import numpy as np

from bench_wei_levoy import load, print_table, timed
from texsynth.core.search import Search
from texsynth.metrics import noise_baseline, texture_energy
from texsynth.pixel import mix_textures, synthesize_solid


def mix_rows(quick):
    """Brick and gravel (skimage, 1/4 scale) 64x64 -> 128x128, ramp weights; energy: left 32 columns vs brick."""
    brick, gravel = load("skimage/brick.png", 4), load("skimage/gravel.png", 4)
    n = 64 if quick else 128
    ramp = np.tile(np.linspace(0, 1, n), (n, 1))
    noise = texture_energy(noise_baseline(brick, n, rng=0), brick)
    rows = []
    for order, method in [("scanline", "exact"), ("independent", "exact"), ("independent", "kdtree"),
                          ("independent", "tsvq")]:
        out, sec = timed(lambda: mix_textures([brick, gravel], n, weights=[1 - ramp, ramp], order=order,
                                              search=Search(method=method), rng=0))
        rows.append((f"mix 2x64 -> {n} ramp {order}", method, sec, texture_energy(out[:, :32], brick), noise))
    # k-coherent candidates (Ashikhmin, Tong et al.): compared with the scanline exact row of the same case
    out, sec = timed(lambda: mix_textures([brick, gravel], n, weights=[1 - ramp, ramp],
                                          search=Search(candidates="k-coherent"), rng=0))
    rows.append((f"mix 2x64 -> {n} ramp scanline", "k-coherent", sec, texture_energy(out[:, :32], brick), noise))
    return rows


def solid_rows(quick):
    """Solid 64^3 (32^3 with --quick): "auto" (kd-tree at this size), tsvq and exact side by side.

    Energy: mean over the three axis-aligned middle slices of texture_energy against the view.
    """
    n = 32 if quick else 64
    bread = load("jcjohnson/bread.png")
    noise = texture_energy(noise_baseline(bread, n, rng=0), bread)
    rows = []
    for method in ["auto", "tsvq", "exact"]:
        (vol, info), sec = timed(lambda: synthesize_solid(bread, n, search=Search(method=method), rng=0,
                                                          return_info=True))
        e = np.mean([texture_energy(s, bread) for s in (vol[n // 2], vol[:, n // 2], vol[:, :, n // 2])])
        rows.append((f"solid 64 -> {n}^3", info.method if method != "auto" else f"auto={info.method}", sec, e, noise))
    return rows


def main(quick=False, solid_only=False):
    load_before = os.getloadavg()
    print(f"load average (1, 5, 15 min) before: {load_before}", flush=True)
    rows = [] if solid_only else mix_rows(quick)
    print_table(rows + solid_rows(quick), load_before)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv, solid_only="--solid" in sys.argv)
