"""Quality of interpolate_textures at alpha = 0 and 1 against ordinary texture optimization.

At the ends the interpolation should be a synthesis of one input. For each
pair, end and seed this prints the texture energy (8 px patches) of ours and
of periodic ``optimize_texture`` on the same 64 px crop, their ratio, and
both on the baselines' scale of ``texsynth.testing.relative_scores`` (0 = the
tiled exemplar, 1 = histogram-matched noise) next to a random-block mosaic.
The figures in docs/methods/ruiters.md (Quality) come from this script.

Usage::

    python benchmarks/bench_ruiters_ends.py                       # 3 pairs x 2 ends x seeds 0-2
    python benchmarks/bench_ruiters_ends.py '{"max_iterations": 8}'   # extra interpolate_textures options

The extra options are named by their fields (``max_iterations``, ``keep_fraction``, ...) and go into
the option group that has the field.
"""

import json
import sys
from pathlib import Path

import numpy as np

from texsynth.optimization import interpolate_textures
from texsynth.registry import group_options
from texsynth.io import load_image
from texsynth.metrics import mosaic_baseline, noise_baseline, texture_energy, tiled_baseline
from texsynth.optimization import optimize_texture

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
PAIRS = [("rohitrango/t1.png", "rohitrango/t7.png"), ("jcjohnson/brick.png", "jcjohnson/bumpy.png"),
         ("rohitrango/t4.png", "rohitrango/t13.png")]
SIZE = 64
OPTIONS = dict(stages=((2, 17), (1, 17), (1, 9)), max_iterations=4, max_neighborhoods=400)


def crop(name):
    image = load_image(TEXTURES / name)
    return image[:SIZE, :SIZE, :3] if image.ndim == 3 else image[:SIZE, :SIZE]


def main():
    extra = json.loads(sys.argv[1]) if len(sys.argv) > 1 else {}
    ratios, gaps = [], []
    for seed in (0, 1, 2):
        for name_a, name_b in PAIRS:
            a, b = crop(name_a), crop(name_b)
            for alpha, ref, name in ((0.0, a, name_a), (1.0, b, name_b)):
                ours = interpolate_textures(a, b, alpha, **group_options(interpolate_textures,
                                                                         {**OPTIONS, "rng": seed, **extra}))
                kwatra = optimize_texture(ref, SIZE, tileable=True, rng=seed)
                energy = {key: texture_energy(image, ref) for key, image in (
                    ("ours", ours), ("kwatra", kwatra), ("mosaic", mosaic_baseline(ref, SIZE, rng=seed)),
                    ("noise", noise_baseline(ref, SIZE, rng=seed)), ("tiled", tiled_baseline(ref, SIZE)))}
                score = {key: (energy[key] - energy["tiled"]) / (energy["noise"] - energy["tiled"])
                         for key in ("ours", "kwatra", "mosaic")}
                ratios.append(energy["ours"] / energy["kwatra"])
                gaps.append((score["ours"] - score["kwatra"]) / (score["mosaic"] - score["kwatra"]))
                print(f"seed {seed}  {name:22s} alpha {alpha:.0f}  energy ours {energy['ours']:.5f} "
                      f"texture optimization {energy['kwatra']:.5f} (x{ratios[-1]:.2f})  scores ours "
                      f"{score['ours']:.3f} texture optimization {score['kwatra']:.3f} mosaic {score['mosaic']:.3f}",
                      flush=True)
    print(f"ratio: geometric mean {np.exp(np.mean(np.log(ratios))):.2f}, range {min(ratios):.2f}-{max(ratios):.2f}; "
          f"way from texture optimization to the mosaic: median {np.median(gaps):.2f}, max {max(gaps):.2f}")


if __name__ == "__main__":
    main()
