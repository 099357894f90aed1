"""
Hole filling with soft constraints (Kwatra et al. 2005, Section 4)
==================================================================

The bundled ``bricks_hole`` (``texsynth.data``) has a round hole in its alpha channel. Texture
optimization fills it: the known pixels are soft constraints (eq. 2,
``λ = 100`` makes them nearly hard), their neighbourhoods are searched for
exemplar neighbourhoods that agree with them (the modified M-step of
Algorithm 2), and the hole is synthesised from neighbourhoods of the same
image that do not touch the hole (``exemplar_mask``).

The sample is Embark Studios' ``bricks.png`` at half resolution (175 x 175),
filled with the library's defaults (3 levels, neighbourhoods 32, 16, 8).
Fewer levels and smaller neighbourhoods (2 levels, 16 and 8, the example's
earlier settings) fill the hole with smeared bricks whose mortar fades
toward the centre: with 2 levels the coarsest level sees the hole at
39 x 44 px, wider than its largest (16-px) neighbourhoods, so nothing
carries the brick rows across it, and the overlapping ``z_p`` inside it
disagree and average into blur. With 3 levels it is 20 x 22 px at the
coarsest level, spanned by 16-px neighbourhoods, and 32-px neighbourhoods
at half resolution carry the rows on. Both are
shown (``inpainting_bricks.png``), with the sharpness (mean absolute
difference of neighbouring pixels) of the hole's interior relative to the
known pixels'.

Saves ``examples/output/inpainting_bricks.png`` and
``inpainting_bricks_result.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from scipy import ndimage  # noqa: E402

from texsynth import data  # noqa: E402
from texsynth.io import save_image  # noqa: E402
from texsynth.optimization import Constraints, Schedule, optimize_texture  # noqa: E402

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

rgba = data.load("bricks_hole")  # (175, 175, 4): colour and alpha, 0 in the hole
known = rgba[..., 3] > 0.999  # pixels untouched by the hole
image = rgba[..., :3]

hole = ~known
core = ndimage.binary_erosion(hole, iterations=3)  # the hole's interior, away from its rim


def sharpness(img, where):
    """Mean absolute difference of neighbouring pixels inside ``where``."""
    dx = np.abs(np.diff(img, axis=1)).mean(-1)[where[:, 1:] & where[:, :-1]]
    dy = np.abs(np.diff(img, axis=0)).mean(-1)[where[1:] & where[:-1]]
    return (dx.mean() + dy.mean()) / 2


common = dict(constraints=Constraints(mask=known, target=image, constraint_weight=100.0, exemplar_mask=known), rng=0,
              return_info=True)
filled, info = optimize_texture(image, image.shape[:2], **common)  # defaults: 3 levels, 32/16/8
smeared, sinfo = optimize_texture(image, image.shape[:2], schedule=Schedule(neighborhood_sizes=(16, 8), levels=2),
                                  **common)
save_image(OUT / "inpainting_bricks_result.png", filled, overwrite=True)
print(f"hole: {hole.sum()} px")
for name, img, inf in [("defaults (3 levels, 32/16/8)", filled, info), ("2 levels, 16/8", smeared, sinfo)]:
    print(f"{name}: {inf.seconds:.1f} s, RMS change of known pixels "
          f"{np.sqrt(np.mean((img[known] - image[known]) ** 2)):.4f}, sharpness of the hole's interior / known "
          f"{sharpness(img, core) / sharpness(image, known):.2f}")
blurred = ndimage.gaussian_filter(image, (1, 1, 0))
print("(the known pixels blurred by a Gaussian of sigma 1 px: "
      f"{sharpness(blurred, known) / sharpness(image, known):.2f})")

shown = image.copy()
shown[hole] = [1.0, 0.0, 1.0]  # the hole in magenta
fig, axes = plt.subplots(1, 4, figsize=(16, 4.4))
rows, cols = np.nonzero(hole)
box = np.s_[max(rows.min() - 8, 0):rows.max() + 9, max(cols.min() - 8, 0):cols.max() + 9]  # the hole and 8 px
for a, img, title in zip(axes, [shown, filled, filled[box], smeared[box]],
                         ["input (hole in magenta)", "filled (defaults: 3 levels, 32/16/8)", "detail",
                          "detail, 2 levels, 16/8: smeared"]):
    a.imshow(img)
    a.set_title(title)
    a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "inpainting_bricks.png", dpi=100)
