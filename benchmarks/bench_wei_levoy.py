"""Speed of Wei-Levoy pixel synthesis: exact, kd-tree and TSVQ search, scanline and order-independent (a table).

Target (issue 7): 64x64 -> 200x200 <= 5 s. Also the speed-up of approximate search (kd-tree,
TSVQ) over exact search and its effect on texture energy: "vs exact" is the exact row's time
over this row's (same case, order and size), "E/exact" this row's energy over the exact row's.
k-coherent candidates are measured in ``benchmarks/bench_kcoherent.py``, mixtures and solids in
``benchmarks/bench_wei_2002.py``.

Run: python benchmarks/bench_wei_levoy.py [--quick]   (--quick: smaller outputs)
"""

import os
import sys
import time
from pathlib import Path

from texsynth.core.search import Search
from texsynth.io import load_image
from texsynth.metrics import noise_baseline, texture_energy
from texsynth.pixel import synthesize_pixels

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
    for order, method, size in [
        ("scanline", "exact", big), ("scanline", "exact", 64), ("scanline", "kdtree", 64), ("scanline", "tsvq", 64),
        ("independent", "exact", big), ("independent", "kdtree", big), ("independent", "tsvq", big),
    ]:
        if quick and size == 64 and method == "exact" and order == "scanline" and rows:
            continue  # same as the first row
        noise = texture_energy(noise_baseline(pebbles, size, rng=0), pebbles)
        out, sec = timed(lambda: synthesize_pixels(pebbles, size, order=order, search=Search(method=method), rng=0))
        rows.append((f"pixels 64->{size} {order}", method, sec, texture_energy(out, pebbles), noise))
    return rows


def versus_exact(rows):
    """Append (speed-up, energy ratio) against the exact-search row of the same case."""
    exact = {case: (sec, e) for case, method, sec, e, _ in rows if method == "exact"}
    result = []
    for case, method, sec, e, nz in rows:
        ref = exact.get(case)
        extra = ("", "") if ref is None or method == "exact" else (f"{ref[0] / sec:.1f}x", f"{e / ref[1]:.2f}")
        result.append((case, method, sec, e, nz) + extra)
    return result


def print_table(rows, load_before):
    print(f"load average (1, 5, 15 min) before: {load_before}, after: {os.getloadavg()}")
    print(f"{'case':38s} {'search':12s} {'seconds':>8s} {'energy':>8s} {'noise':>8s} {'vs exact':>8s} {'E/exact':>8s}")
    for case, method, sec, e, nz, speedup, ratio in versus_exact(rows):
        print(f"{case:38s} {method:12s} {sec:8.2f} {e:8.4f} {nz:8.4f} {speedup:>8s} {ratio:>8s}")


def main(quick=False):
    load_before = os.getloadavg()
    print(f"load average (1, 5, 15 min) before: {load_before}", flush=True)
    print_table(pixel_rows(quick), load_before)


if __name__ == "__main__":
    main(quick="--quick" in sys.argv)
