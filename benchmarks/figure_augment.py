"""Exemplar augmentation (``Search(augment=...)``): writes ``docs/_static/augment_helps.png`` and ``augment_hurts.png``.

Texture optimization (:func:`texsynth.optimize_texture`, preset ``"default"``) from a 96-pixel crop of a
bundled sample to 256 pixels, with ``augment`` ``"none"``, ``"flips"``, ``"rotations"`` and ``"both"``
(columns after the exemplar, seed 0). ``augment_helps.png``: ``water``, caustics on a pool floor, the same
few bright streaks in any orientation. ``augment_hurts.png``: ``brick`` (top row) and ``wood`` (bottom row),
whose courses and grain run one way. Prints, per output, the largest region copied in the exemplar's own
orientation (:func:`texsynth.metrics.verbatim_copy`, share of the exemplar's area), the most any one
exemplar pixel is used (from the source-coordinate map) and the texture energy against the exemplar as it
is (:func:`texsynth.metrics.texture_energy`: a rotated element is far from every neighbourhood of a
directional exemplar).

    python benchmarks/figure_augment.py
"""

import time
from pathlib import Path

import numpy as np

from texsynth import optimize_texture
from texsynth.core.search import AUGMENTS, Search
from texsynth.data import load
from texsynth.io import save_image
from texsynth.metrics import texture_energy, verbatim_copy

STATIC = Path(__file__).resolve().parents[1] / "docs" / "_static"
EXEMPLAR, OUTPUT, GAP = 96, 256, 8


def row(name):
    """The exemplar and its four syntheses side by side, with the measures printed."""
    ex = load(name)[:EXEMPLAR, :EXEMPLAR]
    ex = np.repeat(ex[..., None], 3, -1) if ex.ndim == 2 else ex
    cells = [np.pad(ex, ((0, OUTPUT - ex.shape[0]), (0, 0), (0, 0)), constant_values=1.0)]
    for augment in AUGMENTS:
        t = time.perf_counter()
        out, info = optimize_texture(ex, OUTPUT, search=Search(augment=augment), rng=0, return_info=True)
        c = info.coordinates.reshape(-1, 2)
        most = np.bincount(c[:, 0] * ex.shape[1] + c[:, 1]).max()
        print(f"{name:<6} augment={augment:<10} largest copy {verbatim_copy(out, ex):.2f}  most uses {most:4d}  "
              f"texture energy {texture_energy(out, ex):.5f}  {time.perf_counter() - t:.1f} s")
        cells.append(out)
    gap = np.ones((OUTPUT, GAP, 3))
    return np.concatenate([x for cell in cells for x in (cell, gap)][:-1], 1)


def figure(names, path):
    rows = [row(name) for name in names]
    gap = np.ones((GAP, rows[0].shape[1], 3))
    save_image(path, np.clip(np.concatenate([x for r in rows for x in (r, gap)][:-1], 0), 0, 1), overwrite=True)


def main():
    figure(["water"], STATIC / "augment_helps.png")
    figure(["brick", "wood"], STATIC / "augment_hurts.png")


if __name__ == "__main__":
    main()
