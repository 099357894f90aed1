"""Vertex synthesis on surfaces (issue 20): synthesize_surface on a sphere at the issue's size.

Run: python benchmarks/bench_vertex_synthesis.py [--vertices 50000] [--preset default] [--preview DIR]
     (from the repository root)

:func:`texsynth.synthesize_surface`: a sphere retiled to ``--vertices`` vertices (default 50,000),
3 levels, a 128 x 128 colour exemplar: the top-left crop of the brick photograph
../shared/textures/rohitrango/t1.png (RGB; the bundled 77 x 107 "brick" where that folder is
absent), seed 0, ``--preset`` (default ``default``; ``paper``: Turk's sweep, one vertex at a time):
wall time per stage (retiling hierarchy, field, each level). Target: <= 120 s.
``benchmarks/bench_lapped.py`` measures lapped textures on the same photograph;
``benchmarks/bench_vertex_synthesis_quality.py`` the quality on structured photographs.

``--preview DIR`` also renders the result (texsynth.surface.render_mesh) into DIR.
"""

import argparse
from pathlib import Path

import numpy as np

import texsynth
from _timing import timed_stages
from texsynth.data import load
from texsynth.io import load_image, save_image
from texsynth.surface import render_mesh, sphere

PHOTO = Path(__file__).resolve().parents[2] / "shared" / "textures" / "rohitrango" / "t1.png"


def exemplar():
    image = load_image(PHOTO)[..., :3] if PHOTO.is_file() else load("brick")
    return np.ascontiguousarray(image[:128, :128])


def save_preview(folder, name, mesh):
    """Render ``mesh`` (texsynth.surface.render_mesh, 1000 pixels) into ``folder/name``, making the folder."""
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    save_image(folder / name, render_mesh(mesh, 1000), overwrite=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--vertices", type=int, default=50000)
    parser.add_argument("--preset", default="default")
    parser.add_argument("--preview", default=None)
    args = parser.parse_args()
    ex = exemplar()

    out, info, total, stages = timed_stages(lambda: texsynth.synthesize_surface(
        sphere(10242), ex, n_vertices=args.vertices, schedule=texsynth.SurfaceSchedule(levels=3), rng=0,
        preset=args.preset, return_info=True))
    print(f"vertex synthesis ({args.preset}): {len(out.vertices)} vertices, 3 levels, exemplar "
          f"{ex.shape[1]}x{ex.shape[0]}: {total:.1f} s ({stages}; order {info.order}, search {info.method})")
    if args.preview:
        save_preview(args.preview, "surface_vertex.png", out)


if __name__ == "__main__":
    main()
