"""Benchmark of reaction-diffusion (texsynth.procedural): Turk's system and Gray-Scott at 256^2, 10,000 steps.

Target of the procedural issue: each at most 5 s (float32, the default). No peer
package: the figures are absolute. ``--quick`` runs 2,000 steps and extrapolates.

Run:  python benchmarks/bench_reaction_diffusion.py [--quick]
"""

from __future__ import annotations

import argparse
import platform
import time

import numpy as np

from texsynth.procedural import gray_scott, reaction_diffusion


def timed(fn):
    """Wall time of one call after a warm-up on a tiny grid (imports, first-touch page faults)."""
    fn((16, 16), 10)
    t0 = time.perf_counter()
    fn((256, 256), None)
    return time.perf_counter() - t0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="2000 steps, extrapolated to 10,000")
    args = parser.parse_args()
    print(f"texsynth.procedural reaction-diffusion benchmark -- {platform.python_version()}, {platform.machine()}, "
          f"numpy {np.__version__}")
    steps = 2000 if args.quick else 10000
    print(f"\n{'case':24s} {'library':36s} {'time (ms)':>10s}")
    for name, fn in (("reaction_diffusion", reaction_diffusion), ("gray_scott", gray_scott)):
        seconds = timed(lambda size, n, fn=fn: fn(size, steps=n or steps, rng=0))
        print(f"{f'RD 256^2 x {steps}':24s} {f'texsynth {name} f32':36s} {seconds * 1e3:10.1f}")
        s = seconds * 10000 / steps
        print(f"{'RD 256^2 x 10000 steps <= 5 s: ' + name:58s} {s:8.2f} s   {'PASS' if s <= 5 else 'FAIL'}"
              + ("  (extrapolated)" if steps != 10000 else ""))


if __name__ == "__main__":
    main()
