"""Lapped textures (issue 20): lapped_textures on a torus at the issue's size.

Run: python benchmarks/bench_lapped.py [--faces 20000] [--preview DIR]   (from the repository root)

:func:`texsynth.lapped_textures`: a torus of about ``--faces`` faces (default 20,000), the
128 x 128 colour brick photograph of ``benchmarks/bench_vertex_synthesis.py`` (the bundled
"brick" where ../shared/textures is absent), seed 0: wall time per stage (field, paste, bake).
Target: <= 30 s.

``--preview DIR`` also renders the result (texsynth.surface.render_mesh) into DIR.
"""

import argparse

import texsynth
from _timing import timed_stages
from bench_vertex_synthesis import exemplar, save_preview
from texsynth.surface import torus


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, default=20000)
    parser.add_argument("--preview", default=None)
    args = parser.parse_args()
    ex = exemplar()

    mesh = torus(args.faces // 2)
    lapped, linfo, total, stages = timed_stages(lambda: texsynth.lapped_textures(mesh, ex, rng=0, return_info=True))
    print(f"lapped textures: {len(mesh.faces)} faces, {len(linfo.patches)} patches, atlas "
          f"{lapped.texture.shape[1]}x{lapped.texture.shape[0]}: {total:.1f} s ({stages})")
    if args.preview:
        save_preview(args.preview, "surface_lapped.png", lapped)


if __name__ == "__main__":
    main()
