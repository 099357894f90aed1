"""Dynamic textures (Doretto et al. 2003): learn from a 64-frame 128 x 128 colour clip (target: at most 2 s)
and synthesise 256 frames (target: at most 1 s).

Run: python benchmarks/bench_doretto.py [--repeat 5]

The clip is ``figure_doretto.py``'s simulated choppy water (64 frames, 128 x 128 x 3: 49 152 values a
frame). Side by side in the same run:

- learning: ``learn_dynamic_texture`` with each estimator (the principal components through the
  ``T x T`` Gram matrix), against the LAPACK thin SVD of the same mean-free ``(m, T)`` matrix
  (``numpy.linalg.svd(full_matrices=False)``, what the paper's code listing calls) alone;
- synthesis: ``DynamicTexture.synthesize(256)`` (the states, then ``C X + ybar`` in blocks of frames)
  against a per-frame loop of ``C x(t) + ybar`` (the paper's listing), and 256 frames of 512 x 512
  through one source-coordinate map (``size=512``: patch-based sampling of the mean frame, the modes
  rendered through the map, then the frames), run once.

Times are the best of ``--repeat`` runs, wall clock; the CPU time is printed too (the 2-core VM's BLAS
uses both cores for the products).
"""

import argparse
import os
import time
from pathlib import Path

import numpy as np
from _timing import best_of_seeds
from texsynth import data

from texsynth.metrics import temporal_correlation
from texsynth.video import dynamic_texture, learn_dynamic_texture
from texsynth.video._doretto import run_states

LEARN_TARGET, SYNTH_TARGET = 2.0, 1.0


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    repeat = parser.parse_args().repeat
    clip = data.clip("waves", 64, 128, rng=0)
    print(f"load average {' '.join(f'{v:.2f}' for v in os.getloadavg())}; "
          f"clip {clip.shape} float64, {clip[0].size} values a frame")

    print("\nlearning (target <= 2 s)")
    for estimator in ("yule-walker", "least-squares"):
        wall, cpu, model = best_of_seeds(lambda seed, e=estimator: learn_dynamic_texture(clip, estimator=e), repeat)
        verdict = "meets" if wall <= LEARN_TARGET else "MISSES"
        print(f"  learn_dynamic_texture({estimator!r}) {wall:6.3f} s (cpu {cpu:.3f}), n = {model.state_dim}: "
              f"{verdict} the target")
    Y = clip.reshape(64, -1).T
    Y = Y - Y.mean(1, keepdims=True)
    wall, cpu, _ = best_of_seeds(lambda seed: np.linalg.svd(Y, full_matrices=False), repeat)
    print(f"  reference: numpy.linalg.svd of the (m, T) matrix alone {wall:6.3f} s (cpu {cpu:.3f})")

    model = learn_dynamic_texture(clip)
    print("\nsynthesis of 256 frames (target <= 1 s)")
    wall, cpu, video = best_of_seeds(lambda seed: model.synthesize(256, rng=seed), repeat)
    verdict = "meets" if wall <= SYNTH_TARGET else "MISSES"
    print(f"  DynamicTexture.synthesize(256) {wall:6.3f} s (cpu {cpu:.3f}), {video.nbytes / 2**20:.0f} MiB: "
          f"{verdict} the target")

    def per_frame(seed):
        X = run_states(model.A, model.B, model.x0, 256, np.random.default_rng(seed))
        C, mean = np.asarray(model.C), model.mean.reshape(-1)
        return np.stack([np.clip(C @ X[:, t] + mean, 0, 1).reshape(model.frame_shape) for t in range(256)])

    wall, cpu, _ = best_of_seeds(per_frame, repeat)
    print(f"  reference: a per-frame loop of C x(t) + ybar {wall:6.3f} s (cpu {cpu:.3f})")
    start = time.perf_counter()
    large, info = model.synthesize(256, size=512, rng=0, return_info=True)
    print(f"  256 frames of 512 x 512 through one map (size=512), once: {time.perf_counter() - start:.2f} s, "
          f"{large.nbytes / 2**20:.0f} MiB (map: block {info.map_info.block}, {info.map_info.seconds:.2f} s)")

    real = Path(__file__).resolve().parent / "clips" / "tree_foliage.npz"  # real footage (clips/README.md)
    if real.exists():
        foliage = np.load(real)["frames"] / 255.0
        start = time.perf_counter()
        video = dynamic_texture(foliage, 256, rng=0)
        print(f"\nreal clip tree_foliage {foliage.shape}: learnt and 256 frames in {time.perf_counter() - start:.2f} s; "
              f"lag-1 temporal correlation clip {temporal_correlation(foliage):.3f}, synthesis "
              f"{temporal_correlation(video[32:]):.3f}")


if __name__ == "__main__":
    main()
