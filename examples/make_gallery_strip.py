"""
Gallery strip for the README
============================

Eight methods, each on a bundled sample (``texsynth.data``), side by side with
their names: the one picture at the top of the README,
``docs/_static/gallery_strip.png`` (1200 x 200 px). Every result is 128 x 128,
seed 0, default options; the whole strip takes about ten seconds.
Run it with ``python examples/make_gallery_strip.py`` to re-make the picture
(the docs gallery lists this script without running it; its card shows that picture).
"""

# sphinx_gallery_thumbnail_path = "_static/gallery_strip.png"

import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import texsynth
from texsynth import data
from texsynth.core.search import Search

OUT = Path(__file__).resolve().parents[1] / "docs" / "_static" / "gallery_strip.png"
SIZE = (128, 128)

# (label, sample, run): different methods on different samples, colour and grey
PANELS = [
    ("image quilting", "brick", lambda ex: texsynth.quilt(ex, SIZE, rng=0)),
    ("graph cuts", "bread", lambda ex: texsynth.graphcut_texture(ex, SIZE, rng=0)),
    ("texture optimization", "wood", lambda ex: texsynth.optimize_texture(ex, SIZE, rng=0)),
    ("k-coherent pixels", "bumpy",
     lambda ex: texsynth.synthesize_pixels(ex, SIZE, search=Search(candidates="k-coherent"), rng=0)),
    ("patchwork", "water", lambda ex: texsynth.patchwork(ex, SIZE, rng=0)),
    ("Wang tiles", "reptile", lambda ex: texsynth.wang_texture(ex, SIZE, rng=0)),
    ("Heeger-Bergen", "metal", lambda ex: texsynth.heeger_bergen(ex, SIZE, rng=0)),
    ("tiling and blending", "text", lambda ex: texsynth.tile_and_blend(ex, SIZE, rng=0)),
]


def main():
    fig, axes = plt.subplots(1, len(PANELS), figsize=(12, 2), dpi=100)
    fig.subplots_adjust(left=0.005, right=0.995, bottom=0.01, top=0.86, wspace=0.04)
    for ax, (label, sample, run) in zip(axes, PANELS):
        start = time.perf_counter()
        out = np.clip(run(data.load(sample)), 0, 1)
        print(f"{label:22s} {sample:8s} {time.perf_counter() - start:5.2f} s")
        ax.imshow(out, cmap="gray" if out.ndim == 2 else None, vmin=0, vmax=1, interpolation="nearest")
        ax.set_title(f"{label}\n({sample})", fontsize=9, linespacing=1.1)
        ax.axis("off")
    OUT.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(OUT, dpi=100)
    plt.close(fig)
    print(f"wrote {OUT} ({OUT.stat().st_size // 1024} kB)")


if __name__ == "__main__":
    main()
