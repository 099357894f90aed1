"""
Solid texture from 2-D views, rendered as a sphere (Wei 2002, Figure 2)
=======================================================================

The same exemplar is the view along x, y and z; each view's neighbourhood lies
in the plane perpendicular to its axis. The volume is rendered by a small
numpy ray-caster: a sphere whose surface points take the colour of the voxel
they cut (nearest voxel, toroidal), with Lambert shading; then a cube with
its three visible faces, and three axis slices.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.metrics import mosaic_baseline, noise_baseline, texture_energy
from texsynth.pixel import synthesize_solid

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
N = 40  # volume side: about 10 s (64 takes about 45 s; kd-tree search)

ex = data.load("bread")[:64, :64]  # the bundled bread, a 64 px crop
vol = synthesize_solid(ex, N, rng=0)


def sphere(volume, res=256):
    """Orthographic ray-cast of the sphere inscribed in the volume."""
    n = volume.shape[0]
    y, x = np.mgrid[-1 : 1 : res * 1j, -1 : 1 : res * 1j]
    inside = x**2 + y**2 <= 1
    z = np.sqrt(np.clip(1 - x**2 - y**2, 0, None))
    pts = np.stack([z, -y, x], -1)  # (depth, height, width) coordinates in [-1, 1]
    idx = np.clip(((pts + 1) / 2 * (n - 1)).round().astype(int), 0, n - 1)
    colour = volume[idx[..., 0], idx[..., 1], idx[..., 2]]
    light = np.clip(0.35 + 0.65 * (0.4 * x - 0.5 * y + 0.77 * z), 0, 1)
    img = np.ones(x.shape + (3,))
    img[inside] = colour[inside] * light[inside, None]
    return img


def cube(volume):
    """Three faces of the volume: top (z slice 0), front (y slice -1), right (x slice -1)."""
    n = volume.shape[0]
    top, front, right = volume[0], volume[:, -1, :], volume[:, :, -1]
    canvas = np.ones((2 * n, 2 * n, 3))
    canvas[n // 2 : n // 2 + n, :n] = front
    canvas[n // 2 : n // 2 + n, n : 2 * n] = right * 0.8
    for r in range(n // 2):  # top face sheared into a parallelogram
        canvas[r, n // 2 - r : n // 2 - r + n] = top[2 * r] * 1.1
    return np.clip(canvas, 0, 1)


slices = [vol[N // 2], vol[:, N // 2], vol[:, :, N // 2]]
noise = texture_energy(noise_baseline(ex, N, rng=0), ex)
# Baselines for the slices: noise (right values, no structure), random 16x16 exemplar blocks
# pasted edge to edge (copied pixels, wrong seams), and extrusion (the exemplar repeated along
# depth: perfect z slices, streaks along y and x, which a solid must avoid).
mosaic = np.mean([texture_energy(mosaic_baseline(ex, N, rng=k), ex) for k in range(3)])
extruded = np.broadcast_to(ex[:N, :N][None], (N, N, N, 3))
print("texture energy of the middle slices (along z, y, x):", [round(texture_energy(s, ex), 4) for s in slices])
print(f"baselines: noise {noise:.4f}, mosaic {mosaic:.4f}, extrusion (z, y, x) "
      f"{[round(texture_energy(s, ex), 4) for s in (extruded[N // 2], extruded[:, N // 2], extruded[:, :, N // 2])]}")
fig, axes = plt.subplots(1, 6, figsize=(18, 3.4))
for ax, img, title in zip(
    axes,
    [ex, sphere(vol), cube(vol)] + slices,
    ["exemplar (x, y, z views)", f"sphere cut from the {N}^3 solid", "cube faces"]
    + [f"slice along {a}: E={texture_energy(s, ex):.4f} (noise {noise:.4f})" for a, s in zip("zyx", slices)],
):
    ax.imshow(img, vmin=0, vmax=1)
    ax.set_title(title, fontsize=8)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "solid_texture.png", dpi=80)
