"""Lapped textures (issue 20): lapped_textures on a torus at the issue's size.

Run: python benchmarks/bench_lapped.py [--faces 20000] [--preview DIR]   (from the repository root)

:func:`texsynth.lapped_textures`: a torus of about ``--faces`` faces (default 20,000), the
128 x 128 colour brick photograph of ``benchmarks/bench_vertex_synthesis.py`` (the bundled
"brick" where ../shared/textures is absent), seed 0: wall time per stage (field, paste, bake).
Target: <= 30 s.

``--preview DIR`` also renders the result (texsynth.surface.render_mesh) into DIR.
"""

import argparse
import time
from pathlib import Path

import texsynth
from bench_vertex_synthesis import exemplar
from texsynth.io import save_image
from texsynth.surface import render_mesh, torus


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--faces", type=int, default=20000)
    parser.add_argument("--preview", default=None)
    args = parser.parse_args()
    ex = exemplar()

    mesh = torus(args.faces // 2)
    start = time.perf_counter()
    lapped, linfo = texsynth.lapped_textures(mesh, ex, rng=0, return_info=True)
    total = time.perf_counter() - start
    stages = ", ".join(f"{k} {v:.1f}" for k, v in linfo.stage_seconds.items())
    print(f"lapped textures: {len(mesh.faces)} faces, {len(linfo.patches)} patches, atlas "
          f"{lapped.texture.shape[1]}x{lapped.texture.shape[0]}: {total:.1f} s ({stages})")
    if args.preview:
        folder = Path(args.preview)
        folder.mkdir(parents=True, exist_ok=True)
        save_image(folder / "surface_lapped.png", render_mesh(lapped, 1000), overwrite=True)


if __name__ == "__main__":
    main()
