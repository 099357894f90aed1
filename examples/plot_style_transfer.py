"""
Style transfer by guided synthesis: a photograph painted in a texture (Hertzmann et al. 2001)
=============================================================================================

*Image analogies* (Hertzmann, Jacobs, Oliver, Curless & Salesin, SIGGRAPH 2001,
doi:10.1145/383259.383295) renders a target photograph in the style of a texture: the output
is synthesised from the texture, and each output neighbourhood must match the texture's
neighbourhood in colour and, at the same time, match the photograph's luminance where the
texture's luminance matches. That is guided synthesis with two grey guides:

- ``exemplar_guide``: the texture's own luminance, remapped to the photograph's mean and
  standard deviation (the paper's *luminance remapping*, its Section 3.4, so that a dark
  texture can still follow a bright photograph);
- ``output_guide``: the photograph's luminance.

:func:`texsynth.optimize_texture` adds the guides as extra channels of every neighbourhood
(``guide_weight`` weighs them against the colours), so the output takes the texture's colours
and grain and the photograph's light and dark. Texture by numbers (label maps as guides) is
the same call with other guides (``docs/methods/kwatra.md``).

Photograph: scikit-image's ``camera`` (128 px). Textures: the bundled water caustics
(``water``), wood and pink ink in water (``ink``), 96 px crops. Writes
``examples/output/style_transfer_*.png`` and the figure ``style_transfer.png``: the
photograph, then per texture the exemplar (above, at its size) and the result;
``python plot_style_transfer.py --docs`` in a checkout also refreshes the documentation's copy
in ``docs/_static/``. About 4 s per texture on a quiet 2-core machine.
"""

import sys
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np
from skimage import data as skdata
from skimage.transform import resize

from texsynth import data, optimize_texture
from texsynth.optimization import Guides
from texsynth.io import save_image

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figure of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])

#: weight of the guide (the photograph's luminance) against the colours: 4 follows the photograph a little
#: more closely than the default 1 (correlation of the output's luminance with it 0.958 against 0.951 on bread)
GUIDE_WEIGHT = 4.0


def luminance(image):
    """Rec. 709 luminance of an RGB image (a grey image is its own)."""
    return image[..., :3] @ np.array([0.2125, 0.7154, 0.0721]) if image.ndim == 3 else image


def remap(lum, reference):
    """Hertzmann et al.'s luminance remapping (Sec. 3.4): ``lum`` shifted and scaled to the reference's mean
    and standard deviation, clipped to [0, 1]."""
    return np.clip((lum - lum.mean()) / max(lum.std(), 1e-6) * reference.std() + reference.mean(), 0.0, 1.0)


def style_transfer(texture, photo, *, guide_weight=GUIDE_WEIGHT, rng=0):
    """``photo`` (grey, [0, 1]) painted in ``texture`` by guided texture optimization."""
    guides = Guides(exemplar_guide=remap(luminance(texture), photo), output_guide=photo, guide_weight=guide_weight)
    return optimize_texture(texture, photo.shape, guides=guides, rng=rng)


def main():
    photo = resize(skdata.camera() / 255.0, (128, 128), anti_aliasing=True)
    textures = {name: data.load(name)[:96, :96] for name in ("water", "wood", "ink")}
    columns = [np.repeat(photo[..., None], 3, -1)]
    for name, texture in textures.items():
        t = time.perf_counter()
        out = style_transfer(texture, photo)
        print(f"{name}: {time.perf_counter() - t:.1f} s, correlation of the output's luminance with the photograph "
              f"{np.corrcoef(luminance(out).ravel(), photo.ravel())[0, 1]:.3f}")
        save_image(OUT / f"style_transfer_{name}.png", out, overwrite=True)
        # the exemplar at its size above the result: one column of 96 + 128 px
        top = np.ones((96, 128, 3))
        top[:, 16:112] = texture
        columns.append(np.concatenate([top, out], 0))
    columns[0] = np.concatenate([np.ones((96, 128, 3)), columns[0]], 0)
    gap = np.ones((224, 6, 3))
    figure = np.concatenate([c for column in columns for c in (column, gap)][:-1], 1)
    figure = np.repeat(np.repeat(np.clip(figure, 0, 1), 2, 0), 2, 1)  # 2x, pixels visible
    for folder in FOLDERS:
        save_image(folder / "style_transfer.png", figure, overwrite=True)
    fig, ax = plt.subplots(figsize=(figure.shape[1] / 100, figure.shape[0] / 100), dpi=100)
    fig.subplots_adjust(0, 0, 1, 1)
    ax.imshow(figure, interpolation="nearest")
    ax.axis("off")


if __name__ == "__main__":
    main()
