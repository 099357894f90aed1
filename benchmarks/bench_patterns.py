"""Benchmark of turbulence (texsynth.procedural.turbulence) against other noise libraries' fBm, and its memory.

Peers (the ``bench`` extra), as in ``benchmarks/bench_noise.py``: pyfastnoiselite
(8-octave fBm), ``noise`` (pnoise2 with 8 octaves, one Python call per point),
vnoise (8 octaves on a grid). Prints the timings of 8-octave turbulence at 1024^2
and at 128^3 and the ratios against the targets of the procedural issue.

Memory: the peak memory (tracemalloc) of one call per row, for frequencies 1 to
20000 with octaves up to the band limit, next to the size of the result and to
the finest noise lattice that texsynth 0.1 allocated; the peak must follow the
result. ``--big`` adds 2048^2, 128^3 and turbulence(8192) (a 512 MiB result).

Run:  python benchmarks/bench_patterns.py [--quick] [--memory] [--big]
      (--memory: the memory table only)
"""

from __future__ import annotations

import numpy as np

from _timing import best_of
from bench_noise import fastnoise_perlin, memory_row, peers, print_memory_table, print_rows, ratio_row, start
from texsynth.procedural import band_limit_octaves, turbulence


def memory_table(big):
    """Peak memory per call of turbulence against the size of the result, frequencies 1 to 20000."""
    sizes = [(1024, 1024), (64, 64, 64)] + ([(2048, 2048), (128, 128, 128)] if big else [])
    turbulence((8, 8), rng=0)  # warm-up: imports, the BLAS controller
    rows = [memory_row(turbulence, size, frequency, band_limit_octaves(size, frequency))
            for size in sizes for frequency in (1, 8, 64, 512, 4096, 20000)]
    # few pixels, many octaves: the reliability issue's reproducers
    rows += [memory_row(turbulence, (48, 48), 26, octaves, octaves=octaves) for octaves in (10, 11)]
    if big:
        rows.append(memory_row(turbulence, (8192, 8192), 8, band_limit_octaves((8192, 8192), 8)))
    print_memory_table(rows)


def main():
    rep = start(__doc__, "turbulence", "memory table with 2048^2, 128^3 and turbulence(8192)", memory_table)
    if rep is None:
        return
    n = 1024
    freq = 8
    found, missing = peers()
    rows = []  # (case, library, seconds)

    # ---- 2-D, 1024^2, 8 octaves -----------------------------------------------------
    rows.append(("2-D 8 octaves", "texsynth turbulence f32",
                 best_of(lambda: turbulence((n, n), frequency=freq, octaves=8, dtype=np.float32, rng=0), rep)))
    rows.append(("2-D 8 octaves", "texsynth turbulence f64",
                 best_of(lambda: turbulence((n, n), frequency=freq, octaves=8, rng=0), rep)))
    coords2 = np.indices((n, n)).reshape(2, -1).astype(np.float32)
    if "pyfastnoiselite" in found:
        fnl = found["pyfastnoiselite"]
        gen8 = fastnoise_perlin(fnl, freq / n)
        gen8.fractal_type = fnl.FractalType.FractalType_FBm
        gen8.fractal_octaves = 8
        rows.append(("2-D 8 octaves", "pyfastnoiselite", best_of(lambda: gen8.gen_from_coords(coords2), rep)))
    if "noise" in found:
        pnoise2 = found["noise"].pnoise2
        xs = (coords2[1] * (freq / n)).astype(float).tolist()
        ys = (coords2[0] * (freq / n)).astype(float).tolist()
        rows.append(("2-D 8 octaves", "noise (pnoise2 per point)",
                     best_of(lambda: np.fromiter((pnoise2(x, y, 8) for x, y in zip(xs, ys)), float, count=n * n),
                             1)))
    if "vnoise" in found:
        vn = found["vnoise"].Noise(0)
        axis = np.arange(n) * (freq / n)
        rows.append(("2-D 8 octaves", "vnoise (grid_mode)",
                     best_of(lambda: vn.noise2(axis, axis, octaves=8), 1)))

    # ---- 3-D --------------------------------------------------------------------
    rows.append(("3-D 128^3 turbulence", "texsynth turbulence f32 (8 oct.)",
                 best_of(lambda: turbulence((128, 128, 128), frequency=freq, dtype=np.float32, rng=0), 1)))

    # ---- table ------------------------------------------------------------------------
    t = print_rows(rows, missing)
    print("\nratios (texsynth time / peer time; below 1 = texsynth faster)")
    ratio_row(t, "8-oct turbulence f32 / pyfastnoiselite 8-oct fBm", ("2-D 8 octaves", "texsynth turbulence f32"),
              ("2-D 8 octaves", "pyfastnoiselite"), 1.5, "<=")
    ratio_row(t, "8-oct turbulence f32 / noise pnoise2 8-oct", ("2-D 8 octaves", "texsynth turbulence f32"),
              ("2-D 8 octaves", "noise (pnoise2 per point)"), 0.5, "<=")
    ratio_row(t, "8-oct turbulence f32 / vnoise 8-oct", ("2-D 8 octaves", "texsynth turbulence f32"),
              ("2-D 8 octaves", "vnoise (grid_mode)"), 0.5, "<=")


if __name__ == "__main__":
    main()
