"""Figures of docs/methods/btf.md: a BTF sample, its textons, planar and surface syntheses under several lights.

Run: python benchmarks/figure_btf.py [--out docs/_static]

The sample is ``texsynth.data.btf("stones", 128, n_lights=64)`` (a height field of rounded stones rendered
with Lambert shading and cast shadows under 64 lights), its textons 64 (the defaults).

- ``btf_sample.png``: the sample under 4 lights (azimuths 0, 90, 180, 270 degrees, elevation 25), its texton
  labels (random grey per texton) and its texton coordinates (the first 3 of the 4 axes as RGB);
- ``btf_planar.png``: top row, a 192 x 192 planar synthesis under the same 4 lights (one synthesis of the
  texton image, every light's image copied through its source-coordinate map); bottom row, each light's
  image synthesised on its own by the same k-coherent pixel synthesis (``synthesize_pixels``);
- ``btf_surface.png``: a torus (30,000 vertices) covered by the BTF, rendered by ``render_btf_surface`` under
  two lights (rows: from -x -y and from +x +y, above) and shown by ``texsynth.render_mesh`` from 3 sides
  (``ambient=1``: the BTF's own shading only).
"""

import argparse
import os

import numpy as np

import texsynth
from texsynth.core.btf import btf_textons, render_btf
from texsynth.data import btf
from texsynth.pixel import synthesize_btf
from texsynth.surface import render_btf_surface, synthesize_btf_surface

LIGHTS = [0, 2, 4, 6]  # lowest ring: azimuths 0, 90, 180, 270 degrees


def grey(image):
    return np.repeat(np.clip(image, 0, 1)[..., None], 3, axis=-1)


def gap(height, width=4):
    return np.ones((height, width, 3))


def row(images):
    parts = []
    for image in images:
        parts += [image, gap(image.shape[0])]
    return np.concatenate(parts[:-1], axis=1)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    sample = btf("stones", 128, n_lights=64)
    textons = btf_textons(sample, 64, rng=0)
    image, share = textons.image(4)
    shades = np.random.default_rng(0).random(64)
    print(f"textons in {textons.seconds:.1f} s; 4 axes keep {share:.2f} of the texton distances")
    figure = row([grey(sample.images[i]) for i in LIGHTS] + [grey(shades[textons.labels]), image[..., :3]])
    path = os.path.join(args.out, "btf_sample.png")
    texsynth.io.save_image(path, figure, overwrite=True)
    print(path)

    out = synthesize_btf(sample, 192, textons=textons, rng=0)
    search = texsynth.Search(candidates="k-coherent", k=2)
    neighborhood = texsynth.Neighborhood(neighborhood_size=9, levels=3)
    alone = [texsynth.synthesize_pixels(sample.images[i], 192, neighborhood=neighborhood, search=search, rng=i)
             for i in LIGHTS]
    top = row([grey(render_btf(out, sample.lights[i])) for i in LIGHTS])
    bottom = row([grey(a) for a in alone])
    figure = np.concatenate([top, np.ones((4, top.shape[1], 3)), bottom], axis=0)
    path = os.path.join(args.out, "btf_planar.png")
    texsynth.io.save_image(path, figure, overwrite=True)
    print(path)

    torus = texsynth.surface.torus(4000, major_radius=1.0, minor_radius=0.45)
    surface, info = synthesize_btf_surface(torus, sample, n_vertices=30_000, textons=textons, rng=0,
                                           return_info=True)
    print(f"torus: {len(surface.sources)} vertices in {info.seconds:.1f} s")
    views = [(-60, 35), (30, 35), (120, 60)]
    rows = [row([texsynth.render_mesh(render_btf_surface(surface, light), 400, views=[view], ambient=1.0)
                 for view in views]) for light in [(-0.6, -0.3, 0.75), (0.7, 0.4, 0.6)]]
    figure = np.concatenate([rows[0], np.ones((4, rows[0].shape[1], 3)), rows[1]], axis=0)
    path = os.path.join(args.out, "btf_surface.png")
    texsynth.io.save_image(path, figure, overwrite=True)
    print(path)


if __name__ == "__main__":
    main()
