"""Geometric texture analogies: a 96^3 target in at most 3 minutes, against the grid-axes reference.

Run: python benchmarks/bench_geometry_analogies.py [--size 96] [--seeds 1]

The training pair is ``texsynth.data.volume("cylinder", 48)`` and ``"grooved_cylinder"`` (radius 14.4, 8
grooves 4.3 voxels wide and 2.9 deep), 32 slices of each, the field along the axis; the target
``texsynth.data.volume("torus", size)`` (tube radius 0.13 size), the field along its tube. Defaults: two
levels, 5^3 neighbourhoods, a band of 4 voxels. Side by side in the same run, the reference: the same
search with ``alignment="axes"`` (neighbourhoods on the grid's axes, voxels swept along the depth axis: image
analogies on a voxel grid, without the paper's frames). Printed per run: wall time and its stages, the
process's CPU time (the machine is shared), band voxels, candidates and wavefronts, peak memory, and the
quality: the angle between the grooves and the target's field (from the relief's structure tensor on the
surface) with the relief's orientation coherence (0-1), the share of the surface in a groove (relief above
one voxel) against the example's, and the Wasserstein-1 distance of the relief's distribution to the
example's, against a plain copy's (b' = b).
"""

import argparse
import resource
import time

import numpy as np

from texsynth import data
from texsynth.geometry import as_distance_field, geometry_analogies

TARGET = 180.0  # seconds for a 96^3 target


def relief(plain, textured, margin):
    plain, textured = as_distance_field(plain), as_distance_field(textured)
    shell = np.abs(plain) <= 0.5
    inner = np.zeros_like(shell)
    inner[margin:-margin, margin:-margin, margin:-margin] = True
    return (textured - plain)[shell & inner]


def orientation(plain, textured, field):
    """Degrees between the grooves and ``field``, and the relief's orientation coherence (see the tests)."""
    plain, textured = as_distance_field(plain), as_distance_field(textured)
    voxels = np.argwhere(np.abs(plain) <= 0.5)
    g = np.stack(np.gradient(np.clip(textured - plain, -3, 3)), -1)[tuple(voxels.T)]
    n = np.stack(np.gradient(plain), -1)[tuple(voxels.T)]
    n /= np.linalg.norm(n, axis=1, keepdims=True)
    t = field(voxels.astype(float))
    t -= np.sum(t * n, axis=1, keepdims=True) * n
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    gt, gb = np.sum(g * t, axis=1), np.sum(g * np.cross(n, t), axis=1)
    jtt, jbb, jtb = gt @ gt, gb @ gb, gt @ gb
    return 90.0 - abs(0.5 * np.degrees(np.arctan2(2 * jtb, jtt - jbb))), float(np.hypot(jtt - jbb, 2 * jtb) /
                                                                                 (jtt + jbb))


def w1(x, y):
    q = np.linspace(0.005, 0.995, 199)
    return float(np.mean(np.abs(np.quantile(x, q) - np.quantile(y, q))))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, default=96)
    parser.add_argument("--seeds", type=int, default=1)
    args = parser.parse_args()
    a, a_prime = data.volume("cylinder", 48)[:32], data.volume("grooved_cylinder", 48)[:32]
    b = data.volume("torus", args.size)
    c = (args.size - 1) / 2

    def along_tube(p):
        return np.stack([np.zeros(len(p)), -(p[:, 2] - c), p[:, 1] - c], 1)

    example = relief(a, a_prime, 5)
    plain_w1 = w1(relief(b, b, 2), example)
    geometry_analogies(a, a_prime, data.volume("cylinder", 16), field_a=(1, 0, 0), field_b=(1, 0, 0), levels=1)
    print(f"pair {a.shape}, target torus {b.shape}; example: grooved share {np.mean(example > 1):.3f}; "
          f"plain copy's relief W1 {plain_w1:.3f}")
    for seed in range(args.seeds):
        for alignment in ("field", "axes"):
            t, cpu = time.perf_counter(), time.process_time()
            out, info = geometry_analogies(a, a_prime, b, field_a=(1, 0, 0), field_b=along_tube, alignment=alignment,
                                           rng=seed, return_info=True)
            seconds, cpu = time.perf_counter() - t, time.process_time() - cpu
            stages = ", ".join(f"{k} {v:.1f}" for k, v in info.stage_seconds.items())
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            verdict = "" if alignment == "axes" else ("  target met" if seconds <= TARGET else "  target MISSED")
            error, coherence = orientation(b, out, along_tube)
            ours = relief(b, out, 2)
            print(f"seed {seed} alignment={alignment:5s} {seconds:6.1f} s, CPU {cpu:.1f} s ({stages}; "
                  f"{len(info.voxels)} band voxels, {info.n_candidates} candidates, {info.wavefronts} wavefronts; "
                  f"peak RSS {peak:.0f} MiB){verdict}")
            print(f"    grooves {error:5.1f} deg from the field, coherence {coherence:.2f}; grooved share "
                  f"{np.mean(ours > 1):.3f}; relief W1 {w1(ours, example):.3f} (plain copy {plain_w1:.3f})")


if __name__ == "__main__":
    main()
