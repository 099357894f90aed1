"""Benchmark of PatchMatch (texsynth.core.search._patchmatch) against exact search and the PCA kd-tree.

The question of texture optimization's M-step: for every neighbourhood of the
output on the w/4 grid (Kwatra et al. 2005), the nearest neighbourhood of the
exemplar. Real photographs, colour, float32 (as the optimization searches):

- target 256 x 256: a crop of ``embark/multiexample/2.jpg``; source: a 128 x 128
  crop of ``embark/multiexample/1.jpg`` (another photograph of the same ink);
- target 512 x 512: the whole 400 x 400 photograph ``2.jpg``, mirrored at its
  edges up to 512 (no colour photograph of the set is larger); source: a
  256 x 256 crop of ``1.jpg``;

for w = 8, 16 and 32 (grid spacing w / 4). A second table asks the question
of a synthesis: the target is a 512 px Harrison patchwork of the 256 px source
(``texsynth.patchwork``, blended cells of the exemplar, as an output under
optimization looks), then that target after one E-step of texture optimization
(the matched source patches averaged back with Gaussian fall-off,
``core.neighborhood.accumulate``), searched from scratch and warm-started from
the previous field (``init=``), as the next M-step would. Methods: exact search
(``nearest_field(method="exact")``, chunked BLAS), the PCA kd-tree
(``method="kdtree"``, build + query, default options), and PatchMatch with
1, 2, 3, 5 and 8 iterations; ``--schedules`` adds, for the 512 px target, a
fully parallel jump-flood schedule (every query propagates at once from its
neighbours at distances 2^j, ..., 2, 1 grid steps, Jacobi style) in place of
the library's anti-diagonal scan, to show why the library scans.

recall@1: fraction of queries whose returned patch is at the exact nearest
distance (ties count as hits). Distance ratio: mean of returned / exact
squared distance, over queries whose exact match is not a copy (RMS
difference per value at least half an 8-bit level). Energy ratio: sum of
returned / sum of exact squared distances (the M-step's energy against the
exact M-step's). For the 512 px target the
exact answer is computed for a random sample of ``--sample`` queries only;
its time is that sample's, scaled to every query (marked ``*``).

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_patchmatch.py --schedules   # about 70 s
    python benchmarks/bench_patchmatch.py --quick                              # smaller, seconds
"""

from __future__ import annotations

import argparse
import datetime
import os
import platform
import time
from pathlib import Path

import numpy as np

import texsynth.core.search._patchmatch as pm
from texsynth import patchwork
from texsynth.core.neighborhood import (
    accumulate,
    extract,
    gaussian_falloff,
    grid_centers,
)
from texsynth.io import load_image

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
ITERATIONS = (1, 2, 3, 5, 8)


def load(name):
    return load_image(TEXTURES / name)[..., :3].astype(np.float32)


def cases(quick):
    a, b = load("embark/multiexample/2.jpg"), load("embark/multiexample/1.jpg")
    big = np.pad(a, ((56, 56), (56, 56), (0, 0)), mode="symmetric")  # 400 -> 512, mirrored
    if quick:
        return [("128", a[:128, :128], "64", b[:64, :64])]
    return [("256", a[72:328, 72:328], "128", b[:128, :128]), ("512", big, "256", b[:256, :256])]


def timed(fn, *args, **kwargs):
    t = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t


# a query whose exact match differs by less than half an 8-bit level (RMS per value) is a copy:
# its ratio would divide by rounding noise, so it counts in recall and energy ratio only
_COPY_RMS = 0.5 / 255


def score(d2, exact, dim):
    """recall@1, mean per-query distance ratio, and energy ratio (sum of returned / sum of exact)."""
    hit = d2[:, 0] <= exact[:, 0] * (1 + 1e-5) + 1e-9  # equal to float32 rounding: a tie
    pos = exact[:, 0] > dim * _COPY_RMS**2
    ratio = float(np.mean(d2[pos, 0] / exact[pos, 0])) if pos.any() else 1.0
    return float(hit.mean()), ratio, float(d2[:, 0].sum(dtype=np.float64) / exact[:, 0].sum(dtype=np.float64))


