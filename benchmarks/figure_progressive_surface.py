"""Figures of docs/methods/progressive_surface.md: a progressively-variant texture on a sphere.

Run: python benchmarks/figure_progressive_surface.py [--vertices 50000] [--out docs/_static]
     (from the repository root)

The two exemplars of ``bench_progressive_surface.py`` (small dark spots on beige; large grey-green spots
on slate), ``blend`` from 0 at the south pole to 1 at the north pole, a sphere retiled to ``--vertices``
vertices, 3 levels, seed 0. Writes:

- ``progressive_surface_sample.png``: the two exemplars, then the 2-D progressively-variant sample made
  from them by feature-based warping and blending (its texture T above its texton mask M; F runs from 0
  on the left to 1 on the right);
- ``progressive_surface_sphere.png``: the result rendered by ``texsynth.render_mesh`` (400 pixels a view)
  from four sides around the equator, from above (``blend`` 1) and from below (``blend`` 0) (top row), and
  the texton mask synthesised first, in black and white, from the same six sides (bottom row).
"""

import argparse
import os

import numpy as np

import texsynth
from bench_progressive_surface import exemplars, poles
from texsynth.surface import sphere
from texsynth.surface import progressive_surface

VIEWS = [(0, 0), (90, 0), (180, 0), (270, 0), (0, 89), (0, -89)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vertices", type=int, default=50000)
    parser.add_argument("--out", default=os.path.join(os.path.dirname(__file__), "..", "docs", "_static"))
    args = parser.parse_args()
    a, b = exemplars()
    out, info = progressive_surface(sphere(10242), a, b, poles, n_vertices=args.vertices,
                                    schedule=texsynth.SurfaceSchedule(levels=3), rng=0, return_info=True)
    print(f"{len(out.vertices)} vertices in {info.seconds:.1f} s")
    gap = np.ones((a.shape[0], 8, 3))
    mask = np.repeat(info.sample_mask[..., None].astype(float), 3, axis=2)
    sample = np.concatenate([np.concatenate([a, gap, b, gap, info.sample], axis=1),
                             np.ones((8, a.shape[1] * 2 + 16 + info.sample.shape[1], 3)),
                             np.concatenate([np.ones((a.shape[0], a.shape[1] * 2 + 16, 3)), mask], axis=1)], axis=0)
    texsynth.io.save_image(os.path.join(args.out, "progressive_surface_sample.png"), sample, overwrite=True)
    masked = out.with_colors(np.repeat(info.texton_mask[:, None].astype(float), 3, axis=1))
    image = np.concatenate([np.concatenate([texsynth.render_mesh(m, 400, views=[view]) for view in VIEWS], axis=1)
                            for m in (out, masked)], axis=0)
    path = os.path.join(args.out, "progressive_surface_sphere.png")
    texsynth.io.save_image(path, image, overwrite=True)
    print(path)


if __name__ == "__main__":
    main()
