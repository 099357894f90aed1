"""Hole filling and uncrop: texsynth.inpaint / texsynth.uncrop against the resynthesizer engine, in one run.

Run: python benchmarks/bench_completion.py [--figure] [--photos NAME ...]   (from the repository root; needs the
bench extra)

On the top-left 512x512 of colour photographs of ``benchmarks/photos``, seed 0:

- **hole filling**: a disc of radius 80 px (20 106 pixels) centred at (250, 270) is filled by
  ``texsynth.inpaint``, by the resynthesizer engine (Harrison's C engine, PyPI
  ``resynthesizer``: GIMP's "Heal selection", its source the rest of the image) and by a
  PatchMatch inpainting package (PyPI ``pypatchmatch``, MIT, 7x7 patches);
- **uncrop**: the central 256x256 of the same crop is extended to 512x512 by ``texsynth.uncrop``
  and by both peers filling the canvas around it (GIMP's "Uncrop").

Each line: wall time; the sharpness (mean absolute difference of 4-neighbours) of the filled
pixels over the known pixels' (a fill that averages is blurred: a Gaussian blur of sigma 1 px
keeps about 0.4-0.5); and the seam, the mean absolute difference across the boundary between
known and filled pixels over the same measure inside the known pixels (1: the boundary is as
smooth as the texture; above 1: a visible edge).

``--figure`` writes ``docs/_static/completion.png``: per photograph the input (hole in magenta),
the three fills (texsynth, resynthesizer, pypatchmatch), then the three uncrops.
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np

import texsynth
from texsynth.io import load_image, save_image

HERE = Path(__file__).resolve().parent
PHOTOS = ("bricks_1", "pebbles_1", "stonewall_1", "grass_1")


def resynthesize(image, hole):
    """Harrison's engine filling the pixels of ``hole`` from the rest of ``image``."""
    from PIL import Image
    import resynthesizer

    params = resynthesizer.getDefaultParams()
    params.isMakeSeamlesslyTileableHorizontally = 0
    params.isMakeSeamlesslyTileableVertically = 0
    picture = Image.fromarray(np.round(image * 255).astype(np.uint8))
    mask = Image.fromarray(np.where(hole, 255, 0).astype(np.uint8))
    return np.asarray(resynthesizer.resynthesize(picture, mask, params), dtype=np.float32) / 255.0


def patchmatch_fill(image, hole):
    """PyPatchMatch (PyPI ``pypatchmatch``, MIT: Barnes et al.'s PatchMatch inpainting, coarse to fine) filling
    the pixels of ``hole`` from the rest of ``image``, with 7x7 patches (``patch_size=3``, its examples' value)."""
    from patchmatch import patch_match

    patch_match.set_random_seed(0)
    picture = np.round(image * 255).astype(np.uint8)
    return patch_match.inpaint(picture, hole.astype(np.uint8) * 255, patch_size=3).astype(np.float32) / 255.0


def sharpness(img, where):
    dx = np.abs(np.diff(img, axis=1)).mean(-1)[where[:, 1:] & where[:, :-1]]
    dy = np.abs(np.diff(img, axis=0)).mean(-1)[where[1:] & where[:-1]]
    return (dx.mean() + dy.mean()) / 2


def seam(img, hole):
    """Mean absolute difference of 4-neighbour pairs that cross the hole's boundary, over the known pairs'."""
    dx, dy = np.abs(np.diff(img, axis=1)).mean(-1), np.abs(np.diff(img, axis=0)).mean(-1)
    cross = np.concatenate([dx[hole[:, 1:] != hole[:, :-1]], dy[hole[1:] != hole[:-1]]])
    return cross.mean() / sharpness(img, ~hole)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--figure", action="store_true")
    parser.add_argument("--photos", nargs="+", default=PHOTOS, help="names in benchmarks/photos (default: %(default)s)")
    args = parser.parse_args()
    print(f"# {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}, {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print("| photo | task | method | seconds | sharpness of the fill / known | seam |")
    print("|---|---|---|---|---|---|")
    rows_, cols_ = np.mgrid[:512, :512]
    hole = (rows_ - 250) ** 2 + (cols_ - 270) ** 2 < 80**2
    outside = np.ones((512, 512), bool)
    outside[128:384, 128:384] = False
    figure = []
    for photo in args.photos:
        image = np.ascontiguousarray(load_image(HERE / "photos" / f"{photo}.png")[:512, :512, :3]).astype(np.float32)
        shown = image.copy()
        shown[hole] = [1.0, 0.0, 1.0]
        canvas = np.zeros_like(image)
        canvas[128:384, 128:384] = image[128:384, 128:384]
        panels = [shown]
        for task, mask, run_ours, image_in in (
            ("hole", hole, lambda: texsynth.inpaint(image, hole, rng=0), image),
            ("uncrop", outside, lambda: texsynth.uncrop(image[128:384, 128:384], 512, rng=0), canvas),
        ):
            for method, run in (("texsynth", run_ours), ("resynthesizer", lambda: resynthesize(image_in, mask)),
                                ("pypatchmatch", lambda: patchmatch_fill(image_in, mask))):
                start = time.perf_counter()
                out = run()
                seconds = time.perf_counter() - start
                fill = sharpness(out, mask) / sharpness(out, ~mask)
                print(f"| {photo} | {task} | {method} | {seconds:.1f} | {fill:.2f} | {seam(out, mask):.2f} |", flush=True)
                panels.append(out)
        figure.append(np.concatenate([np.pad(p, ((4, 4), (4, 4), (0, 0)), constant_values=1.0) for p in panels], 1))
    if args.figure:
        small = [f[::2, ::2] for f in figure]  # half size: the whole set in one picture
        save_image(HERE.parent / "docs" / "_static" / "completion.png", np.concatenate(small, 0), overwrite=True)
        save_image(HERE / "output" / "completion_full.png", np.concatenate(figure, 0), overwrite=True)


if __name__ == "__main__":
    main()