def run(quick, sample, schedules):
    rows = []
    for tname, target, sname, source in cases(quick):
        for w in (8, 16, 32):
            if w > source.shape[0] // 2:
                continue
            centers = grid_centers(target.shape[:2], w, w // 4, mode="valid")
            n = len(centers)
            sub = np.arange(n)
            if n > sample and tname == "512":
                sub = np.sort(np.random.default_rng(0).choice(n, sample, replace=False))
            (_, exact), t_exact = timed(pm.nearest_field, target, source, w, centers=centers[sub], method="exact")
            scaled = len(sub) < n
            t_exact *= n / len(sub)
            label = f"{tname} <- {sname}, w={w}"
            rows.append((label, n, "exact", "", t_exact, scaled, 1.0, 1.0, 1.0))
            (_, d2), t = timed(pm.nearest_field, target, source, w, centers=centers, method="kdtree", rng=0)
            rows.append((label, n, "kdtree (build + query)", "", t, False, *score(d2[sub], exact, w * w * 3)))
            for it in ITERATIONS:
                (_, d2), t = timed(pm.patchmatch, target, source, w, centers=centers, iterations=it, rng=0)
                rows.append((label, n, "patchmatch", it, t, False, *score(d2[sub], exact, w * w * 3)))
            if schedules and tname == "512":
                scan = pm._iterate
                pm._iterate = pm._iterate_parallel
                try:
                    for it in (1, 5):
                        (_, d2), t = timed(pm.patchmatch, target, source, w, centers=centers, iterations=it, rng=0)
                        rows.append((label, n, "patchmatch, jump-flood schedule", it, t, False,
                                     *score(d2[sub], exact, w * w * 3)))
                finally:
                    pm._iterate = scan
            (_, d2), _t = timed(pm.patchmatch, target, source, w, centers=centers, iterations=0, rng=0)
            rows.append((label, n, "random field", 0, _t, False, *score(d2[sub], exact, w * w * 3)))
            print(f"  {label}: done", flush=True)
    return rows


def cpu_name():
    try:
        with open("/proc/cpuinfo") as f:
            return next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        return platform.processor() or platform.machine()


def run_synthesis(quick, sample):
    """Patchwork target, then one E-step: cold and warm-started fields."""
    b = load("embark/multiexample/1.jpg")
    source = b[:64, :64] if quick else b[:256, :256]
    size = 128 if quick else 512
    rows = []
    for w in (8, 16, 32):
        if w > source.shape[0] // 2:
            continue
        x0 = patchwork(source.astype(np.float64), size, rng=0).astype(np.float32)
        centers = grid_centers(x0.shape[:2], w, w // 4, mode="valid")
        n = len(centers)
        sub = np.sort(np.random.default_rng(0).choice(n, min(n, sample), replace=False))
        field = None
        for stage, target in (("patchwork", x0), ("after one E-step", None)):
            if target is None:  # E-step: the matched patches, averaged with fall-off (Kwatra et al. 2005)
                patches = extract(source, field[:, 0], w, mode="valid")
                target, _ = accumulate(patches, centers, x0.shape[:2], pixel_weights=gaussian_falloff(w),
                                       mode="valid")
                target = target.astype(np.float32)
            label = f"{size} {stage} <- {source.shape[0]}, w={w}"
            (_, exact), t_exact = timed(pm.nearest_field, target, source, w, centers=centers[sub], method="exact")
            rows.append((label, n, "exact", "", t_exact * n / len(sub), len(sub) < n, 1.0, 1.0, 1.0))
            (_, d2), t = timed(pm.nearest_field, target, source, w, centers=centers, method="kdtree", rng=0)
            rows.append((label, n, "kdtree (build + query)", "", t, False, *score(d2[sub], exact, w * w * 3)))
            for it in (1, 3, 5):
                (f, d2), t = timed(pm.patchmatch, target, source, w, centers=centers, iterations=it, rng=0)
                rows.append((label, n, "patchmatch", it, t, False, *score(d2[sub], exact, w * w * 3)))
            if field is not None:
                for it in (1, 2):
                    (_, d2), t = timed(pm.patchmatch, target, source, w, centers=centers, iterations=it,
                                       init=field, rng=0)
                    rows.append((label, n, "patchmatch, warm start", it, t, False,
                                 *score(d2[sub], exact, w * w * 3)))
            field = f  # the 5-iteration field: what the M-step handed to the E-step
        print(f"  synthesis, w={w}: done", flush=True)
    return rows


def table(rows):
    print("| target <- source, w | queries | method | iterations | time s | recall@1 | distance ratio "
          "| energy ratio |")
    print("|---|---|---|---|---|---|---|---|")
    for label, n, method, it, t, scaled, recall, ratio, energy in rows:
        print(f"| {label} | {n} | {method} | {it} | {t:.2f}{'*' if scaled else ''} | {recall:.3f} | {ratio:.3f} "
              f"| {energy:.3f} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="a 128 px target against a 64 px source")
    parser.add_argument("--sample", type=int, default=2000, help="queries of the 512 px target searched exactly")
    parser.add_argument("--schedules", action="store_true", help="also the jump-flood schedule (512 px target)")
    args = parser.parse_args()
    start = time.perf_counter()
    rows = run(args.quick, args.sample, args.schedules)
    synthesis = run_synthesis(args.quick, args.sample)
    print()
    print(f"Machine: {cpu_name()}, {os.cpu_count()} cores, "
          f"Python {platform.python_version()}, numpy {np.__version__}, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}, "
          f"load average {os.getloadavg()[0]:.1f}; {datetime.date.today().isoformat()}; "
          f"run {time.perf_counter() - start:.0f} s")
    print()
    print("Photograph against photograph:")
    print()
    table(rows)
    print()
    print("A synthesis: patchwork target, then one E-step (exact answers of a sample of queries):")
    print()
    table(synthesis)


if __name__ == "__main__":
    main()
