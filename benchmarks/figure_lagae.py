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
from texsynth.geometry import sdf_to_mesh, synthesize_geometry


def render(volume, size):
    return texsynth.render_mesh(sdf_to_mesh(volume), size, views=[(-60, 35)])


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    for name, example, size, kw in [("pebbles", texsynth.data.volume("pebbles"), 64, {}),
                                    ("plate", texsynth.data.volume("plate", rng=2), (16, 112, 112), {"block": 16, "overlap": 4})]:
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
