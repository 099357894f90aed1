"""The figures of docs/methods/jamriska.md: a clip stylised from painted keyframes.

A simulated clip (``texsynth.data.clip``) gets "painted" keyframes made procedurally: the frame
posterised into a few luminance bands, each band a colour of a warm palette, modulated by the bundled
bread texture (a canvas grain) and outlined along the bands' edges (strokes). Then
:func:`texsynth.stylize_video` paints every frame, with the temporal guide and without it (each frame
on its own), and the script saves a strip (rows: frames, with the temporal guide, without) and a GIF.

    python benchmarks/figure_jamriska.py [--clip waves] [--frames 12] [--size 128] [--out docs/_static]
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

import texsynth
from texsynth.metrics import flicker
from texsynth.video import stylize_video

PALETTE = np.array([[0.10, 0.05, 0.20], [0.55, 0.12, 0.18], [0.93, 0.45, 0.15], [0.99, 0.86, 0.45]])


def paint(frame, bands=4):
    """A procedural "painting" of ``frame``: posterised luminance in a warm palette, canvas grain, outlines."""
    lum = frame @ np.array([0.2125, 0.7154, 0.0721]) if frame.ndim == 3 else frame
    lum = ndimage.gaussian_filter(lum, 1.0)
    edges = np.quantile(lum, np.linspace(0, 1, bands + 1)[1:-1])
    label = np.digitize(lum, edges)
    out = PALETTE[np.linspace(0, len(PALETTE) - 1, bands).round().astype(int)][label]
    grain = texsynth.data.load("bread")
    grain = grain.mean(axis=-1) if grain.ndim == 3 else grain
    reps = (-(-frame.shape[0] // grain.shape[0]), -(-frame.shape[1] // grain.shape[1]))
    grain = np.tile(grain, reps)[: frame.shape[0], : frame.shape[1]]
    out = out * (0.75 + 0.5 * (grain - grain.mean()))[..., None]
    outline = ndimage.morphological_gradient(label, size=2) > 0
    out[outline] *= 0.35
    return np.clip(out, 0.0, 1.0)


def main(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--clip", default="waves")
    parser.add_argument("--frames", type=int, default=12)
    parser.add_argument("--size", type=int, default=128)
    parser.add_argument("--out", default="docs/_static")
    parser.add_argument("--rng", type=int, default=0)
    args = parser.parse_args(argv)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    frames = texsynth.data.clip(args.clip, args.frames, args.size, rng=args.rng)
    last = args.frames - 1
    keys = {0: paint(frames[0]), last: paint(frames[last])}
    t0 = time.perf_counter()
    video, info = stylize_video(frames, keys, rng=args.rng, return_info=True)
    t1 = time.perf_counter()
    alone = stylize_video(frames, keys, temporal_weight=0.0, flows=info.flows, rng=args.rng)
    t2 = time.perf_counter()
    one = stylize_video(frames, {0: keys[0]}, flows=info.flows, rng=args.rng)
    def energy(v):
        return np.mean([texsynth.metrics.texture_energy(f, keys[0]) for f in v[1:-1]])

    print(f"{args.clip} {args.frames}x{args.size}^2: temporal {t1 - t0:.1f} s, per frame {t2 - t1:.1f} s")
    print(f"flicker along the motion: temporal {flicker(video, info.flows):.4f}, per frame "
          f"{flicker(alone, info.flows):.4f}, the clip itself {flicker(frames, info.flows):.4f}")
    print(f"texture energy against keyframe 0 (frames 1..T-2): temporal {energy(video):.5f}, per frame "
          f"{energy(alone):.5f}, keyframe 0 itself against keyframe {last}: "
          f"{texsynth.metrics.texture_energy(keys[last], keys[0]):.5f}")
    show = np.linspace(0, last, min(6, args.frames)).round().astype(int)
    def pad(row):
        return np.concatenate([np.pad(f, ((2, 2), (2, 2), (0, 0)), constant_values=1.0) for f in row], 1)

    strip = np.concatenate([pad(frames[show]), pad(video[show]), pad(alone[show]), pad(one[show])], axis=0)
    texsynth.io.save_image(out / f"jamriska_{args.clip}_strip.png", strip, overwrite=True)
    gif = np.concatenate([frames, video, alone], axis=2)
    texsynth.io.save_frames(out / f"jamriska_{args.clip}.gif", gif, fps=8, overwrite=True)
    print("rows of the strip: frames", show.tolist(), "| two keyframes, temporal guide | each frame on its own "
          "| keyframe 0 alone, carried forward")


if __name__ == "__main__":
    main()
