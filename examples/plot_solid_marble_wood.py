"""
Solid textures: a sphere and a cube cut from marble and wood
============================================================

The slides "Example: Marble Texture Function" and "Solid Textures" (Peachey
1985, Perlin 1985): a texture defined everywhere in 3-D space, so any object
carved from it shows continuous veins or growth rings across its faces and
edges, with no parameterisation of the surface. Here 3-D marble and wood
volumes (128^3) are evaluated once and sampled at the visible surface points
of a sphere and of a rotated cube (orthographic ray casting with numpy,
trilinear sampling with ``scipy.ndimage.map_coordinates``, Lambert shading).

Figures (examples/output/): ``procedural_solid.png`` (marble and wood
sphere and cube) and ``procedural_marble_wood_2d.png`` (2-D marble with the
default and two other transfer functions, and 2-D wood).
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from scipy.ndimage import map_coordinates

from texsynth.procedural import marble, wood

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
SIZE = 128  # volume resolution
PIX = 300  # rendered image size
LIGHT = np.array([-0.5, 0.6, 0.65]) / np.linalg.norm([-0.5, 0.6, 0.65])

marble_vol = marble((SIZE, SIZE, SIZE), frequency=3, veins=2.5, turbulence_strength=5.0, rng=7,
                    dtype=np.float32)
wood_vol = wood((SIZE, SIZE, SIZE), frequency=2, rings=7, turbulence_strength=1.2, center=(0.35, 0.4), rng=7,
                dtype=np.float32)


def rotation(yaw, pitch):
    cy, sy, cp, sp = np.cos(yaw), np.sin(yaw), np.cos(pitch), np.sin(pitch)
    ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    rx = np.array([[1, 0, 0], [0, cp, -sp], [0, sp, cp]])
    return rx @ ry


def cast(shape_kind, rot):
    """Hit points (in the object's [0, 1]^3 frame), normals (view frame) and a mask."""
    u = np.linspace(-1, 1, PIX)
    x, y = np.meshgrid(u, -u)  # view plane, camera looks along -z
    origin = np.stack([x, y, np.full_like(x, 5.0)], axis=-1).reshape(-1, 3)
    direction = np.array([0.0, 0.0, -1.0])
    if shape_kind == "sphere":
        r = 0.9
        b = origin @ direction
        c = (origin**2).sum(1) - r * r
        disc = b * b - c
        hit = disc >= 0
        t = -b - np.sqrt(np.where(hit, disc, 0))
        point = origin + t[:, None] * direction
        normal = point / r
    else:  # cube [-h, h]^3 rotated by rot: slab method in the cube's frame
        h = 0.55
        o_local = origin @ rot  # rot is orthonormal: local = R^T p  ->  p @ R
        d_local = direction @ rot
        with np.errstate(divide="ignore", invalid="ignore"):
            t1 = (-h - o_local) / d_local
            t2 = (h - o_local) / d_local
        tmin = np.nanmax(np.minimum(t1, t2), axis=1)
        tmax = np.nanmin(np.maximum(t1, t2), axis=1)
        hit = tmax >= tmin
        point_local = o_local + tmin[:, None] * d_local
        face = np.argmax(np.abs(point_local) / h, axis=1)
        n_local = np.zeros_like(point_local)
        n_local[np.arange(len(face)), face] = np.sign(point_local[np.arange(len(face)), face])
        normal = n_local @ rot.T
        point = point_local @ rot.T
    # object coordinates: rotate the world point into the solid, map to [0, 1]
    local = point @ rot if shape_kind == "sphere" else point_local
    extent = 0.9 if shape_kind == "sphere" else 0.55
    return (local / extent + 1) / 2, normal, hit


def render(volume, shape_kind, rot):
    coords01, normal, hit = cast(shape_kind, rot)
    idx = np.clip(coords01, 0, 1) * (SIZE - 1)  # (x, y, z) -> volume index (z, y, x)
    colour = np.stack([map_coordinates(volume[..., ch], [idx[:, 2], idx[:, 1], idx[:, 0]], order=1)
                       for ch in range(3)], axis=-1)
    shade = 0.25 + 0.75 * np.clip(normal @ LIGHT, 0, 1)
    image = np.where(hit[:, None], colour * shade[:, None], 1.0)
    return image.reshape(PIX, PIX, 3).clip(0, 1)


rot_sphere = rotation(0.5, 0.3)
rot_cube = rotation(0.62, 0.5)
fig, axes = plt.subplots(2, 2, figsize=(9, 9))
for row, (vol, name) in enumerate([(marble_vol, "marble"), (wood_vol, "wood")]):
    for col, kind in enumerate(["sphere", "cube"]):
        axes[row, col].imshow(render(vol, kind, rot_sphere if kind == "sphere" else rot_cube))
        axes[row, col].set_title(f"{name} {kind} cut from a {SIZE}^3 solid texture", fontsize=10)
        axes[row, col].axis("off")
fig.tight_layout()
fig.savefig(OUT / "procedural_solid.png", dpi=80)

# %%
# 2-D marble with several transfer functions, and 2-D wood
panels = [
    (marble((256, 256), rng=2), "marble, default transfer (white, grey veins)"),
    (marble((256, 256), rng=2, colormap=[(0.0, "#1b2a1f"), (0.3, "#3f6b4a"), (1.0, "#d9e8d0")]),
     "green marble (list of (position, colour))"),
    (marble((256, 256), rng=2, turbulence_strength=0), "turbulence_strength=0: sin(x) layers"),
    (wood((256, 256), rng=2), "wood: rings sin(r) + turbulence"),
]
fig, axes = plt.subplots(1, 4, figsize=(16, 4.4))
for ax, (img, title) in zip(axes, panels):
    ax.imshow(img)
    ax.set_title(title, fontsize=9)
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "procedural_marble_wood_2d.png", dpi=80)
print("wrote procedural_solid.png, procedural_marble_wood_2d.png")
