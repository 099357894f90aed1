"""Progressively-variant textures on surfaces (issue 36, item 2): progressive_surface at the issue's size.

Run: python benchmarks/bench_progressive_surface.py [--vertices 50000] [--preview DIR]
     (from the repository root)

``texsynth.surface._progressive_surface.progressive_surface``: a sphere retiled to ``--vertices`` vertices
(default 50,000), 3 levels, two 128 x 128 colour exemplars made here (:func:`exemplars`: small dark
spots on a light ground, and large spots on a darker ground), ``blend`` running from 0 at the south
pole to 1 at the north pole, seed 0; beside it, in the same run, the reference: plain
``texsynth.synthesize_surface`` of the first exemplar at the same size. Wall time per stage.
Target: <= 180 s (3 minutes).

``--preview DIR`` also renders both results (texsynth.surface.render_mesh) into DIR.
"""

import argparse

import numpy as np

import texsynth
from _timing import timed_stages
from bench_vertex_synthesis import save_preview
from texsynth.surface import sphere
from texsynth.surface import progressive_surface


def spots(size, spacing, radius, spot, ground, seed):
    """A toroidal ``size`` x ``size`` RGB image of round spots of colour ``spot`` on ``ground``, on a jittered grid."""
    rng = np.random.default_rng(seed)
    rows, cols = np.mgrid[0:size, 0:size]
    inside = np.zeros((size, size), bool)
    for y in range(spacing // 2, size, spacing):
        for x in range(spacing // 2, size, spacing):
            cy, cx = y + rng.uniform(-2, 2), x + rng.uniform(-2, 2)
            dy = (rows - cy + size / 2) % size - size / 2
            dx = (cols - cx + size / 2) % size - size / 2
            r = radius * rng.uniform(0.85, 1.15)
            inside |= dy ** 2 + dx ** 2 <= r ** 2
    image = np.where(inside[..., None], np.array(spot), np.array(ground))
    return np.clip(image + 0.04 * rng.standard_normal(image.shape), 0, 1)


def exemplars(size=128):
    """The two exemplars: small dark brown spots on beige, and large grey-green spots on a slate ground."""
    return (spots(size, 16, 3.5, (0.30, 0.18, 0.10), (0.88, 0.80, 0.62), 0),
            spots(size, 24, 7.5, (0.55, 0.70, 0.45), (0.25, 0.28, 0.33), 1))


def poles(points):
    """``blend``: 0 at the south pole, 1 at the north pole of the unit sphere."""
    return np.clip((points[:, 2] + 1) / 2, 0, 1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vertices", type=int, default=50000)
    parser.add_argument("--preview", default=None)
    args = parser.parse_args()
    a, b = exemplars()
    schedule = texsynth.SurfaceSchedule(levels=3)

    out, info, total, stages = timed_stages(lambda: progressive_surface(
        sphere(10242), a, b, poles, n_vertices=args.vertices, schedule=schedule, rng=0, return_info=True))
    ref, ref_info, ref_total, ref_stages = timed_stages(lambda: texsynth.synthesize_surface(
        sphere(10242), a, n_vertices=args.vertices, schedule=schedule, rng=0, return_info=True))
    print("| method | vertices | seconds | stages |")
    print("|---|---|---|---|")
    print(f"| progressive_surface (two exemplars, mask then texture) | {len(out.vertices)} | {total:.1f} | {stages} |")
    print(f"| synthesize_surface (one exemplar, reference) | {len(ref.vertices)} | {ref_total:.1f} | {ref_stages} |")
    verdict = "met" if total <= 180 else "NOT met"
    print(f"\ndocs/benchmarks.md: progressive_surface, sphere retiled to {len(out.vertices)} vertices, 3 levels, two "
          f"128² exemplars: {total:.1f} s (target <= 180 s: {verdict}); synthesize_surface of one exemplar "
          f"{ref_total:.1f} s")
    if args.preview:
        save_preview(args.preview, "progressive_surface.png", out)
        save_preview(args.preview, "progressive_surface_reference.png", ref)


if __name__ == "__main__":
    main()
