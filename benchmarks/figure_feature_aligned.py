"""Figures of docs/methods/feature_aligned.md: textures along a surface's ridges and along drawn curves.

Run: python benchmarks/figure_feature_aligned.py [--out docs/_static] [--n-vertices 30000]

- ``feature_aligned_curves.png``: the creased mesh of ``bench_feature_aligned.py`` (four meridian crests) with
  the vertices of ``salient_curves`` in red;
- ``feature_aligned_surface.png``: ``feature_aligned_surface`` with the brick photograph (its mortar joints
  are the feature lines), retiled to ``--n-vertices``;
- ``feature_aligned_smooth.png``: the reference, ``texsynth.synthesize_surface`` with the smooth field that
  ignores the crests (same mesh, exemplar, density and seed);
- ``feature_aligned_planar.png``: the planar form: the drawn curves (two rings), ``feature_aligned_texture``
  and ``texsynth.optimize_texture`` of the same size, 192^2 from the brick photograph.

Every surface is rendered by ``texsynth.render_mesh`` from four sides, 2 x 2: azimuths 0, 45 and 90 degrees
at 20 degrees elevation (the crests at 0 and 90 degrees face the camera in the first and third views) and
from above (azimuth 45, elevation 75).
"""

import argparse
import os
import sys

import numpy as np

import texsynth
from texsynth.optimization import feature_aligned_texture
from texsynth.surface import curve_alignment, feature_aligned_surface, salient_curves

sys.path.insert(0, os.path.dirname(__file__))
from bench_feature_aligned import creased_mesh, rings  # noqa: E402

VIEWS = [(0, 20), (45, 20), (90, 20), (45, 75)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    parser.add_argument("--n-vertices", type=int, default=30000)
    args = parser.parse_args()
    brick = texsynth.data.load("brick")
    mesh = creased_mesh(args.n_vertices)
    curves = salient_curves(mesh)
    marked = np.full((len(mesh.vertices), 3), 0.8)
    marked[curves.vertices] = (0.9, 0.1, 0.1)
    images = {"curves": texsynth.render_mesh(mesh.with_colors(marked), (700, 700), views=VIEWS)}
    ours, info = feature_aligned_surface(mesh, brick, n_vertices=args.n_vertices, rng=0, return_info=True)
    smooth = texsynth.synthesize_surface(mesh, brick, n_vertices=args.n_vertices, rng=0)
    images["surface"] = texsynth.render_mesh(ours, (700, 700), views=VIEWS)
    images["smooth"] = texsynth.render_mesh(smooth, (700, 700), views=VIEWS)
    print(f"{curves.n_curves} curves, {len(curves.vertices)} vertices; feature angle {info.feature_angle:.0f} deg; "
          f"angle to the ridges: feature-aligned {curve_alignment(ours, curves):.1f}, "
          f"smooth field {curve_alignment(smooth, curves):.1f} deg")
    lines = rings(192)
    planar, pinfo = feature_aligned_texture(brick, lines, rng=0, return_info=True)
    plain = texsynth.optimize_texture(brick, lines.shape, rng=0)
    drawn = np.repeat(1.0 - lines[..., None].astype(float), 3, axis=-1)
    gap = np.ones((192, 8, 3))
    images["planar"] = np.concatenate([drawn, gap, planar, gap, plain], axis=1)
    print(f"planar: feature angle {pinfo.feature_angle:.0f} deg, {pinfo.seconds:.1f} s")
    os.makedirs(args.out, exist_ok=True)
    for name, image in images.items():
        path = os.path.join(args.out, f"feature_aligned_{name}.png")
        texsynth.io.save_image(path, np.clip(image, 0, 1), overwrite=True)
        print("wrote", path)


if __name__ == "__main__":
    main()
