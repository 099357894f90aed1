"""The README's pictures: every recipe of README.md run on the bundled samples (``texsynth.data``).

Writes ``docs/_static/readme_*.png``, one per recipe, with the calls the README shows (the same
functions, samples, sizes and seeds), and prints each picture's time and file size. The pictures are
stored as 8-bit palette PNGs (Floyd-Steinberg dithered), so that all of them together stay a few
hundred kB; look at them after a change (no seams, no blur).

    python benchmarks/figure_readme.py            # all pictures, about a minute on 2 cores
    python benchmarks/figure_readme.py hero hole  # some of them
"""

import io
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
from PIL import Image

import texsynth
from texsynth import data
from texsynth.core import flows
from texsynth.surface import render_mesh, torus

OUT = Path(__file__).resolve().parents[1] / "docs" / "_static"
GAP = 8


def rgb(image):
    """A grey or colour image in [0, 1] as (H, W, 3)."""
    image = np.clip(np.asarray(image, dtype=float), 0.0, 1.0)
    return np.repeat(image[..., None], 3, -1) if image.ndim == 2 else image[..., :3]


def row(*images, gap=GAP):
    """Images side by side on white, top-aligned (a small exemplar beside its larger result)."""
    images = [rgb(image) for image in images]
    height = max(image.shape[0] for image in images)
    parts = []
    for image in images:
        pad = np.ones((height - image.shape[0],) + image.shape[1:])
        parts += [np.concatenate([image, pad]), np.ones((height, gap, 3))]
    return np.concatenate(parts[:-1], axis=1)


def column(*images, gap=GAP):
    width = max(image.shape[1] for image in images)
    parts = []
    for image in images:
        parts += [np.concatenate([image, np.ones((image.shape[0], width - image.shape[1], 3))], 1),
                  np.ones((gap, width, 3))]
    return np.concatenate(parts[:-1], axis=0)


def save(name, image, colors=256):
    """``docs/_static/readme_NAME.png`` as a dithered palette PNG; returns its size in bytes."""
    pixels = Image.fromarray(np.round(rgb(image) * 255).astype(np.uint8))
    palette = pixels.quantize(colors=colors, method=Image.Quantize.MEDIANCUT, dither=Image.Dither.FLOYDSTEINBERG)
    buffer = io.BytesIO()
    palette.save(buffer, format="PNG", optimize=True)
    path = OUT / f"readme_{name}.png"
    path.write_bytes(buffer.getvalue())
    return path.stat().st_size


# --------------------------------------------------------------------------- one function per picture
def hero():
    """The first screen: bread and bricks enlarged by the front door (the README's first snippet)."""
    bread, brick = data.load("bread"), data.load("brick")
    big = texsynth.synthesize(bread, (192, 288), rng=0)
    wall = texsynth.synthesize(brick, (192, 288), rng=0)
    return row(bread, big, np.ones((1, 16, 3)), brick, wall)


def enlarge():
    """Texture optimization on a colour photo and a grey structured one."""
    bumpy = data.load("bumpy")
    reptile = data.load("reptile")[:128, :128]
    return row(bumpy, texsynth.optimize_texture(bumpy, (192, 288), rng=0), np.ones((1, 16, 3)),
               reptile, texsynth.optimize_texture(reptile, (192, 288), rng=0))


def tileable():
    """The bread photo tiled 2 x 2 before and after make_tileable."""
    photo = data.load("bread")
    tile = texsynth.make_tileable(photo, rng=0)
    return row(np.tile(photo, (2, 2, 1)), np.tile(tile, (2, 2, 1)), gap=16)


def hole():
    """A disc of the reptile-skin photo filled: the photo with the hole, the mask (white = fill), the result."""
    photo = data.load("reptile")[:192, :192]
    rows, cols = np.mgrid[:192, :192]
    mask = (rows - 96) ** 2 + (cols - 100) ** 2 < 40**2  # True (white in a mask file) = fill
    filled = texsynth.inpaint(photo, mask, rng=0)
    shown = photo.copy()
    shown[mask] = 1.0
    return row(shown, mask.astype(float), filled)


def uncrop():
    """The bread photo (99 x 108) extended to 160 x 240, its place marked on the left."""
    photo = data.load("bread")
    wide = texsynth.uncrop(photo, (160, 240), rng=0)
    canvas = np.full((160, 240, 3), 0.85)
    top, left = (160 - photo.shape[0]) // 2, (240 - photo.shape[1]) // 2
    canvas[top:top + photo.shape[0], left:left + photo.shape[1]] = photo
    return row(canvas, wide)


