"""Portilla-Simoncelli synthesis: time of 256x256 grey, 50 iterations (target <= 30 s).

Run: python benchmarks/bench_portilla_simoncelli.py [--repeat 2] [--size 256]

Rows: the statistics of the exemplar alone; one ``ps_step`` (one projection iteration, what
Ruiters et al. interleave), on the whole image and with ``mask=`` on its left half; the whole synthesis (analysis + 50 iterations, paper defaults: 4
scales, 4 orientations, 7x7 neighbourhood) in grey and in colour; and, in the same run for
scale, Heeger-Bergen (5 iterations) on the same exemplar. Best of ``--repeat`` runs, wall clock.
Also printed: the final SNR of every statistics group (dB), which says the time buys a match.

No other implementation of Portilla-Simoncelli runs here: the authors' is MATLAB, and
plenoptic's (PyTorch) would need torch, which is not a dependency of this project.
"""

import argparse
import platform
import time
from pathlib import Path

import numpy as np

from texsynth.io import load_image
from texsynth.statistical import SNR_GROUPS, portilla_simoncelli, ps_statistics, ps_step

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def best_time(fn, repeat):
    best, out = np.inf, None
    for _ in range(repeat):
        start = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - start)
    return best, out


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=256)
    parser.add_argument("--iterations", type=int, default=50)
    parser.add_argument("--repeat", type=int, default=2)
    args = parser.parse_args()
    n, iters = args.size, args.iterations
    grey = load_image(TEXTURES / "lcv" / "metal.pgm")
    grey = np.tile(grey, (n // grey.shape[0] + 1, n // grey.shape[1] + 1))[:n, :n]
    colour = load_image(TEXTURES / "embark" / "1.jpg")[:n, :n]

    rows = []
    t, stats = best_time(lambda: ps_statistics(grey), args.repeat)
    rows.append((f"ps_statistics {n}x{n} grey", t))
    noise = np.random.default_rng(0).random((n, n))
    ps_step(noise, stats)  # warm the pyramid cache, as inside a synthesis loop
    t, _ = best_time(lambda: ps_step(noise, stats), max(args.repeat, 3))
    rows.append((f"ps_step {n}x{n} grey (one iteration)", t))
    half = np.zeros((n, n), bool)
    half[:, : n // 2] = True
    t, _ = best_time(lambda: ps_step(noise, stats, mask=half), max(args.repeat, 3))
    rows.append((f"ps_step {n}x{n} grey, mask= left half", t))
    t, (out, info) = best_time(lambda: portilla_simoncelli(grey, iterations=iters, rng=0, return_info=True),
                               args.repeat)
    rows.append((f"portilla_simoncelli {n}x{n} grey, {iters} iterations", t))
    t_colour, (_, info_colour) = best_time(
        lambda: portilla_simoncelli(colour, iterations=iters, rng=0, return_info=True), 1)
    rows.append((f"portilla_simoncelli {colour.shape[0]}x{colour.shape[1]} colour, {iters} iterations", t_colour))
    try:
        from texsynth.statistical import heeger_bergen

        t, _ = best_time(lambda: heeger_bergen(grey, rng=0), args.repeat)
        rows.append((f"heeger_bergen {n}x{n} grey, 5 iterations (for scale)", t))
    except ImportError:
        pass

    print(f"# Portilla-Simoncelli benchmark - Python {platform.python_version()}, numpy {np.__version__}, "
          f"best of {args.repeat}")
    print(f"| {'case':<55} | {'time (s)':>9} |")
    print(f"|{'-' * 57}|{'-' * 11}|")
    for name, seconds in rows:
        print(f"| {name:<55} | {seconds:>9.2f} |")
    target = "met" if rows[3][1] <= 30 else "MISSED"
    print(f"\ntarget <= 30 s for {n}x{n} grey, {iters} iterations: {target}")
    print("\nfinal SNR (dB) per statistics group, grey / colour:")
    for g in SNR_GROUPS:
        print(f"  {g:<30} {info.snr[g][-1]:7.1f} / {info_colour.snr[g][-1]:7.1f}")


if __name__ == "__main__":
    main()
