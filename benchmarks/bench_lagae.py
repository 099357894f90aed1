"""Geometry synthesis by example: a 128^3 distance field from a 48^3 example in at most 2 minutes.

Run: python benchmarks/bench_lagae.py [--size 128] [--seeds 1]

The example is ``texsynth.data.volume("pebbles")`` (48^3, 26 separate spheres of radii 3-5 voxels), as occupancy;
the output 128^3 with the defaults (block 16, overlap 4, candidate stride "auto": 2, a 3-D minimum cut per
block). Also timed: ``levels=2`` (a coarse pass first) and ``copy_elements=True`` (the paper's element
copies). Side by side in the same run, the reference: a random arrangement of the same blocks with the same
cuts (``placement="random"``), which skips the search. Printed per run: wall time and its stages, peak
memory of the process (``ru_maxrss``) against the output's size, the interior fragments (occupancy
components not touching the border and smaller than half the example's smallest sphere: cut elements)
and the marching-cubes mesh's size and time.
"""

import argparse
import resource
import time

import numpy as np
from scipy import ndimage

from texsynth import data
from texsynth.geometry import sdf_to_mesh, synthesize_geometry

TARGET = 120.0  # seconds for 128^3 from 48^3


def fragments(sdf, smallest):
    labels, n = ndimage.label(sdf < 0)
    border = np.unique(np.concatenate([labels[[0, -1]].ravel(), labels[:, [0, -1]].ravel(),
                                       labels[:, :, [0, -1]].ravel()]))
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    return n, sum(1 for lab in range(1, n + 1) if lab not in border and sizes[lab] < smallest)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--seeds", type=int, default=1)
    args = parser.parse_args()
    example = data.volume("pebbles")
    labels, _ = ndimage.label(example)
    smallest = np.bincount(labels.ravel())[1:].min() / 2
    synthesize_geometry(example, 24, rng=0)  # warm-up: imports, first-touch pages
    print(f"example {example.shape} occupancy, output {args.size}^3 "
          f"({args.size ** 3 * 8 / 2**20:.0f} MiB as float64)")
    for seed in range(args.seeds):
        for name, kw in [("overlap", {}), ("levels=2", {"levels": 2}), ("elements", {"copy_elements": True}),
                         ("random", {"placement": "random"})]:
            t = time.perf_counter()
            sdf, info = synthesize_geometry(example, args.size, rng=seed, return_info=True, **kw)
            seconds = time.perf_counter() - t
            t = time.perf_counter()
            vertices, faces = sdf_to_mesh(sdf)
            mesh_seconds = time.perf_counter() - t
            n, cut = fragments(sdf, smallest)
            stages = ", ".join(f"{k} {v:.2f}" for k, v in info.stage_seconds.items())
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            verdict = "" if name == "random" else ("  target met" if seconds <= TARGET else "  target MISSED")
            print(f"seed {seed} {name:8s} {seconds:6.1f} s ({stages}; {len(info.sources)} blocks of "
                  f"{info.block}, overlap {info.overlap}, stride {info.candidate_stride}){verdict}")
            print(f"    components {n}, interior fragments {cut}; mesh {len(vertices)} vertices, "
                  f"{len(faces)} faces in {mesh_seconds:.1f} s; peak RSS so far {peak:.0f} MiB")


if __name__ == "__main__":
    main()
