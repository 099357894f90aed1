"""Benchmark of Perlin noise (texsynth.procedural.perlin) against other noise libraries, in one run, and its memory.

Peers (the ``bench`` extra): pyfastnoiselite (FastNoiseLite, C++), ``noise``
(C, one Python call per point), vnoise (numpy). A peer that is not installed
is reported as missing. Prints the timings (a 1024^2 grid, 1M scattered points,
a 128^3 volume), the ratios against the targets of the procedural issue, and a
cross-check of our noise against the ``noise`` package (same permutation and
gradient table).

Memory: a table of the peak memory (tracemalloc, which sees numpy's
allocations) of one call per row, for frequencies 1 to 20000, next to the size
of the result and to the noise lattice that the whole-lattice evaluation of
texsynth 0.1 allocated. The peak must follow the result, not the lattice. It
runs in a few seconds; ``--big`` adds 2048^2 and 128^3.
``benchmarks/bench_patterns.py`` measures turbulence (octaves of this noise) the
same way and imports the helpers below.

Run:  python benchmarks/bench_noise.py [--quick] [--memory] [--big]
      (--memory: the memory table only)
"""

from __future__ import annotations

import argparse
import math
import platform
import time
import tracemalloc

import numpy as np

from _timing import best_of
from texsynth.procedural import FADES, perlin
from texsynth.procedural._noise import noise_points

# Perlin's reference permutation (Perlin 2002) and the `noise` package's
# gradient table (Perlin's, with the last four entries in another order).
PERLIN_PERMUTATION = [
    151, 160, 137, 91, 90, 15, 131, 13, 201, 95, 96, 53, 194, 233, 7, 225, 140, 36, 103, 30, 69, 142, 8, 99, 37,
    240, 21, 10, 23, 190, 6, 148, 247, 120, 234, 75, 0, 26, 197, 62, 94, 252, 219, 203, 117, 35, 11, 32, 57, 177,
    33, 88, 237, 149, 56, 87, 174, 20, 125, 136, 171, 168, 68, 175, 74, 165, 71, 134, 139, 48, 27, 166, 77, 146,
    158, 231, 83, 111, 229, 122, 60, 211, 133, 230, 220, 105, 92, 41, 55, 46, 245, 40, 244, 102, 143, 54, 65, 25,
    63, 161, 1, 216, 80, 73, 209, 76, 132, 187, 208, 89, 18, 169, 200, 196, 135, 130, 116, 188, 159, 86, 164, 100,
    109, 198, 173, 186, 3, 64, 52, 217, 226, 250, 124, 123, 5, 202, 38, 147, 118, 126, 255, 82, 85, 212, 207, 206,
    59, 227, 47, 16, 58, 17, 182, 189, 28, 42, 223, 183, 170, 213, 119, 248, 152, 2, 44, 154, 163, 70, 221, 153,
    101, 155, 167, 43, 172, 9, 129, 22, 39, 253, 19, 98, 108, 110, 79, 113, 224, 232, 178, 185, 112, 104, 218, 246,
    97, 228, 251, 34, 242, 193, 238, 210, 144, 12, 191, 179, 162, 241, 81, 51, 145, 235, 249, 14, 239, 107, 49,
    192, 214, 31, 181, 199, 106, 157, 184, 84, 204, 176, 115, 121, 50, 45, 127, 4, 150, 254, 138, 236, 205, 93,
    222, 114, 67, 29, 24, 72, 243, 141, 128, 195, 78, 66, 215, 61, 156, 180,
]
NOISE_PKG_GRADIENTS = np.array([
    (1, 1, 0), (-1, 1, 0), (1, -1, 0), (-1, -1, 0), (1, 0, 1), (-1, 0, 1), (1, 0, -1), (-1, 0, -1),
    (0, 1, 1), (0, -1, 1), (0, 1, -1), (0, -1, -1), (1, 0, -1), (-1, 0, -1), (0, -1, 1), (0, 1, 1),
], dtype=float)


def peers():
    """(the peer modules found by name, the names of those missing)."""
    found = {}
    try:
        import pyfastnoiselite.pyfastnoiselite as fnl

        found["pyfastnoiselite"] = fnl
    except ImportError:
        pass
    try:
        import noise

        found["noise"] = noise
    except ImportError:
        pass
    try:
        import vnoise

        found["vnoise"] = vnoise
    except ImportError:
        pass
    return found, sorted({"pyfastnoiselite", "noise", "vnoise"} - set(found))


def fastnoise_perlin(fnl, frequency):
    """A pyfastnoiselite Perlin generator, seed 0, of ``frequency`` cycles per sample."""
    gen = fnl.FastNoiseLite(0)
    gen.noise_type = fnl.NoiseType.NoiseType_Perlin
    gen.frequency = frequency
    return gen


def peak_memory(fn):
    """(peak bytes traced during one call, seconds, result): numpy reports its allocations to tracemalloc."""
    tracemalloc.start()
    t0 = time.perf_counter()
    try:
        result = fn()
        seconds = time.perf_counter() - t0
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    return peak, seconds, result