def pbr():
    """An albedo and a height map (the bread's luminance standing in for one) synthesised as one."""
    albedo = data.load("bread")
    height = albedo.mean(axis=-1)
    big, info = texsynth.quilt(albedo, (192, 288), rng=0, return_info=True)
    big_height = texsynth.apply_coordinates(height, info)
    return row(albedo, height, np.ones((1, 16, 3)), big, big_height)


def batch():
    """A batch (3 samples x 2 methods x 2 seeds) on Dask, and a 1:1 crop of a 32768^2 lazy patchwork."""
    import imageio.v3 as iio

    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp) / "exemplars"
        folder.mkdir()
        samples = ("bread", "bumpy", "water")
        for name in samples:
            iio.imwrite(folder / f"{name}.png", np.round(data.load(name) * 255).astype(np.uint8))
        texsynth.batch(folder, Path(tmp) / "results", methods=["patchwork", "quilt"], seeds=2, size=80,
                       n_workers=2, processes=False, progress=False)
        results = sorted((Path(tmp) / "results").glob("*.png"))
        grid = column(*[row(*[iio.imread(p) / 255.0 for p in results if p.name.startswith(name)], gap=4)
                        for name in samples], gap=4)
    big = texsynth.patchwork(data.load("water"), 32768, rng=0, chunks=2048)  # lazy: nothing computed yet
    crop = big[16000:16256, 16000:16256].compute()  # any part, without the rest
    return row(grid, crop, gap=16)


def surface():
    """Lapped textures: the brick photo pasted over a torus along a smooth field, two views."""
    mesh = texsynth.lapped_textures(torus(), data.load("brick"), rng=0)
    preview = render_mesh(mesh, 512, views=2)
    inside = np.nonzero((preview < 0.99).any(axis=(1, 2)))[0]
    return preview[max(inside[0] - 4, 0):inside[-1] + 5]


def animation():
    """Flow-guided animation of the water (half size) flowing down and right, 1 and 3 px a frame: frames 1, 5, 9.

    A translation by whole pixels keeps every frame as sharp as the first; flows that warp by fractions of a
    pixel (rotation, sink, vortex) soften the frames as they go (docs/methods/kwatra.md)."""
    water = data.load("water")[::2, ::2]
    frames = texsynth.animate_texture(water, flows.translation((128, 128), (1.0, 3.0)), n_frames=9, rng=0)
    return row(frames[0], frames[4], frames[8])


def clip():
    """The simulated water clip's first frame and frames 100, 200 of its dynamic texture; frames 1, 41, 81 of a
    120-frame loop of the simulated candle (the flame's part of the frame)."""
    waves = data.clip("waves")
    water = texsynth.dynamic_texture(waves, 200, rng=0)
    loop = texsynth.video_texture(data.clip("flame", 300), 120, loop=True, rng=0)
    flame = [frame[:, 16:112] for frame in loop[[0, 40, 80]]]
    return row(waves[0], water[99], water[199], np.ones((1, 16, 3)), *flame)


def geometry():
    """Geometry by example: the pebbles volume (48³) and a 96³ volume synthesised from it; rivets quilted over a
    bumpy sphere (about 200 elements), each rendered from one side."""
    from texsynth.geometry import mesh_quilting, sdf_to_mesh, synthesize_geometry
    from texsynth.surface import bumpy

    pebbles = data.volume("pebbles")
    more = synthesize_geometry(pebbles, 96, rng=0)
    views = [render_mesh(sdf_to_mesh(v), 256, views=[(30, 30)]) for v in (pebbles, more)]
    ball = bumpy(10242, rng=0)
    elements, faces = mesh_quilting(data.swatch("rivets"), ball, unit_length=0.13, rng=0)
    joined = (np.concatenate([ball.vertices, elements]), np.concatenate([ball.faces, faces + len(ball.vertices)]))
    return row(*views, render_mesh(joined, 256, views=[(30, 20)]))


FIGURES = {f.__name__: f for f in (hero, enlarge, tileable, hole, uncrop, pbr, batch, surface, animation, clip,
                                   geometry)}


def main(names):
    total = 0
    for name in names or FIGURES:
        start = time.perf_counter()
        size = save(name, FIGURES[name]())
        total += size
        print(f"readme_{name}.png  {time.perf_counter() - start:6.1f} s  {size / 1000:6.1f} kB", flush=True)
    print(f"total {total / 1000:.0f} kB")


if __name__ == "__main__":
    main(sys.argv[1:])
