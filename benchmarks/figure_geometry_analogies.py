"""Figures of docs/methods/geometry_analogies.md: a : a' :: b : b' on volumes, rendered as meshes.

Run: python benchmarks/figure_geometry_analogies.py [--out docs/_static]

The examples come from ``texsynth.data.volume`` (no data file): the plain cylinder ``a`` and its textured
copies ``a'`` (grooves, pits, spikes, a dilation), 32 slices of a 48^3 (grooves) or 40^3 (the others) volume,
the field along the axis; the target ``b`` a torus, the field along its tube.

- ``geometry_analogies_pairs.png``: the training pairs' textured cylinders (grooved, pitted, spiked, dilated)
  and the plain one, one view each;
- ``geometry_analogies_grooves.png``: the grooved torus (96^3, the benchmark's run) from four sides;
- ``geometry_analogies_reference.png``: the same with ``alignment="axes"`` (neighbourhoods on the grid's axes, no
  field: image analogies on a voxel grid), four sides;
- ``geometry_analogies_variants.png``: pits, spikes and the dilation on a 72^3 torus, two sides each.

Each mesh is ``texsynth.geometry.sdf_to_mesh`` of the volume, rendered by ``texsynth.render_mesh``.
"""

import argparse
import os

import numpy as np

import texsynth
from texsynth import data
from texsynth.geometry import geometry_analogies, sdf_to_mesh


def along_tube(size):
    c = (size - 1) / 2
    return lambda p: np.stack([np.zeros(len(p)), -(p[:, 2] - c), p[:, 1] - c], 1)


def render(volume, size, views, label):
    return texsynth.render_mesh(sdf_to_mesh(volume), size, views=views)


def save(out, name, image):
    path = os.path.join(out, f"geometry_analogies_{name}.png")
    texsynth.io.save_image(path, image, overwrite=True)
    print(path, os.path.getsize(path) // 1024, "kB")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    four = [(-60, 35), (30, 5), (0, 90), (150, -35)]
    pairs = [data.volume(name, 40)[:32] for name in ("cylinder", "grooved_cylinder", "pitted_cylinder",
                                                      "spiked_cylinder", "dilated_cylinder")]
    save(args.out, "pairs", np.concatenate([render(v, 300, [(-60, 25)], "pair") for v in pairs], axis=1))

    a, a_prime = data.volume("cylinder", 48)[:32], data.volume("grooved_cylinder", 48)[:32]
    b = data.volume("torus", 96)
    for name, alignment in (("grooves", "field"), ("reference", "axes")):
        out, info = geometry_analogies(a, a_prime, b, field_a=(1, 0, 0), field_b=along_tube(96), alignment=alignment,
                                       rng=0, return_info=True)
        print(f"{name}: {len(info.voxels)} band voxels, {info.wavefronts} wavefronts, {info.seconds:.1f} s")
        save(args.out, name, render(out, 800, four, name))

    b = data.volume("torus", 72)
    tiles = []
    for kind in ("pitted", "spiked", "dilated"):
        out = geometry_analogies(pairs[0], data.volume(f"{kind}_cylinder", 40)[:32], b, field_a=(1, 0, 0),
                                 field_b=along_tube(72), rng=0)
        tiles.append(render(out, (300, 600), [(-60, 35), (30, -20)], kind))
    save(args.out, "variants", np.concatenate(tiles, axis=0))


if __name__ == "__main__":
    main()
