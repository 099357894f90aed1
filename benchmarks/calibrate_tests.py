"""Seed sweeps behind the suite's quality bounds: the figures each bound's comment quotes.

Another CPU gives another, equally good sample for the same seed (numpy and OpenBLAS pick other
SIMD kernels, a last bit differs and then an argmin). Another seed stands for that here: a bound
that holds over seeds 0-4 with a margin holds on another machine. For each check the script
prints, per texture, the range of every ratio the test asserts over the seeds, and the worst of
them all; the bound in the test keeps the margin its comment states over that worst figure.

    python benchmarks/calibrate_tests.py                      # every check, seeds 0-4
    python benchmarks/calibrate_tests.py optimization_4x --seeds 0 1 2 3 4 5 6 7

The baselines are drawn with rng=0, as in the tests; only the synthesis' seed changes.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

from texsynth import InterpolationSchedule, NeighborhoodSet
from texsynth import (find_textons, interpolate_textures, linear_blend, metrics, optimize_texture,
                      ridge_feature_map, synthesize_controlled)
from texsynth.io import load_image
from texsynth.optimization import Terms

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "tests"))
from test_ruiters import _sharpness  # noqa: E402  the tests' own measures, not copies
from test_texton import _fragments  # noqa: E402
# tests/test_kwatra.py's QUALITY set
QUALITY = ["rohitrango/t4.png", "jcjohnson/bread.png", "lcv/metal.pgm", "rohitrango/t1.png", "lcv/reptil_skin.pgm",
           "lcv/text.pgm"]


def texture(name, size):
    image = load_image(TEXTURES / name)
    if image.ndim == 3 and image.shape[-1] == 4:
        image = image[..., :3]
    return np.ascontiguousarray(image if size is None else image[:size, :size])


def _quality(name, seed, **options):
    """Ratios of tests/test_kwatra.py's quality tests at 64 -> 96."""
    ex = texture(name, 64)
    out = optimize_texture(ex, 96, rng=seed, **options)
    noise, mosaic = metrics.noise_baseline(ex, 96, rng=0), metrics.mosaic_baseline(ex, 96, rng=0)
    energy = metrics.texture_energy(out, ex)
    return {"energy/noise": energy / metrics.texture_energy(noise, ex),
            "energy/mosaic": energy / metrics.texture_energy(mosaic, ex),
            "completeness/mosaic": metrics.completeness(out, ex) / metrics.completeness(mosaic, ex),
            "verbatim": metrics.verbatim_copy(out, ex)}


def optimization_defaults(name, seed):
    return _quality(name, seed)


def optimization_paper(name, seed):
    return _quality(name, seed, preset="paper")


def optimization_bidirectional(name, seed):
    return _quality(name, seed, preset="paper", terms=Terms(completeness_weight=1.0, copy_limit=0.2))


def optimization_pairs(name, seed):
    """The paired tests of tests/test_kwatra.py: one option against the paper's preset, same seed."""
    ex = texture(name, 64)
    paper = optimize_texture(ex, 96, rng=seed, preset="paper")
    complete = optimize_texture(ex, 96, rng=seed, preset="paper", terms=Terms(completeness_weight=1.0))
    limited = optimize_texture(ex, 96, rng=seed, preset="paper", terms=Terms(copy_limit=0.1))
    spread = optimize_texture(ex, 96, rng=seed, preset="paper", terms=Terms(occurrence_weight=1.0))
    mosaic = metrics.mosaic_baseline(ex, 96, rng=0)
    c, v, e = metrics.completeness, metrics.verbatim_copy, metrics.texture_energy
    return {"completeness: complete/paper": c(complete, ex) / c(paper, ex),
            "copy: complete": v(complete, ex), "copy: paper": v(paper, ex),
            "copy: limit 0.1": v(limited, ex), "copy: limit 0.1/paper": v(limited, ex) / v(paper, ex),
            "energy: limit 0.1/mosaic": e(limited, ex) / e(mosaic, ex),
            "completeness: occurrence/paper": c(spread, ex) / c(paper, ex),
            "energy: occurrence/paper": e(spread, ex) / e(paper, ex)}


