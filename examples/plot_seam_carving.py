"""
Seam carving: content-aware resizing and object removal (Avidan & Shamir 2007)
==============================================================================

A 512 x 512 photograph (scikit-image's astronaut) is made narrower (384 columns)
and wider (640 columns) by removing and inserting seams of least gradient energy,
next to plain rescaling to the same sizes (``skimage.transform.resize``): seam
carving keeps the astronaut's face and the flag at their proportions and takes the
columns out of (or puts them into) the plain background, where rescaling squeezes
or stretches everything alike.

Then object removal: in scikit-image's rocket photograph one of the lightning towers
is masked, and seams are removed until no masked pixel is left, then inserted again
to restore the width (Section 4.6 of the paper).

Writes ``examples/output/seam_carving_resize.png``, ``seam_carving_removal.png``
and the figures ``seam_carving.png`` and ``seam_carving_object_removal.png``;
``python plot_seam_carving.py --docs`` in a checkout also refreshes the
documentation's copies in ``docs/_static/``.
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

from texsynth.io import save_image
from texsynth.patch import carve_seams

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)
# the figures of the documentation, refreshed only on request (never by the docs build itself)
FOLDERS = [OUT] + ([HERE.parent / "docs" / "_static"] if "--docs" in sys.argv else [])

photo = skdata.astronaut() / 255.0  # 512 x 512 colour photograph
results = {}
for width in (384, 640):
    started = time.perf_counter()
    carved = carve_seams(photo, (512, width))
    seconds = time.perf_counter() - started
    scaled = resize(photo, (512, width), anti_aliasing=True)
    results[width] = (carved, scaled, seconds)
    print(f"512 x 512 -> 512 x {width}: seam carving {seconds:.2f} s")

# object removal: the left inner lightning tower of the rocket photograph
rocket = skdata.rocket() / 255.0  # 427 x 640
mask = np.zeros(rocket.shape[:2], bool)
mask[110:300, 178:214] = True  # the mast and the upper tower
mask[300:427, 160:216] = True  # its wider foot and its lamps
started = time.perf_counter()
removed, info = carve_seams(rocket, remove_mask=mask, enlarge=False, return_info=True)
restored = carve_seams(rocket, remove_mask=mask)
print(f"object removal: {info.n_removed[1]} seams removed in {time.perf_counter() - started:.2f} s "
      f"(with restoring the width)")

save_image(OUT / "seam_carving_resize.png",
           np.concatenate([results[384][0], np.ones((512, 8, 3)), results[640][0]], axis=1), overwrite=True)
save_image(OUT / "seam_carving_removal.png", np.concatenate([rocket, np.ones((427, 8, 3)), restored], axis=1),
           overwrite=True)



def figure(panels, widths, height, name):
    """Images side by side at their relative widths, titled; saved to FOLDERS."""
    fig, axes = plt.subplots(1, len(panels), figsize=(16, height), gridspec_kw={"width_ratios": widths})
    for ax, (image, title) in zip(axes, panels):
        ax.imshow(np.clip(image, 0, 1))
        ax.set_title(title, fontsize=9)
        ax.axis("off")
    fig.tight_layout()
    for folder in FOLDERS:
        fig.savefig(folder / name, dpi=80)


figure([(photo, "input 512 x 512"), (results[384][0], "seam carving to 384 wide"),
        (results[384][1], "rescaling to 384 wide"), (results[640][0], "seam carving to 640 wide"),
        (results[640][1], "rescaling to 640 wide")], [512, 384, 384, 640, 640], 3.4, "seam_carving.png")
marked = np.where(mask[..., None], 0.5 * rocket + 0.5 * np.array([1.0, 0.0, 0.0]), rocket)
figure([(marked, "input, the mask in red"), (removed, f"the tower removed ({info.n_removed[1]} seams)"),
        (restored, "the width restored by inserting seams")], [640, 640 - info.n_removed[1], 640], 3.9,
       "seam_carving_object_removal.png")
