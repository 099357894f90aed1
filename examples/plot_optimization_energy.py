"""
Texture energy per iteration (Kwatra et al. 2005, Figure 3)
===========================================================

The energy of eq. 1 after every EM iteration, the stages (resolution level,
neighbourhood size) concatenated in synthesis order. Within a stage the
minimised (robust) energy falls from iteration to iteration, with an
occasional rise (in this run once, at half resolution with 16 px
neighbourhoods); it jumps at every change of level or size, as in the
paper. The normalised curve divides eq. 1 by the number of neighbourhoods
and values per neighbourhood, as the paper's plot does, so stages are
comparable. The exemplar is the bundled ``nuts`` at half size
(128 px). Saves ``examples/output/optimization_energy.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from skimage.transform import rescale  # noqa: E402

from texsynth import data  # noqa: E402
from texsynth.optimization import Schedule, optimize_texture  # noqa: E402

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

exemplar = rescale(data.load("nuts"), 0.5, anti_aliasing=True)
out, info = optimize_texture(exemplar, 192, rng=0, schedule=Schedule(tolerance=0.0), return_info=True)

fig, (ax, ax2, ax3) = plt.subplots(1, 3, figsize=(15, 4.5), gridspec_kw={"width_ratios": [2, 2, 1.2]})
it = np.arange(len(info.energy))
for k, s in enumerate(info.stages):
    sel = info.stage == k
    label = f"1/{2 ** s.level}, {s.size}x{s.size}"
    ax.plot(it[sel], info.mse[sel], "o-", label=label)
    ax2.plot(it[sel], info.energy[sel] / info.energy[sel][0], "o-")
for b in info.boundaries[1:]:
    for a in (ax, ax2):
        a.axvline(b - 0.5, color="0.8", lw=0.8)
ax.set(xlabel="iteration", ylabel="eq. 1 energy / (neighbourhoods x values)", title="normalised texture energy")
ax.legend(title="resolution, size", fontsize=8)
ax2.set(xlabel="iteration", ylabel="E / E at stage start",
        title="minimised robust energy (r = 0.8), per stage")
ax3.imshow(np.clip(out, 0, 1), cmap="gray", vmin=0, vmax=1)
ax3.set_title("result, 192 x 192")
ax3.axis("off")
fig.tight_layout()
fig.savefig(OUT / "optimization_energy.png", dpi=100)
for s in info.stages:
    e = info.energy[s.first : s.first + s.iterations + (0 if s.first == 0 else 1)]
    print(f"level {s.level} size {s.size:2d}: {s.iterations} iterations, converged={s.converged}, "
          f"{s.seconds:.2f} s, energy {e[0]:.4g} -> {e[-1]:.4g}")