def finest_lattice(size, frequency, octaves):
    """Points of the finest octave's whole lattice (what texsynth 0.1 hashed and stored per component)."""
    top = frequency * 2.0 ** (octaves - 1)
    return math.prod(top * n / max(size) + 2 for n in size)


def memory_row(fn, size, frequency, n_octaves, **options):
    """One row of the memory table: ``fn(size, frequency=frequency, rng=0, **options)`` measured; ``n_octaves``
    is the number of octaves the call sums (1 for perlin), for the finest lattice of texsynth 0.1."""
    peak, seconds, out = peak_memory(lambda: fn(size, frequency=frequency, rng=0, **options))
    return (fn.__name__, size, frequency, n_octaves, out.nbytes, peak, seconds,
            finest_lattice(size, frequency, n_octaves))


def print_memory_table(rows):
    print("\npeak memory per call (tracemalloc) against the result and the whole finest lattice of texsynth 0.1")
    print(f"{'function':11s} {'size':>15s} {'freq':>6s} {'oct':>4s} {'result MiB':>11s} {'peak MiB':>9s} "
          f"{'peak/result':>11s} {'0.1 lattice pts':>15s} {'time s':>7s}")
    for name, size, frequency, octaves, nbytes, peak, seconds, lattice in rows:
        size_text = "x".join(map(str, size))
        print(f"{name:11s} {size_text:>15s} {frequency:6g} {octaves:4d} {nbytes / 2**20:11.2f} {peak / 2**20:9.2f} "
              f"{peak / nbytes:11.2f} {lattice:15.3g} {seconds:7.2f}")
    worst = max(peak - nbytes for _, _, _, _, nbytes, peak, _, _ in rows)
    print(f"largest peak beyond the result itself: {worst / 2**20:.1f} MiB (block-sized temporaries: "
          "independent of the frequency and of the number of octaves)")


def memory_table(big):
    """Peak memory per call of perlin against the size of the result, frequencies 1 to 20000."""
    sizes = [(1024, 1024), (64, 64, 64)] + ([(2048, 2048), (128, 128, 128)] if big else [])
    perlin((8, 8), rng=0)  # warm-up: imports, the BLAS controller
    rows = [memory_row(perlin, size, frequency, 1) for size in sizes for frequency in (1, 8, 64, 512, 4096, 20000)]
    rows.append(memory_row(perlin, (64, 64), 20000, 1))  # few pixels, a fine lattice: the reliability issue's
    print_memory_table(rows)


def ratio_row(times, label, ours, theirs, target, better):
    """One line of the ratio table: our time over a peer's, against the target."""
    if theirs not in times:
        print(f"{label:58s} {'n/a (peer missing)':>12s}")
        return
    r = times[ours] / times[theirs]
    print(f"{label:58s} {r:8.2f}x   target {better}{target:g}x  {'PASS' if r <= target else 'FAIL'}")


def print_rows(rows, missing):
    if missing:
        print("missing peers (pip install 'texsynth[bench]'):", ", ".join(missing))
    print(f"\n{'case':24s} {'library':36s} {'time (ms)':>10s}")
    for case, lib, sec in rows:
        print(f"{case:24s} {lib:36s} {sec * 1e3:10.1f}")
    return {(c, lib): s for c, lib, s in rows}


def start(doc, function, big_help, memory_table):
    """The start of this benchmark and of bench_patterns.py: the options --quick, --memory and --big, the header,
    ``memory_table(big)``; the number of repeats per timing, or None with --memory (the memory table only)."""
    parser = argparse.ArgumentParser(description=doc.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="one repeat")
    parser.add_argument("--memory", action="store_true", help="only the memory table")
    parser.add_argument("--big", action="store_true", help=big_help)
    args = parser.parse_args()
    print(f"texsynth.procedural.{function} benchmark -- {platform.python_version()}, {platform.machine()}, "
          f"numpy {np.__version__}")
    memory_table(args.big)
    if args.memory:
        return None
    return 1 if args.quick else 5


