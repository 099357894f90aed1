"""Dynamic textures (Doretto et al. 2003) on a simulated water clip: writes the figures of docs/methods/doretto.md.

The clips are ``texsynth.data.clip("waves")`` and ``clip("rain")``: a 2-D damped wave equation on a periodic
grid, stirred by random drops and shaded by its slope (no files needed), 64 frames of 128 x 128 colour. Writes to ``docs/_static``:

- ``doretto_strip.png``: two clips, choppy water (dense drops) and raindrops (sparse drops, rings):
  each clip's frames 0, 12, ..., 60 above synthesised frames 0, 64, ..., 319 (the default Yule-Walker
  estimate; for choppy water also the paper's least squares, third row), 128 x 128 each;
- ``doretto_large.png``: one 256 x 384 frame rendered through the source-coordinate map (``size=``),
  and the temporal standard deviation of the 64 large frames (brighter: more motion; a grid there would be
  the patches' boundary zones);
- ``doretto_water.gif``: the choppy clip (left) and the synthesis (right), frames 256-311 of a 320-frame
  run, side by side, 96 x 96 crops.

and prints what the pictures show in numbers: the clip's and the synthesis' lag-1 temporal correlation and
temporal standard deviation in 64-frame windows, and the spectrum distance of frames to the clip's.

    python benchmarks/figure_doretto.py
"""

import time
from pathlib import Path

import numpy as np

from texsynth import data, metrics
from texsynth.io import save_frames, save_image
from texsynth.metrics import temporal_correlation
from texsynth.video import learn_dynamic_texture

STATIC = Path(__file__).resolve().parents[1] / "docs" / "_static"
GIF_FRAMES, GIF_CROP = 56, 96  # frames and the side of each panel: the GIF stays under 1.5 MB


def strip_row(video, frames, gap):
    return np.concatenate([np.pad(video[t], ((0, 0), (0, gap), (0, 0)), constant_values=1) for t in frames], 1)


def report(name, clip, model, video):
    """Print what the pictures show, in numbers."""
    print(f"{name}, {model.estimator}: n = {model.state_dim}, n_v = {model.noise_dim}, "
          f"stabilised: {model.stabilized}, spectral radius {model.spectral_radius:.4f} "
          f"(estimate: {np.abs(model.eigenvalues).max():.4f})")
    shuffled = clip[np.random.default_rng(0).permutation(len(clip))]
    print(f"  lag-1 correlation: clip {temporal_correlation(clip):.3f}, synthesis {temporal_correlation(video):.3f}, "
          f"shuffled clip {temporal_correlation(shuffled):.3f}")
    windows = [video[a:a + 64].std(0).mean() / clip.std(0).mean() for a in range(0, len(video), 64)]
    print("  temporal std over the clip's, 64-frame windows:", " ".join(f"{w:.2f}" for w in windows))
    spectrum = [np.mean([metrics.spectrum_distance(video[t], clip[s]) for s in (10, 40)]) for t in (0, 100, 200, 319)]
    between = np.mean([metrics.spectrum_distance(clip[t], clip[s]) for t in (0, 20, 50) for s in (10, 40)])
    print("  spectrum distance to clip frames, synthesised frames 0/100/200/319:",
          " ".join(f"{s:.2f}" for s in spectrum), f"(clip frames between themselves {between:.2f})")


def main():
    gap = 6
    rows = []
    for name, kind in (("choppy water", "waves"), ("raindrops", "rain")):
        clip = data.clip(kind, 64, 128, rng=0)
        rows.append(strip_row(clip, range(0, 64, 12), gap))
        for estimator in ("yule-walker", "least-squares"):
            start = time.perf_counter()
            model = learn_dynamic_texture(clip, estimator=estimator)
            learnt = time.perf_counter() - start
            start = time.perf_counter()
            video = model.synthesize(320, rng=0)
            print(f"{name}, {estimator}: learnt in {learnt:.2f} s, 320 frames in {time.perf_counter() - start:.2f} s")
            report(name, clip, model, video)
            if name == "choppy water" or estimator == "yule-walker":
                rows.append(strip_row(video, (0, 64, 128, 192, 256, 319), gap))
            if name == "choppy water" and estimator == "yule-walker":
                choppy, choppy_model, choppy_video = clip, model, video
    white = np.ones((gap,) + rows[0].shape[1:])
    strip = np.concatenate([part for row in rows for part in (row, white)][:-1], 0)[:, :-gap]
    save_image(STATIC / "doretto_strip.png", strip, overwrite=True)

    start = time.perf_counter()
    large, info = choppy_model.synthesize(64, size=(256, 384), rng=1, return_info=True)
    print(f"64 frames of 256 x 384 through one map in {time.perf_counter() - start:.2f} s "
          f"(block {info.map_info.block}, boundary zone {info.map_info.overlap}); "
          f"lag-1 correlation {temporal_correlation(large):.3f}")
    motion = large.std(0).mean(-1)
    zones = info.weights[..., 0] < 0.999
    print(f"temporal std in the boundary zones {motion[zones].mean():.4f}, inside the patches "
          f"{motion[~zones].mean():.4f}")
    motion = np.repeat(np.clip(motion / (2.5 * motion.mean()), 0, 1)[..., None], 3, -1)
    save_image(STATIC / "doretto_large.png",
               np.concatenate([large[40], np.ones((256, gap, 3)), motion], 1), overwrite=True)

    frames, c = GIF_FRAMES, GIF_CROP
    side = np.concatenate([choppy[:frames, :c, :c], np.ones((frames, c, gap, 3)),
                           choppy_video[256:256 + frames, :c, :c]], 2)
    path = save_frames(STATIC / "doretto_water.gif", side, fps=12, overwrite=True)
    print(f"{path.name}: {frames} frames, {path.stat().st_size / 1e6:.2f} MB")


if __name__ == "__main__":
    main()
