"""
Texture synthesis on surfaces: vertex synthesis and lapped textures
===================================================================

Four surfaces, two methods (docs/methods/surfaces.md):

- ``synthesize_surface`` (Turk 2001; Wei & Levoy 2001) on a sphere retiled to
  20,000 vertices with the bundled red-brick photograph and a *latitude* field
  (``lambda p: np.cross([0, 0, 1], p)``): the courses run round the sphere and
  close in rings at the poles, the field's two singularities;
- the same on a torus with the relaxed (``"smooth"``) field and the bundled
  reptile-skin photograph;
- ``lapped_textures`` (Praun et al. 2000) on the bumpy sphere with the bundled
  brick photograph and the smooth field, and on the Stanford Bunny
  (``scanned_mesh()``) with the bread photograph.

Writes the meshes to ``examples/output/`` (PLY) and the figure
``surface_synthesis.png`` (render_mesh previews, two views each);
``python plot_surface_synthesis.py --docs`` in a checkout also refreshes the
documentation's copy in ``docs/_static/``.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth.data import load
from texsynth.surface import (bumpy, lapped_textures, render_mesh, scanned_mesh, sphere, synthesize_surface,
                              torus, write_mesh)

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figure of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])

# the documentation's figure at full resolution (--docs); the gallery and a plain run with fewer vertices and a
# coarser Bunny (about half the time)
FULL = "--docs" in sys.argv
N_VERTICES = 20000 if FULL else 5000
PIXEL = (0.5 if FULL else 1.0) / 128  # the Bunny's lapped textures: the length of an exemplar pixel on it ...
TEXELS = 8 if FULL else 4  # ... and the side of each face's cell in the baked atlas

brick = load("brick")
reptile = load("reptile")[:128, :128]
bread = load("bread")[:128, :128]

runs = [
    ("vertex synthesis, sphere, latitude field", lambda: synthesize_surface(
        sphere(10242), brick, n_vertices=N_VERTICES, field=lambda p: np.cross([0, 0, 1.0], p), rng=0)),
    ("vertex synthesis, torus, smooth field", lambda: synthesize_surface(
        torus(10000), reptile, n_vertices=N_VERTICES, rng=0)),
    ("lapped textures, bumpy sphere", lambda: lapped_textures(bumpy(10242, rng=0), brick, rng=0)),
]
try:  # the Stanford Bunny ships with visvis: python -m pip install visvis (the mesh extra)
    bunny = scanned_mesh()
    runs.append(("lapped textures, Stanford Bunny",
                 lambda: lapped_textures(bunny, bread, pixel_size=PIXEL, texels=TEXELS, rng=0)))
except ModuleNotFoundError as error:
    print(f"skipping the Stanford Bunny: {error}")

fig, axes = plt.subplots(1, len(runs), figsize=(5 * len(runs), 3.1), dpi=150)
for ax, (title, run) in zip(axes, runs):
    start = time.perf_counter()
    mesh = run()
    seconds = time.perf_counter() - start
    name = title.replace(", ", "_").replace(" ", "_")
    write_mesh(OUT / f"{name}.ply", mesh, overwrite=True)
    ax.imshow(render_mesh(mesh, (400, 800), views=[(30, 25), (210, 25)]))
    ax.set_title(f"{title}\n{seconds:.1f} s", fontsize=9)
    ax.axis("off")
    print(f"{title}: {mesh}, {seconds:.1f} s")
fig.tight_layout()
for folder in FOLDERS:
    fig.savefig(folder / "surface_synthesis.png")
