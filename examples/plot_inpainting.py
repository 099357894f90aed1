"""
Hole filling with soft constraints (Kwatra et al. 2005, Section 4)
==================================================================

``embark/bricks.png`` has a round hole in its alpha channel. Texture
optimization fills it: the known pixels are soft constraints (eq. 2,
``λ = 100`` makes them nearly hard), their neighbourhoods are searched for
exemplar neighbourhoods that agree with them (the modified M-step of
Algorithm 2), and the hole is synthesised from neighbourhoods of the same
image that do not touch the hole (``exemplar_mask``).

The image is processed at half resolution (175 x 175) to keep the example
quick. Saves ``examples/output/inpainting_bricks.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from texsynth.io import load_image, save_image  # noqa: E402
from texsynth.optimization import optimize_texture  # noqa: E402
from texsynth.pyramid import downsample  # noqa: E402

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
OUT = Path(__file__).resolve().parent / "output"
OUT.mkdir(exist_ok=True)

rgba = load_image(TEXTURES / "embark" / "bricks.png")
small = downsample(rgba)  # (175, 175, 4)
known = small[..., 3] > 0.999  # pixels untouched by the hole
image = small[..., :3]

filled, info = optimize_texture(
    image, image.shape[:2], neighborhood_sizes=(16, 8), levels=2,
    mask=known, target=image, constraint_weight=100.0, exemplar_mask=known,
    rng=0, return_info=True,
)
save_image(OUT / "inpainting_bricks_result.png", filled, overwrite=True)
hole = ~known
print(f"hole: {hole.sum()} px, time {info.seconds:.1f} s, nn share {info.nn_share:.2f}")
print("RMS change of known pixels:", float(np.sqrt(np.mean((filled[known] - image[known]) ** 2))).__round__(4))

shown = image.copy()
shown[hole] = [1.0, 0.0, 1.0]  # the hole in magenta
fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
for a, img, title in zip(axes, [shown, filled, filled[30:130, 30:130]],
                         ["input (hole in magenta)", "filled by texture optimization", "detail"]):
    a.imshow(img)
    a.set_title(title)
    a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "inpainting_bricks.png", dpi=100)
