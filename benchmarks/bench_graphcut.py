"""Graph-cut textures: speed at 256x256 -> 512x512 colour, side by side with quilting and patchwork.

Run: nice -n 10 python benchmarks/bench_graphcut.py [--repeat 1] [--save]   (from the repository root)

Target (issue 17): graph-cut textures 256x256 -> 512x512 colour, with refinement, in at most 60 s.

Side by side, in the same run, on the same 256 px crops of benchmarks/photos:
- ``texsynth.quilt`` (image quilting, its defaults: 64 px blocks) and
- ``texsynth.patchwork`` (Harrison's patchwork, its default grid),
the library's other patch methods; for graph cuts the stages (covering, refinement passes; search and cuts), the
number of patches and the total seam cost after covering and at the end. ``--save`` writes every output to
benchmarks/output/graphcut_<photo>_<method>.png for looking.
"""

import argparse
import os
from pathlib import Path

import numpy as np

# the shortest wall time of repeated calls, and the result (benchmarks/ is on the path of a script run from it)
from bench_quilting import best_of

ROOT = Path(__file__).resolve().parents[1]
PHOTOS = ROOT / "benchmarks" / "photos"
OUTPUT = ROOT / "benchmarks" / "output"


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--save", action="store_true")
    args = parser.parse_args()

    import texsynth
    from texsynth.io import load_image, save_image

    print(f"Synthesis 256x256 -> 512x512 colour (benchmarks/photos, top-left 256 px crops), best of {args.repeat}; "
          f"load {os.getloadavg()[0]:.1f}")
    print(f"{'photo':<16} {'graphcut s':>10} {'quilt s':>8} {'patchwork s':>12}   graphcut: patches, stages, seam cost")
    for name in ("bricks_1", "pebbles_1", "cobblestones_1", "moss_1"):
        image = load_image(PHOTOS / f"{name}.png")
        ex = np.ascontiguousarray(image[:256, :256, :3])
        t_g, (out_g, info) = best_of(texsynth.graphcut_texture, args.repeat, ex, 512, rng=0, return_info=True)
        t_q, out_q = best_of(texsynth.quilt, args.repeat, ex, 512, rng=0)
        t_h, out_h = best_of(texsynth.patchwork, args.repeat, ex, 512, rng=0)
        stages = ", ".join(f"{k} {v:.1f}" for k, v in info.stage_seconds.items())
        covered = info.energy[info.n_initial - 1]
        print(f"{name:<16} {t_g:10.2f} {t_q:8.2f} {t_h:12.2f}   {info.n_initial} + {len(info.corners) - info.n_initial} "
              f"patches of {info.block} px; {stages}; seam cost {covered:.0f} -> {info.seam_cost:.0f}", flush=True)
        if args.save:
            OUTPUT.mkdir(exist_ok=True)
            for method, out in (("graphcut", out_g), ("quilt", out_q), ("patchwork", out_h)):
                save_image(OUTPUT / f"graphcut_{name}_{method}.png", out, overwrite=True)


if __name__ == "__main__":
    main()
