"""Mesh previews (issue 20): render_mesh of a 100,000-face mesh at 512^2 (four views of 256^2).

Run: python benchmarks/bench_render.py [--repeats 5] [--save FOLDER] [--figure PNG]

Target: <= 2 s for the 512^2 preview of a 100,000-face mesh. Timed: a bumpy sphere of 100,820
faces (closed: the faces turned away are skipped), the same mesh with its faces split into two
sheets (open: every face is rasterised and lit on both sides), with vertex colours, with a uv
texture, orthographic, and the Stanford Bunny (69,666 faces, needs texsynth[mesh]). "cold" is
the first render of a freshly built Mesh (it includes as_mesh's checks and the normals and
adjacency, computed once and cached); "warm" is the median of the repeats on the same object.
With --save, the previews are written as PNGs to look at; --figure writes the figure of
docs/methods/surfaces.md (a textured sphere, a coloured bumpy sphere, a torus, the bunny).
"""

import argparse
import os
import platform
import statistics
import time
from pathlib import Path

import numpy as np

from texsynth import data
from texsynth.io import save_image
from texsynth.surface import Mesh, bumpy, render_mesh, scanned_mesh, sphere, torus


def _timed(build, repeats, **options):
    mesh = build()
    start = time.perf_counter()
    image = render_mesh(mesh, 512, **options)
    cold = time.perf_counter() - start
    warm = []
    for _ in range(repeats):
        start = time.perf_counter()
        render_mesh(mesh, 512, **options)
        warm.append(time.perf_counter() - start)
    return image, cold, statistics.median(warm), len(mesh.faces)


def spherical_uv(mesh):
    """Longitude/latitude uv per face corner; faces across the date line get u > 1 (the texture repeats)."""
    x, y, z = (mesh.vertices / np.linalg.norm(mesh.vertices, axis=1, keepdims=True)).T
    uv = np.stack([np.arctan2(y, x) / (2 * np.pi) + 0.5, np.arcsin(np.clip(z, -1, 1)) / np.pi + 0.5], axis=1)
    uv = uv[mesh.faces]
    across = uv[:, :, 0].max(axis=1) - uv[:, :, 0].min(axis=1) > 0.5
    uv[:, :, 0] += across[:, None] & (uv[:, :, 0] < 0.5)
    return uv


def figure(path):
    ball = sphere(10242)
    textured = ball.with_texture(spherical_uv(ball), data.load("brick"))
    lumpy = bumpy(10242, rng=1)
    coloured = lumpy.with_colors(0.5 + 0.5 * lumpy.vertex_normals)
    meshes = [textured, coloured, torus(4000), scanned_mesh()]
    views = [(30, 20), (30, 20), (30, 35), (-60, 10)]
    tiles = [render_mesh(m, 256, views=[v]) for m, v in zip(meshes, views)]
    save_image(path, np.concatenate(tiles, axis=1), overwrite=True)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--save", type=Path, default=None)
    parser.add_argument("--figure", type=Path, default=None)
    args = parser.parse_args()
    if args.figure:
        figure(args.figure)
    print(f"python {platform.python_version()}, numpy {np.__version__}, {os.cpu_count()} cores, "
          f"load average {os.getloadavg()[0]:.1f}")
    base = bumpy(50_000, rng=0)
    rng = np.random.default_rng(0)
    texture = rng.random((256, 256, 3))

    def opened():  # drop one face: the mesh has a boundary, so nothing is culled
        return Mesh(base.vertices, base.faces[1:])

    cases = {
        "bumpy sphere, grey, perspective": (lambda: Mesh(base.vertices, base.faces), {}),
        "bumpy sphere, grey, orthographic": (lambda: Mesh(base.vertices, base.faces), {"projection": "orthographic"}),
        "bumpy sphere minus one face (open: no culling)": (opened, {}),
        "bumpy sphere, vertex colours": (lambda: Mesh(base.vertices, base.faces,
                                                      colors=(base.vertices + 1.2) / 2.4), {}),
        "bumpy sphere, 256^2 texture through uv": (lambda: Mesh(base.vertices, base.faces,
                                                                uv=rng.random((len(base.faces), 3, 2)),
                                                                texture=texture), {}),
    }
    try:
        bunny = scanned_mesh()
        cases["Stanford Bunny"] = (lambda: Mesh(bunny.vertices, bunny.faces), {})
    except ModuleNotFoundError as exc:
        print(f"(no Stanford Bunny: {exc})")
    print(f"{'mesh':50s} {'faces':>8s} {'cold s':>8s} {'warm s':>8s}")
    for name, (build, options) in cases.items():
        image, cold, warm, faces = _timed(build, args.repeats, **options)
        print(f"{name:50s} {faces:8d} {cold:8.3f} {warm:8.3f}")
        if args.save:
            args.save.mkdir(parents=True, exist_ok=True)
            slug = "".join(c if c.isalnum() else "_" for c in name)[:40]
            save_image(args.save / f"{slug}.png", image, overwrite=True)


if __name__ == "__main__":
    main()