def optimization_4x(name, seed):
    """tests/test_kwatra.py::test_defaults_at_4x_keep_the_completeness_term_on_the_coarse_levels."""
    ex = texture(name, 64)
    out = optimize_texture(ex, 128, rng=seed)
    off = optimize_texture(ex, 128, terms=Terms(completeness_weight=0), rng=seed)
    return {"completeness on/off": metrics.completeness(out, ex) / metrics.completeness(off, ex),
            "verbatim": metrics.verbatim_copy(out, ex)}


def texton_turned(name, seed):
    """tests/test_texton.py::test_texton_mask_keeps_pebbles_whole_when_turned."""
    ex = texture(name, 96)
    reference = find_textons(ex)
    mosaic = metrics.mosaic_baseline(ex, 160, rng=0)
    with_mask = _fragments(find_textons(synthesize_controlled(ex, 160, orientation=0.6, rng=seed)), reference)
    without = _fragments(find_textons(synthesize_controlled(ex, 160, orientation=0.6, texton_mask=None, rng=seed)),
                         reference)
    return {"with mask": with_mask, "without": without, "mosaic": _fragments(find_textons(mosaic), reference)}


def interpolation_halfway(name, seed):
    """tests/test_ruiters.py::test_halfway_is_as_sharp_as_the_linear_blend (pebbles <-> paving)."""
    from skimage.transform import resize

    a = resize(texture(name, None), (96, 96), anti_aliasing=True)
    b = resize(texture("rohitrango/t13.png", None), (96, 96), anti_aliasing=True)
    out = interpolate_textures(a, b, 0.5, features=(ridge_feature_map(a), ridge_feature_map(b)),
                               schedule=InterpolationSchedule(stages=((2, 17), (1, 17), (1, 9)), max_iterations=4),
                               neighborhood_set=NeighborhoodSet(max_neighborhoods=400), rng=seed)
    blend = linear_blend(a, b, 0.5)
    e = metrics.texture_energy
    return {"sharpness/blend": _sharpness(out) / _sharpness(blend), "energy a/blend": e(out, a) / e(blend, a),
            "energy b/blend": e(out, b) / e(blend, b)}


CHECKS = {
    "optimization_defaults": (optimization_defaults, QUALITY),
    "optimization_paper": (optimization_paper, QUALITY),
    "optimization_bidirectional": (optimization_bidirectional, QUALITY),
    "optimization_4x": (optimization_4x, QUALITY),
    "optimization_pairs": (optimization_pairs, ["rohitrango/t4.png", "jcjohnson/bread.png"]),
    "texton_turned": (texton_turned, ["rohitrango/t4.png"]),
    "interpolation_halfway": (interpolation_halfway, ["rohitrango/t4.png"]),
}


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("checks", nargs="*", default=list(CHECKS), choices=list(CHECKS))
    parser.add_argument("--seeds", nargs="+", type=int, default=[0, 1, 2, 3, 4])
    args = parser.parse_args()
    for check in args.checks:
        fn, names = CHECKS[check]
        start = time.perf_counter()
        print(f"\n## {check} (seeds {args.seeds[0]}-{args.seeds[-1]})\n")
        rows = {}
        for name in names:
            values = [fn(name, seed) for seed in args.seeds]
            rows[name] = {key: [v[key] for v in values] for key in values[0]}
        keys = list(next(iter(rows.values())))
        print("| texture | " + " | ".join(keys) + " |")
        print("|---" * (len(keys) + 1) + "|")
        for name, row in rows.items():
            print(f"| {name} | " + " | ".join(f"{min(row[k]):.3f}-{max(row[k]):.3f}" for k in keys) + " |")
        every = {k: np.concatenate([row[k] for row in rows.values()]) for k in keys}
        print("| all | " + " | ".join(f"{every[k].min():.3f}-{every[k].max():.3f}" for k in keys) + " |")
        print(f"\n{time.perf_counter() - start:.0f} s")


if __name__ == "__main__":
    main()
