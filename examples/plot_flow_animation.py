"""
Flow-guided texture animation (Kwatra et al. 2005, Section 4.1, Figures 1 and 7)
================================================================================

A texture animated along a flow field. Frame 1 is an ordinary synthesis;
every next frame starts from the previous one warped along the flow and is
re-synthesised with the warped frame as a soft constraint (eq. 3), at a
single resolution as in the paper.

Figure 7 of the paper compares this with plain warping: warping the first
frame again and again along a rotation leaves holes (the corners come from
outside the frame) and smears the texture elements (each warp blurs them a
little more), while flow-guided synthesis keeps the elements' shape.

The run prints, per frame 1, 8 and 16, the texture energy (eq. 1 measured
by texsynth.metrics) and the sharpness (mean absolute difference of
neighbouring pixels, relative to frame 1), and the flicker (mean absolute
change against the warped previous frame), for the default frames'
E-step (``frame_falloff=0.25``) and the plain one (``frame_falloff=None``).

A time-varying flow (the paper: "flow fields that may dynamically change
over time") is given as a callable of the frame index: a vortex whose
strength swings from counter-clockwise to clockwise and back, plus a drift
whose direction turns through a full circle over the sequence.

Saves ``examples/output/flow_rotation.gif``, ``flow_rotation_frames.png``,
``flow_sink.gif``, ``flow_sink.png``, ``flow_varying.gif``,
``flow_varying.png`` and ``flow_vs_warp.png``.
"""

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from skimage.transform import rescale  # noqa: E402

from texsynth import data, metrics
from texsynth.core import flows  # noqa: E402
from texsynth.io import save_frames  # noqa: E402
from texsynth.optimization import Animation, animate_texture  # noqa: E402

HERE = Path(__file__).resolve().parent if "__file__" in globals() else Path.cwd()  # the gallery runs without __file__
OUT = HERE / "output"
OUT.mkdir(exist_ok=True)

# the bundled nuts (256 px, grey) at half size: distinct elements, several across a frame
exemplar = rescale(data.load("nuts"), 0.5, anti_aliasing=True)
shape, frames = (128, 128), 16

# Figure 7: rotation about the centre, 0.06 rad (3.4 degrees) per frame
rot = flows.rotation(shape, 0.06)


def sharpness(img):
    return np.mean(np.abs(np.diff(img, axis=0))) + np.mean(np.abs(np.diff(img, axis=1)))


def report(name, video, seconds):
    keys = (1, 8, 16)
    energy = [metrics.texture_energy(video[k - 1], exemplar) for k in keys]
    sharp = [sharpness(video[k - 1]) / sharpness(video[0]) for k in keys]
    inner = (slice(16, 112), slice(16, 112))
    flicker = np.mean([np.mean(np.abs(video[i + 1] - flows.warp(video[i], rot, mode="nearest", spline_order=3))[inner])
                       for i in range(frames - 1)])
    print(f"{name}: {seconds:.2f} s per frame; texture energy frames {keys}: "
          + ", ".join(f"{e:.5f}" for e in energy) + "; sharpness " + ", ".join(f"{v:.2f}" for v in sharp)
          + f"; flicker {flicker:.4f}")


video, info = animate_texture(exemplar, rot, n_frames=frames, rng=0, return_info=True)
save_frames(OUT / "flow_rotation.gif", video, fps=8, overwrite=True)
print(f"rotation: frame 1 {info.first.seconds:.1f} s")
report("frame_falloff=0.25 (default)", video, info.frame_seconds.mean())
plain, pinfo = animate_texture(exemplar, rot, n_frames=frames, first_frame=video[0],
                               animation=Animation(frame_falloff=None), rng=0, return_info=True)
report("frame_falloff=None (plain E-step)", plain, pinfo.frame_seconds.mean())

