"""Feature-aligned texturing: a 50,000-vertex surface in at most 3 minutes, beside a smooth field ignoring its ridges.

Run: python benchmarks/bench_feature_aligned.py [--n-vertices 50000] [--seeds 1] [--no-planar]

The surface is ``creased_mesh``: a flattened sphere with four sharp meridian crests (its ridges, which a
smooth field circling the short axis crosses at right angles), ~50,000 vertices, retiled to ``--n-vertices``;
the exemplar ``texsynth.data.load("brick")`` (77 x 107, mortar joints as its feature lines), 3 levels. Side
by side in the same run, the reference: ``texsynth.synthesize_surface`` with the smooth field of the same
mesh and exemplar (the synthesis without the curves, the field constraints and the feature channel).
Printed per run: wall time and its stages, and ``curve_alignment`` (the angle in degrees between the
texture's dominant orientation within 3 vertex spacings of each ridge and the ridge, averaged over the
ridges: 0 along, 90 across). The planar form (``feature_aligned_texture``, 256^2 from the same exemplar with two
rings as the curves) is timed beside ``texsynth.optimize_texture`` of the same size.
"""

import argparse
import resource
import time

import numpy as np

import texsynth
from texsynth.optimization import feature_aligned_texture
from texsynth.surface import curve_alignment, feature_aligned_surface, salient_curves

TARGET = 180.0  # seconds for 50,000 vertices


def creased_mesh(n_vertices):
    """A flattened sphere (z times 0.7) with four sharp crests along the meridians at 0, 90, 180, 270 degrees."""
    ball = texsynth.surface.sphere(n_vertices)
    v = ball.vertices
    phi = np.arctan2(v[:, 1], v[:, 0])
    v = v * (1 + 0.25 * (1 - np.abs(np.sin(2 * phi))) * np.sqrt(np.clip(1 - v[:, 2] ** 2, 0, 1)))[:, None]
    v[:, 2] *= 0.7
    return texsynth.surface.Mesh(v, ball.faces)


def rings(size):
    """Two concentric circles as a line image."""
    curves = np.zeros((size, size), bool)
    t = np.linspace(0, 2 * np.pi, 16 * size)
    c = (size - 1) / 2
    for r in (0.2 * size, 0.4 * size):
        curves[np.rint(c + r * np.sin(t)).astype(int), np.rint(c + r * np.cos(t)).astype(int)] = True
    return curves


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n-vertices", type=int, default=50000)
    parser.add_argument("--seeds", type=int, default=1)
    parser.add_argument("--no-planar", action="store_true")
    args = parser.parse_args()
    exemplar = texsynth.data.load("brick")
    mesh = creased_mesh(args.n_vertices)
    curves = salient_curves(mesh)
    print(f"mesh {len(mesh.vertices)} vertices, {curves.n_curves} ridge curves through {len(curves.vertices)} "
          f"vertices; exemplar brick {exemplar.shape}; retiled to {args.n_vertices}")
    for seed in range(args.seeds):
        for name in ("feature_aligned", "smooth field"):
            t = time.perf_counter()
            if name == "smooth field":
                out, info = texsynth.synthesize_surface(mesh, exemplar, n_vertices=args.n_vertices, rng=seed,
                                                        return_info=True)
            else:
                out, info = feature_aligned_surface(mesh, exemplar, n_vertices=args.n_vertices, rng=seed,
                                                    return_info=True)
            seconds = time.perf_counter() - t
            angle = curve_alignment(out, curves)
            stages = ", ".join(f"{k} {v:.1f}" for k, v in info.stage_seconds.items())
            peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
            verdict = "" if name == "smooth field" else ("  target met" if seconds <= TARGET else "  target MISSED")
            print(f"seed {seed} {name:15s} {seconds:6.1f} s ({stages}); {len(out.vertices)} vertices; "
                  f"angle to the ridges {angle:5.1f} deg; peak RSS so far {peak:.0f} MiB{verdict}")
    if not args.no_planar:
        lines = rings(256)
        for name in ("feature_aligned_texture", "optimize_texture"):
            t = time.perf_counter()
            if name == "optimize_texture":
                texsynth.optimize_texture(exemplar, lines.shape, rng=0)
                stages = ""
            else:
                _, info = feature_aligned_texture(exemplar, lines, rng=0, return_info=True)
                stages = " (" + ", ".join(f"{k} {v:.1f}" for k, v in info.stage_seconds.items()) + ")"
            print(f"planar 256^2 {name:24s} {time.perf_counter() - t:6.1f} s{stages}")


if __name__ == "__main__":
    main()
