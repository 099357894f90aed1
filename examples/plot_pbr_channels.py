"""
PBR channel sets: one synthesis, albedo + height + normal map that line up
==========================================================================

A material for a game engine is a set of images of one surface: albedo (colour),
height, a tangent-space normal map, roughness. Synthesising each channel on its own
gives textures whose bumps do not sit under their colours. Instead, synthesise the
albedo once with ``return_info=True``: ``info.coordinates`` says, for every output
pixel, which exemplar pixel it was copied from (or, for blending methods, which
pixels it blends and with what weights), and :func:`texsynth.apply_coordinates`
renders every other channel through the same map. Normal maps are renormalised
where pixels blend (``normals=True``); 16-bit channels stay 16-bit.

The exemplar set is made from one photograph, the bundled red brick wall
(``texsynth.data.load("brick")``, 77 x 107): the height is its blurred luminance
(inverted: the dark bricks stand above the bright mortar), the normal map that
height's gradient. The set is synthesised twice, by image quilting (copies along
cuts) and by patch-based sampling (feathered blends), to 256 x 256. The last
column lights the synthesised normal map from the upper left: its bumps sit under
the bricks of the albedo. Writes the channels to ``examples/output/pbr_*.png``
(height and normals as 16-bit PNG) and the figure ``pbr_channels.png``;
``python plot_pbr_channels.py --docs`` in a checkout also refreshes the
documentation's copy in ``docs/_static/``.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from scipy import ndimage

from texsynth import apply_coordinates, data, patch_sampling, quilt
from texsynth.io import save_image

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figure of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])
SIZE = 256


def height_of(albedo, sigma=2.0):
    """A height map from a photograph: its blurred luminance, inverted (the dark bricks stand above the
    bright mortar)."""
    lum = albedo[..., :3] @ np.array([0.2125, 0.7154, 0.0721])
    return 1 - ndimage.gaussian_filter(lum, sigma)


def normals_of(height, strength=12.0):
    """A tangent-space normal map of a height field (x right, y up, z out), encoded in [0, 1]."""
    gy, gx = np.gradient(height)
    n = np.stack([-strength * gx, strength * gy, np.ones_like(height)], -1)
    return (n / np.linalg.norm(n, axis=-1, keepdims=True) + 1) / 2


def lit(normal_map, light=(-1.0, 1.0, 1.5)):
    """Lambert shading of a normal map by a light from the upper left."""
    n = normal_map * 2 - 1
    direction = np.asarray(light) / np.linalg.norm(light)
    return np.clip(n @ direction, 0, 1)


albedo = data.load("brick")
height = height_of(albedo)
normal = normals_of(height)
exemplar_set = {"albedo": albedo, "height": height, "normal": normal}

rows = {f"exemplar ({albedo.shape[0]} x {albedo.shape[1]})": exemplar_set}
for name, method in (("quilt", quilt), ("patch sampling", patch_sampling)):
    started = time.perf_counter()
    out, info = method(albedo, SIZE, block=32, rng=1, return_info=True)
    channels = apply_coordinates({"height": height, "normal": normal}, info, normals={"normal": True})
    seconds = time.perf_counter() - started
    lengths = np.linalg.norm(channels["normal"] * 2 - 1, axis=-1)
    print(f"{name}: {seconds:.2f} s; map {info.coordinates.shape}, normals' length {lengths.min():.6f}-"
          f"{lengths.max():.6f}")
    rows[f"{name} ({SIZE} x {SIZE})"] = {"albedo": out, **channels}
    slug = name.replace(" ", "_")
    save_image(OUT / f"pbr_{slug}_albedo.png", out, overwrite=True)
    save_image(OUT / f"pbr_{slug}_height.png", channels["height"], bits=16, overwrite=True)
    save_image(OUT / f"pbr_{slug}_normal.png", channels["normal"], bits=16, overwrite=True)

fig, axes = plt.subplots(len(rows), 4, figsize=(12, 3.2 * len(rows)))
for r, (title, images) in enumerate(rows.items()):
    panels = [images["albedo"], images["height"], images["normal"], lit(images["normal"])]
    labels = ["albedo", "height", "normal map", "normal map, lit from the upper left"]
    for ax, image, label in zip(axes[r], panels, labels):
        ax.imshow(image, cmap="gray" if image.ndim == 2 else None, vmin=0, vmax=1)
        ax.set_title(f"{title}: {label}" if label == "albedo" else label, fontsize=9)
        ax.axis("off")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "pbr_channels.png", dpi=80)
    print(f"wrote {folder / 'pbr_channels.png'}")
