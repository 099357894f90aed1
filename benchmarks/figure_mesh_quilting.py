"""Figures of docs/methods/mesh_quilting.md: swatches of separate elements quilted over surfaces.

Run: python benchmarks/figure_mesh_quilting.py [--out docs/_static]

- ``mesh_quilting_swatches.png``: the three swatches of ``texsynth.data.swatch`` (rivets, pebbles, spikes),
  16 x 16 units each, over a grey base plate (the plate is drawn for the picture only).
- ``mesh_quilting_bumpy_<name>.png``: each swatch quilted over ``texsynth.surface.bumpy(10242, rng=0)``
  (20,480 faces) at the unit length that would put 200 elements there at the swatch's density, four views.
- ``mesh_quilting_torus.png``: the spikes over a torus (major radius 1, minor 0.4), four views.
- ``mesh_quilting_plane.png``: rivets (in rows) over a flat 24 x 24 plane, from above: geometry matching
  (left) and random offsets (``placement="random"``, right).
All rendered by ``texsynth.render_mesh``; the surface and the elements are joined into one mesh for it.
"""

import argparse
import os

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

import texsynth
from texsynth.data import swatch
from texsynth.geometry import mesh_quilting


def joined(base, elements):
    v, f = base
    return np.vstack([v, elements[0]]), np.vstack([f, elements[1] + len(v)])


def plate(side, n=2):
    x, y = np.meshgrid(np.linspace(0, side, n), np.linspace(0, side, n))
    q = np.arange(n * n).reshape(n, n)[:-1, :-1].ravel()
    return np.c_[x.ravel(), y.ravel(), np.zeros(x.size)], np.r_[np.c_[q, q + 1, q + n + 1], np.c_[q, q + n + 1, q + n]]


def save(image, out, name):
    path = os.path.join(out, f"mesh_quilting_{name}.png")
    texsynth.io.save_image(path, image, overwrite=True)
    print(path, os.path.getsize(path) // 1024, "kB")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    names = ("rivets", "pebbles", "spikes")
    below = plate(16.0)
    below = (below[0] - [0, 0, 0.01], below[1])  # just under the elements' bottoms, for the picture
    save(np.concatenate([texsynth.render_mesh(joined(below, swatch(n)), 400, views=[(-60, 40)]) for n in names],
                        axis=1), args.out, "swatches")
    bumpy = texsynth.surface.bumpy(10242, rng=0)
    base = (bumpy.vertices, bumpy.faces)
    a, b, c = (bumpy.vertices[bumpy.faces[:, i]] for i in range(3))
    area = 0.5 * np.linalg.norm(np.cross(b - a, c - a), axis=1).sum()
    for name in names:
        sw = swatch(name)
        edges = (sw[1][:, :2].ravel(), sw[1][:, 1:].ravel())
        n_swatch = connected_components(coo_matrix((np.ones(2 * len(sw[1])), edges), shape=(len(sw[0]),) * 2),
                                        directed=False)[0]
        unit_length = float(np.sqrt(n_swatch * area / (200 * 16.0 ** 2)))
        out = mesh_quilting(sw, base, unit_length=unit_length, rng=0, return_info=True)
        info = out[2]
        print(f"{name}: unit_length {unit_length:.4f}, {len(info.element_sources)} elements, {len(info.patch_centers)} patches, "
              f"{info.n_duplicates} duplicates, {info.n_collisions} collisions, {info.n_folded} folded, "
              f"{info.seconds:.1f} s")
        save(texsynth.render_mesh(joined(base, out[:2]), 800, views=4), args.out, f"bumpy_{name}")
    ring = texsynth.surface.torus(10000, major_radius=1.0, minor_radius=0.4)
    out = mesh_quilting(swatch("spikes"), ring, unit_length=0.12, rng=0, return_info=True)
    print(f"torus: {len(out[2].element_sources)} elements in {out[2].seconds:.1f} s")
    save(texsynth.render_mesh(joined((ring.vertices, ring.faces), out[:2]), 800,
                              views=[(0, 30), (90, 60), (200, 15), (300, -40)]), args.out, "torus")
    ground = plate(24.0, 49)
    images = []
    for placement in ("matched", "random"):
        out = mesh_quilting(swatch("rivets"), ground, unit_length=1.0, placement=placement, rng=0, return_info=True)
        print(f"plane, {placement}: {len(out[2].element_sources)} elements")
        images.append(texsynth.render_mesh(joined(ground, out[:2]), 500, views=[(-90, 90)],
                                           projection="orthographic"))
    save(np.concatenate(images, axis=1), args.out, "plane")


if __name__ == "__main__":
    main()
