"""Figures of docs/methods/lagae.md: geometry synthesised from example distance fields, rendered as meshes.

Run: python benchmarks/figure_lagae.py [--out docs/_static]

Two examples are made here (no data file):

- ``pebbles``: a 48^3 volume of separate spheres of random radii 3-5 voxels (a 3-D texture of elements),
  synthesised to 64^3 (the figure; ``bench_lagae.py`` times 128^3);
- ``plate``: a 16 x 48 x 48 riveted plate: a 4-voxel slab with hemispherical rivets, cones (spikes) and
  two grooves along its width, synthesised to 16 x 112 x 112 (one layer of blocks: quilting of a relief).

``lagae_pebbles.png`` shows the example's mesh, the synthesis's mesh, the paper's second output (the
example's whole pebbles copied at the matched blocks, ``copy_elements=True``) and a random arrangement of
the same blocks with the same cuts (``placement="random"``); ``lagae_plate.png`` the example, the
synthesis and the random arrangement (the plate's rivets and spikes are joined to the slab: no separate
elements to copy). All rendered by ``texsynth.render_mesh``, one view each.
"""

import argparse
import os

import numpy as np

import texsynth
from texsynth.geometry._lagae import sdf_to_mesh, synthesize_geometry


def pebbles(n=48, count=26, seed=1):
    """Separate spheres of random radii 3-5 voxels, at least 2 voxels apart, in an ``n^3`` occupancy volume."""
    rng = np.random.default_rng(seed)
    z, y, x = np.indices((n, n, n))
    occ = np.zeros((n, n, n), bool)
    centres, radii = [], []
    while len(centres) < count:
        c, r = rng.uniform(0, n, 3), rng.uniform(3, 5)
        if all(np.linalg.norm(c - c2) > r + r2 + 2 for c2, r2 in zip(centres, radii)):
            centres.append(c)
            radii.append(r)
            occ |= (z - c[0]) ** 2 + (y - c[1]) ** 2 + (x - c[2]) ** 2 < r * r
    return occ


def plate(n=48, depth=16, seed=2):
    """A slab 4 voxels thick with rivets (hemispheres), spikes (cones) and two grooves, as occupancy."""
    rng = np.random.default_rng(seed)
    z, y, x = np.indices((depth, n, n)).astype(float)
    occ = z < 4
    for _ in range(7):
        cy, cx, r = rng.uniform(0, n), rng.uniform(0, n), rng.uniform(3, 4.5)
        occ |= (z - 4) ** 2 + (y - cy) ** 2 + (x - cx) ** 2 < r * r
    for _ in range(5):
        cy, cx, h = rng.uniform(0, n), rng.uniform(0, n), rng.uniform(7, 10)
        occ |= (z >= 4) & (np.hypot(y - cy, x - cx) < 2.5 * (1 - (z - 4) / h))
    for gy in (12, 36):
        occ &= ~((np.abs(y - gy) < 1.5) & (z >= 2))
    return occ


def render(volume, size):
    return texsynth.render_mesh(sdf_to_mesh(volume), size, views=[(-60, 35)])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    for name, example, size, kw in [("pebbles", pebbles(), 64, {}),
                                    ("plate", plate(), (16, 112, 112), {"block": 16, "overlap": 4})]:
        out, info = synthesize_geometry(example, size, rng=0, return_info=True, **kw)
        volumes = [example, out]
        if name == "pebbles":
            volumes.append(synthesize_geometry(example, size, rng=0, copy_elements=True, **kw))
        volumes.append(synthesize_geometry(example, size, rng=0, placement="random", **kw))
        print(f"{name}: {example.shape} -> {out.shape}, block {info.block}, overlap {info.overlap}, "
              f"{len(info.sources)} blocks in {info.seconds:.1f} s")
        image = np.concatenate([render(v, 300) for v in volumes], axis=1)
        path = os.path.join(args.out, f"lagae_{name}.png")
        texsynth.io.save_image(path, image, overwrite=True)
        print(path, os.path.getsize(path) // 1024, "kB")


if __name__ == "__main__":
    main()