def main():
    rep = start(__doc__, "perlin", "memory table with 2048^2 and 128^3", memory_table)
    if rep is None:
        return
    n = 1024
    freq = 8
    found, missing = peers()
    rows = []  # (case, library, seconds)

    # ---- 2-D, 1024^2, one octave --------------------------------------------------
    rows.append(("2-D 1 octave", "texsynth perlin f32",
                 best_of(lambda: perlin((n, n), frequency=freq, dtype=np.float32, rng=0), rep)))
    rows.append(("2-D 1 octave", "texsynth perlin f64", best_of(lambda: perlin((n, n), frequency=freq, rng=0), rep)))
    coords2 = np.indices((n, n)).reshape(2, -1).astype(np.float32)
    # arbitrary points (no grid structure to exploit): 1M random 2-D points
    scatter = np.random.default_rng(0).uniform(0, freq, (n * n, 2))
    rows.append(("2-D 1M points", "texsynth perlin(points) f64",
                 best_of(lambda: perlin(points=scatter, rng=0), max(1, rep // 2))))
    rows.append(("2-D 1M points", "texsynth perlin(points) f32",
                 best_of(lambda: perlin(points=scatter, rng=0, dtype=np.float32), max(1, rep // 2))))
    if "pyfastnoiselite" in found:
        gen = fastnoise_perlin(found["pyfastnoiselite"], freq / n)
        rows.append(("2-D 1 octave", "pyfastnoiselite", best_of(lambda: gen.gen_from_coords(coords2), rep)))
        scatter32 = np.ascontiguousarray(scatter.T * (n / freq), dtype=np.float32)
        rows.append(("2-D 1M points", "pyfastnoiselite", best_of(lambda: gen.gen_from_coords(scatter32), rep)))
        coords3 = np.indices((128, 128, 128)).reshape(3, -1).astype(np.float32)
        gen3 = fastnoise_perlin(found["pyfastnoiselite"], freq / 128)
        rows.append(("3-D 128^3", "pyfastnoiselite", best_of(lambda: gen3.gen_from_coords(coords3), rep)))
    if "noise" in found:
        pnoise2 = found["noise"].pnoise2
        xs = (coords2[1] * (freq / n)).astype(float).tolist()
        ys = (coords2[0] * (freq / n)).astype(float).tolist()
        rows.append(("2-D 1 octave", "noise (pnoise2 per point)",
                     best_of(lambda: np.fromiter(map(pnoise2, xs, ys), float, count=n * n), max(1, rep // 3))))
    if "vnoise" in found:
        vn = found["vnoise"].Noise(0)
        axis = np.arange(n) * (freq / n)
        rows.append(("2-D 1 octave", "vnoise (grid_mode)", best_of(lambda: vn.noise2(axis, axis), max(1, rep // 3))))

    # ---- 3-D --------------------------------------------------------------------
    rows.append(("3-D 128^3", "texsynth perlin f32",
                 best_of(lambda: perlin((128, 128, 128), frequency=freq, dtype=np.float32, rng=0), rep)))
    rows.append(("3-D 128^3", "texsynth perlin f64",
                 best_of(lambda: perlin((128, 128, 128), frequency=freq, rng=0), rep)))

    # ---- table ------------------------------------------------------------------------
    t = print_rows(rows, missing)
    print("\nratios (texsynth time / peer time; below 1 = texsynth faster)")
    ratio_row(t, "1-oct perlin f32 / pyfastnoiselite 1-oct", ("2-D 1 octave", "texsynth perlin f32"),
              ("2-D 1 octave", "pyfastnoiselite"), 3.0, "<=")
    ratio_row(t, "1-oct perlin f64 / pyfastnoiselite 1-oct", ("2-D 1 octave", "texsynth perlin f64"),
              ("2-D 1 octave", "pyfastnoiselite"), 3.0, "<=")
    ratio_row(t, "1M scattered points perlin f32 / pyfastnoiselite (no target)",
              ("2-D 1M points", "texsynth perlin(points) f32"), ("2-D 1M points", "pyfastnoiselite"), np.inf, "<=")
    ratio_row(t, "3-D 128^3 perlin f32 / pyfastnoiselite", ("3-D 128^3", "texsynth perlin f32"),
              ("3-D 128^3", "pyfastnoiselite"), 3.0, "<=")
    print("\nabsolute targets")
    s3 = t[("3-D 128^3", "texsynth perlin f64")]
    print(f"{'3-D noise 128^3 (f64) <= 2 s':58s} {s3:8.3f} s   {'PASS' if s3 <= 2 else 'FAIL'}")

    # ---- cross-check ------------------------------------------------------------------
    if "noise" in found:
        noise = found["noise"]
        perm = np.array(PERLIN_PERMUTATION * 2)
        pts = np.random.default_rng(0).uniform(0, 50, (20000, 3))
        ours2 = noise_points(pts[:, :2], perm, None, FADES["quintic"], np.float64, NOISE_PKG_GRADIENTS)
        ref2 = np.array([noise.pnoise2(x, y) for x, y in pts[:, :2]])
        ours3 = noise_points(pts, perm, None, FADES["quintic"], np.float64, NOISE_PKG_GRADIENTS)
        ref3 = np.array([noise.pnoise3(*p) for p in pts])
        ours_p = noise_points(pts[:, :2], perm, (7, 7), FADES["quintic"], np.float64, NOISE_PKG_GRADIENTS)
        ref_p = np.array([noise.pnoise2(x, y, repeatx=7, repeaty=7) for x, y in pts[:, :2]])
        print("\ncross-check against the `noise` package (same permutation and gradient table, 20,000 points):")
        print(f"  max |ours - pnoise2| = {np.abs(ours2 - ref2).max():.2e}   "
              f"max |ours - pnoise3| = {np.abs(ours3 - ref3).max():.2e}   "
              f"periodic (repeat 7): {np.abs(ours_p - ref_p).max():.2e}   (noise computes in C float)")


if __name__ == "__main__":
    main()
