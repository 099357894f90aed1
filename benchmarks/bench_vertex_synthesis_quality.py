"""Vertex synthesis on structured photographs: a flat patch, read back as an image and measured.

Run: python benchmarks/bench_vertex_synthesis_quality.py [--seeds 0 1] [--preview DIR] [--preset default] [--order sweep]
     [--passes N]   (from the repository root)

A 1 x 1 square (a 48 x 48 grid of vertices) is retiled to 20,000 vertices and textured by
:func:`texsynth.synthesize_surface` (3 levels, a constant field along x) from the 128 x 128
top-left crop of three structured photographs (bricks, paving, cobblestones); the vertex
colours are read back as an image (the nearest vertex at each point of a grid of spacing
``pixel_size``, 118 x 118) and compared with the exemplar: ``texsynth.metrics.spectrum_distance``
over all wavelengths and above 16 pixels (the arrangement of the elements), completeness and
texture energy of 8 x 8 patches. ``--preview DIR`` writes each image beside its exemplar, 3x enlarged.
The numbers of docs/methods/vertex_synthesis.md ("Structured textures") come from this script.
"""

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.spatial import cKDTree

import texsynth
from texsynth import metrics
from texsynth.io import load_image, save_image
from texsynth.surface import as_mesh

ROOT = Path(__file__).resolve().parents[1]
PHOTOS = {"bricks": ROOT.parent / "shared" / "textures" / "rohitrango" / "t1.png",
          "paving": ROOT.parent / "shared" / "textures" / "rohitrango" / "t13.png",
          "cobblestones": ROOT / "benchmarks" / "photos" / "cobblestones_1.png"}


def square(n=48):
    """The unit square in the z = 0 plane, facing +z, as an ``n x n`` grid of vertices."""
    y, x = np.mgrid[0:n, 0:n] / (n - 1)
    vertices = np.stack([x.ravel(), -y.ravel(), np.zeros(n * n)], axis=1)
    i = (np.arange(n - 1)[:, None] * n + np.arange(n - 1)[None, :]).ravel()
    faces = np.concatenate([np.stack([i, i + n, i + n + 1], 1), np.stack([i, i + n + 1, i + 1], 1)])
    return as_mesh((vertices, faces))


def flatten(out, pixel_size):
    """The vertex colours at a grid of spacing ``pixel_size`` inside the square (5 % margin)."""
    side = int(0.9 / pixel_size)
    r, c = np.mgrid[0:side, 0:side]
    points = np.stack([0.05 + c.ravel() * pixel_size, -(0.05 + r.ravel() * pixel_size), np.zeros(side * side)], 1)
    _, near = cKDTree(out.vertices).query(points)
    return out.colors[near].reshape(side, side, -1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", type=int, nargs="+", default=[0, 1])
    parser.add_argument("--preset", default="default")
    parser.add_argument("--order", default="auto", help="the visiting order (default: the preset's)")
    parser.add_argument("--passes", type=int, default=None, help="passes per level (default: the preset's)")
    parser.add_argument("--preview", default=None)
    args = parser.parse_args()
    mesh = square()
    for seed in args.seeds:
        for name, path in PHOTOS.items():
            ex = np.ascontiguousarray(load_image(path)[:128, :128, :3])
            start = time.perf_counter()
            schedule = texsynth.SurfaceSchedule(levels=3, order=args.order,
                                                passes="auto" if args.passes is None else args.passes)
            out, info = texsynth.synthesize_surface(mesh, ex, n_vertices=20000, schedule=schedule, preset=args.preset,
                                                    field=lambda p: np.tile([1.0, 0, 0], (len(p), 1)), rng=seed,
                                                    return_info=True)
            seconds = time.perf_counter() - start
            image = flatten(out, info.pixel_size)
            print(f"{name} seed {seed}: spectrum distance {metrics.spectrum_distance(image, ex):.3f} "
                  f"(above 16 px {metrics.spectrum_distance(image, ex, min_wavelength=16):.3f}), completeness "
                  f"{metrics.completeness(image, ex, patch_size=8, stride=4):.4f}, texture energy "
                  f"{metrics.texture_energy(image, ex, patch_size=8, stride=4):.4f}; {seconds:.1f} s", flush=True)
            if args.preview:
                side = image.shape[0]
                both = np.zeros((max(side, 128), side + 8 + 128, 3))
                both[:side, :side], both[:128, side + 8:] = image, ex
                folder = Path(args.preview)
                folder.mkdir(parents=True, exist_ok=True)
                save_image(folder / f"surface_{name}_{seed}.png", np.kron(both, np.ones((3, 3, 1))), overwrite=True)


if __name__ == "__main__":
    main()