fig, axes = plt.subplots(2, 4, figsize=(14, 7.4))
for row, (vid, name) in enumerate([(video, "default"), (plain, "plain E-step")]):
    for a, k in zip(axes[row], [0, 3, 7, 15]):
        a.imshow(np.clip(vid[k], 0, 1), cmap="gray", vmin=0, vmax=1)
        a.set_title(f"{name}, frame {k + 1}")
        a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "flow_rotation_frames.png", dpi=100)

# plain warping of frame 1, frame after frame (what the synthesis is compared with)
warped = [video[0]]
for _ in range(frames - 1):
    warped.append(flows.warp(warped[-1], rot, mode="constant"))

fig, axes = plt.subplots(1, 3, figsize=(12, 4.4))
for a, img, title in zip(axes, [video[0], warped[-1], video[-1]],
                         ["frame 1", f"plain warping, frame {frames}", f"flow-guided synthesis, frame {frames}"]):
    a.imshow(np.clip(img, 0, 1), cmap="gray", vmin=0, vmax=1)
    a.set_title(title)
    a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "flow_vs_warp.png", dpi=100)

# Figure 1: a sink, the texture drains into the centre
sink = flows.sink(shape, 1.5)
video_sink = animate_texture(exemplar, sink, n_frames=frames, first_frame=video[0], rng=0)
save_frames(OUT / "flow_sink.gif", video_sink, fps=8, overwrite=True)
fig, axes = plt.subplots(1, 4, figsize=(14, 3.8))
for a, k in zip(axes, [0, 5, 10, 15]):
    a.imshow(np.clip(video_sink[k], 0, 1), cmap="gray", vmin=0, vmax=1)
    a.set_title(f"sink, frame {k + 1}")
    a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "flow_sink.png", dpi=100)

# A time-varying flow, as a callable of the frame index i (flow from frame i to i + 1):
# a vortex whose strength swings from +1.5 to -1.5 px per frame and back, on top of a
# drift of 1 px per frame whose direction turns once around the circle.
def varying(i):
    phase = 2 * np.pi * i / (frames - 1)
    swirl = flows.vortex(shape, 1.5 * np.cos(phase))
    drift = flows.translation(shape, (np.sin(phase), np.cos(phase)))
    return swirl + drift


video_var = animate_texture(exemplar, varying, n_frames=frames, first_frame=video[0], rng=0)
save_frames(OUT / "flow_varying.gif", video_var, fps=8, overwrite=True)
var_seq = flows.flow_sequence(varying, frames)
var_flicker = [np.mean(np.abs(video_var[i + 1] - flows.warp(video_var[i], var_seq[i], mode="nearest", spline_order=3))
                       [16:112, 16:112]) for i in range(frames - 1)]
print("time-varying vortex + turning drift: flicker (mean abs change against the warped previous frame) "
      f"{np.mean(var_flicker):.4f}; sharpness frames 8, 16: "
      + ", ".join(f"{sharpness(video_var[k - 1]) / sharpness(video_var[0]):.2f}" for k in (8, 16)))
fig, axes = plt.subplots(2, 4, figsize=(14, 7.4))
step = 6
yy, xx = np.mgrid[step // 2:shape[0]:step, step // 2:shape[1]:step]
for a, k in zip(axes[0], [0, 4, 8, 12]):
    f = var_seq[k][step // 2::step, step // 2::step]
    a.quiver(xx, yy, f[..., 1], -f[..., 0], angles="xy", scale_units="xy", scale=0.4)
    a.set_xlim(0, shape[1]); a.set_ylim(shape[0], 0); a.set_aspect("equal")  # noqa: E702
    a.set_title(f"flow {k + 1} -> {k + 2}")
    a.axis("off")
for a, k in zip(axes[1], [0, 5, 10, 15]):
    a.imshow(np.clip(video_var[k], 0, 1), cmap="gray", vmin=0, vmax=1)
    a.set_title(f"time-varying flow, frame {k + 1}")
    a.axis("off")
fig.tight_layout()
fig.savefig(OUT / "flow_varying.png", dpi=100)
