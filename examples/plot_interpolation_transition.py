"""
Spatially varying interpolation: transition strip and a grey-image map
======================================================================

Ruiters et al. 2010, Figure 4 (a continuous transition strip from one
texture to the other) and Figure 7 (a transition controlled by a grey image
used as the distribution map of alpha). Interpolated neighbourhoods for
several alphas carry alpha as an extra channel that the synthesis matches to
the map. The pair is the bundled brick wall and wood grain (64 px crops), as
in ``plot_interpolation_sequence.py``, with the same shortened schedule.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

from texsynth import data
from texsynth.optimization import (InterpolationSchedule, NeighborhoodSet, VaryingAlpha, interpolate_textures,
                                   linear_blend, transition_alpha_map)

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

a = data.load("brick")[:64, :64]  # red bricks, light mortar
b = data.load("wood")[:64, :64]  # wood grain
options = dict(schedule=InterpolationSchedule(stages=((2, 17), (1, 9)), max_iterations=3),
               varying=VaryingAlpha(alpha_steps=6, statistics_bands=3),
               neighborhood_set=NeighborhoodSet(max_neighborhoods=300), rng=0)

strip_map = transition_alpha_map((64, 192))
strip = interpolate_textures(a, b, strip_map, **options)

# a grey image as distribution map (Figure 7): a disc of texture 2 inside texture 1
yy, xx = np.mgrid[:96, :96]
disc = np.clip((30 - np.hypot(yy - 48, xx - 48)) / 9 + 0.5, 0, 1)
controlled = interpolate_textures(a, b, disc, **options)

fig, axes = plt.subplots(3, 2, figsize=(10, 8), gridspec_kw=dict(width_ratios=[2, 1]))
axes[0, 0].imshow(np.clip(strip, 0, 1))
axes[0, 0].set_title("transition strip (ours)")
axes[1, 0].imshow(linear_blend(np.tile(a, (1, 3, 1)), np.tile(b, (1, 3, 1)), strip_map))
axes[1, 0].set_title("linear blend with the same alpha ramp")
axes[2, 0].imshow(strip_map, cmap="gray")
axes[2, 0].set_title("alpha map")
axes[0, 1].imshow(np.clip(controlled, 0, 1))
axes[0, 1].set_title("grey-image controlled")
axes[1, 1].imshow(disc, cmap="gray")
axes[1, 1].set_title("distribution map")
axes[2, 1].imshow(np.concatenate([a, b], 1))
axes[2, 1].set_title("I1 | I2")
for ax in axes.ravel():
    ax.axis("off")
fig.tight_layout()
fig.savefig(OUT / "interpolation_transition.png", dpi=80)
print("saved", OUT / "interpolation_transition.png")
