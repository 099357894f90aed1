"""Random phase noise / ADSN: time of a 1024x1024 colour synthesis (target: at most 0.2 s).

Run: python benchmarks/bench_random_phase.py [--repeat 5]

Exemplar: jcjohnson/bread.png (99x108 colour, spot-extended to the output) and lcv/metal.pgm
(256x256 grey). Side by side in the same run: a plain numpy version of the same RPN (complex float64
FFTs of every channel, ``numpy.fft``, one thread), which shows what the real float32 FFTs on all
cores give, and Heeger-Bergen at the same output size (the statistical family's other one-shot
spectral method, 5 iterations of 4 scales x 4 orientations), run once. Quality: the spectrum
distance to the exemplar, against histogram-matched white noise's.
"""

import argparse
from pathlib import Path

import numpy as np
from _timing import best_of_seeds

from texsynth.core.pyramid import periodic_smooth_decomposition
from texsynth.io import load_image
from texsynth.metrics import noise_baseline, spectrum_distance
from texsynth.statistical import heeger_bergen, random_phase_noise

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
SIZE = 1024


def numpy_rpn(exemplar, size, rng):
    """The same random phase noise in plain numpy: complex float64 FFTs, one channel at a time."""
    ex = exemplar if exemplar.ndim == 3 else exemplar[..., None]
    p = periodic_smooth_decomposition(ex)[0]
    mean = ex.reshape(-1, ex.shape[-1]).mean(0)
    spot = np.zeros((size, size, ex.shape[-1]))
    spot[: ex.shape[0], : ex.shape[1]] = (p - mean) / np.sqrt(ex.shape[0] * ex.shape[1])
    noise = np.fft.fft2(rng.standard_normal((size, size)))
    phase = noise / np.abs(noise) * size
    out = np.stack([np.real(np.fft.ifft2(np.fft.fft2(spot[..., c]) * phase)) for c in range(ex.shape[-1])], -1)
    out = np.clip(out + mean, 0, 1)
    return out if exemplar.ndim == 3 else out[..., 0]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    args = parser.parse_args()
    bread = load_image(TEXTURES / "jcjohnson" / "bread.png")
    metal = load_image(TEXTURES / "lcv" / "metal.pgm")
    rows = []
    for label, ex in (("bread 99x108 colour", bread), ("bread, float32 input", bread.astype(np.float32)),
                      ("metal 256x256 grey", metal)):
        for process in ("rpn", "adsn"):
            rows.append((f"random_phase_noise {process}", label, ex,
                         lambda seed, ex=ex, process=process: random_phase_noise(ex, SIZE, process=process, rng=seed),
                         args.repeat))
        if "float32" not in label:
            rows.append(("numpy RPN (complex128, 1 thread)", label, ex,
                         lambda seed, ex=ex: numpy_rpn(ex, SIZE, np.random.default_rng(seed)), args.repeat))
            rows.append(("heeger_bergen (5 iterations)", label, ex,
                         lambda seed, ex=ex: heeger_bergen(ex, SIZE, rng=seed), 1))
    print(f"Output {SIZE}x{SIZE}; wall time best of --repeat runs (Heeger-Bergen: one run) and CPU time of this")
    print("process (all threads); spectrum distance to the exemplar (histogram-matched white noise in brackets)")
    print(f"{'method':<34} {'exemplar':<22} {'wall [s]':>9} {'CPU [s]':>8} {'spectrum':>9} {'(noise)':>8}")
    for name, label, ex, func, repeat in rows:
        wall, cpu, out = best_of_seeds(func, repeat)
        noise = noise_baseline(ex, SIZE, rng=0)
        print(f"{name:<34} {label:<22} {wall:9.3f} {cpu:8.3f} {spectrum_distance(out, ex):9.3f} "
              f"{spectrum_distance(noise, ex):8.3f}")


if __name__ == "__main__":
    main()
