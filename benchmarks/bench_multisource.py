"""Speed of Wei-Levoy pixel synthesis, Wei mixtures and solid textures (prints a table).

Targets (issue 7): single source 64x64 -> 200x200 <= 5 s; two-source mixture
128x128 <= 15 s; solid 64^3 from a 64x64 exemplar <= 60 s. Also the speed-up of
approximate (kd-tree, TSVQ) and k-coherent candidates (mixture, issue 16) over exact search and its effect on texture energy:
"vs exact" is the exact row's time over this row's (same case, order and size),
"E/exact" this row's energy over the exact row's.

Run: python benchmarks/bench_multisource.py [--quick] [--solid]
(--quick: smaller outputs; --solid: only the solid-texture rows.)
"""

import os
import sys
import time
from pathlib import Path

import numpy as np

from texsynth.io import load_image
from texsynth.metrics import noise_baseline, texture_energy
from texsynth.pixel import mix_textures, synthesize_pixels, synthesize_solid

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def load(name, step=1):
    img = load_image(TEXTURES / name)
    img = img[..., :3] if img.ndim == 3 else img
    return img[: 64 * step : step, : 64 * step : step]


def timed(fn):
    start = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - start


def pixel_rows(quick):
    """Pebbles 64x64 -> 200x200 (64x64 for per-pixel approximate search in scanline order, next
    to exact search at the same size)."""
    pebbles = load("rohitrango/t4.png")
    big = 64 if quick else 200
    rows = []
    for order, search, size in [
        ("scanline", "exact", big), ("scanline", "exact", 64), ("scanline", "kdtree", 64), ("scanline", "tsvq", 64),
        ("independent", "exact", big), ("independent", "kdtree", big), ("independent", "tsvq", big),
    ]:
        if quick and size == 64 and search == "exact" and order == "scanline" and rows:
            continue  # same as the first row
        noise = texture_energy(noise_baseline(pebbles, size, rng=0), pebbles)
        out, sec = timed(lambda: synthesize_pixels(pebbles, size, order=order, method=search, rng=0))
        rows.append((f"pixels 64->{size} {order}", search, sec, texture_energy(out, pebbles), noise))
    return rows


def mix_rows(quick):
    """Brick and gravel (skimage, 1/4 scale) 64x64 -> 128x128, ramp weights; energy: left 32 columns vs brick."""
    brick, gravel = load("skimage/brick.png", 4), load("skimage/gravel.png", 4)
    n = 64 if quick else 128
    ramp = np.tile(np.linspace(0, 1, n), (n, 1))
    noise = texture_energy(noise_baseline(brick, n, rng=0), brick)
    rows = []
    for order, search in [("scanline", "exact"), ("independent", "exact"), ("independent", "kdtree"),
                          ("independent", "tsvq")]:
        out, sec = timed(lambda: mix_textures([brick, gravel], n, weights=[1 - ramp, ramp], order=order,
                                              method=search, rng=0))
        rows.append((f"mix 2x64 -> {n} ramp {order}", search, sec, texture_energy(out[:, :32], brick), noise))
    # k-coherent candidates (Ashikhmin, Tong et al.): compared with the scanline exact row of the same case
    out, sec = timed(lambda: mix_textures([brick, gravel], n, weights=[1 - ramp, ramp], candidates="k-coherent",
                                          rng=0))
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
    for search in ["auto", "tsvq", "exact"]:
        (vol, info), sec = timed(lambda: synthesize_solid(bread, n, method=search, rng=0, return_info=True))
        e = np.mean([texture_energy(s, bread) for s in (vol[n // 2], vol[:, n // 2], vol[:, :, n // 2])])
        rows.append((f"solid 64 -> {n}^3", info.method if search != "auto" else f"auto={info.method}", sec, e, noise))
    return rows


def versus_exact(rows):
    """Append (speed-up, energy ratio) against the exact-search row of the same case."""
    exact = {case: (sec, e) for case, search, sec, e, _ in rows if search == "exact"}
    result = []
    for case, search, sec, e, nz in rows:
        ref = exact.get(case)
        extra = ("", "") if ref is None or search == "exact" else (f"{ref[0] / sec:.1f}x", f"{e / ref[1]:.2f}")
        result.append((case, search, sec, e, nz) + extra)
    return result


def main(quick=False, solid_only=False):
    load_before = os.getloadavg()
    print(f"load average (1, 5, 15 min) before: {load_before}", flush=True)
    rows = [] if solid_only else pixel_rows(quick) + mix_rows(quick)
    rows += solid_rows(quick)
    print(f"load average (1, 5, 15 min) before: {load_before}, after: {os.getloadavg()}")
    print(f"{'case':38s} {'search':12s} {'seconds':>8s} {'energy':>8s} {'noise':>8s} {'vs exact':>8s} {'E/exact':>8s}")
    for case, search, sec, e, nz, speedup, ratio in versus_exact(rows):
        print(f"{case:38s} {search:12s} {sec:8.2f} {e:8.4f} {nz:8.4f} {speedup:>8s} {ratio:>8s}")


if __name__ == "__main__":
    main(quick="--quick" in sys.argv, solid_only="--solid" in sys.argv)
