"""assert_texture_like: its verdicts and seconds, beside the full computation in the same run.

The reference is the full computation the assertion made before issue 34 (and
that ``texture_report`` still makes): every metric of the output and of the
three baselines, each patch metric on the default grid (a neighbourhood every
``patch_size // 4`` pixels, the verbatim copy every 2), then the same bounds.
(Its ``noise_baseline`` is today's, which gives the same noise in 10 ms where
the one before issue 34 took 0.6 s for a 128² exemplar, 6 s for a 256² one.)
Both sides start cold (the baselines' caches emptied before each call).

Cases:

- ``calib``: the 11 textures of ``benchmarks/calibrate_metrics.py`` (64-px crops
  of ``../shared/textures``), each judged on a 96-px output of noise and of a
  random-block mosaic (other seeds than the baselines' 0), the tiled exemplar,
  and an image-quilting synthesis;
- ``tests``: the cases of ``tests/test_metrics.py`` and ``tests/test_testing.py``
  (a fresh crop, noise and a tiled copy of gravel; random 20-px images);
- ``timing``: colour outputs of 128² and 256² from a 128² and a 256² exemplar
  (``texsynth.data`` "water"): image quilting, the exemplar itself, noise, the
  tiled exemplar, a blurred crop and half of the exemplar pasted into noise;
  the quilting of 256² is timed three times (the median is printed).

    python benchmarks/bench_testing.py                 # everything: 20-45 min, nearly all the reference's
    python benchmarks/bench_testing.py calib tests     # some groups
    python benchmarks/bench_testing.py --no-reference  # the new side only

``margin`` is ``min(bound - score)`` over the four checks: positive passes by that
much, negative fails by that much (scores are 0 for the tiled exemplar and 1 for
noise; the copy is a fraction of the exemplar's area).
"""

import argparse
import math
import os
import statistics
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

import texsynth
from texsynth import data, metrics
from texsynth.metrics import _patches  # the baselines' caches
from texsynth.io import load_image
from texsynth.testing import TextureAssertionError, assert_texture_like, relative_scores

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
CALIBRATION = ["embark/1.jpg", "skimage/gravel.png", "lcv/metal.pgm", "jcjohnson/bread.png", "rohitrango/t1.png",
               "skimage/brick.png", "lcv/reptil_skin.pgm", "rohitrango/t8.png", "lcv/text.pgm", "rohitrango/t16.png",
               "lcv/nuts.pgm"]
NAMES = ("energy", "completeness", "spectrum", "verbatim_copy")
ABBREV = {"energy": "E", "completeness": "C", "spectrum": "S", "verbatim_copy": "V"}
DEFAULT_BOUNDS = {"energy": 0.5, "completeness": 0.5, "spectrum": 0.6, "verbatim_copy": 0.5}


def texture(name, size):
    image = load_image(TEXTURES / name)
    if image.ndim == 3 and image.shape[-1] == 4:
        image = image[..., :3]
    return np.ascontiguousarray(image[:size, :size])


def _cold():
    for cache in (_patches._BASELINE_METRICS, _patches._VERDICT_BASELINES):
        cache.clear()


def reference_verdict(output, exemplar, *, patch_size=8, rng=0, **bounds):
    """The full computation: texture_report (every metric, every baseline, default grids) and the bounds."""
    bounds = {name: bounds.get(f"max_{'copy' if name == 'verbatim_copy' else name}", DEFAULT_BOUNDS[name])
              for name in NAMES}
    scores = relative_scores(metrics.texture_report(output, exemplar, patch_size=patch_size, rng=rng))
    return scores, bounds


def new_verdict(output, exemplar, *, patch_size=8, rng=0, **bounds):
    try:
        report = assert_texture_like(output, exemplar, patch_size=patch_size, rng=rng, **bounds)
    except TextureAssertionError as error:
        report = error.report
    full = {name: bounds.get(f"max_{'copy' if name == 'verbatim_copy' else name}", DEFAULT_BOUNDS[name])
            for name in NAMES}
    return relative_scores(report), full


def judge(fn, output, exemplar, kwargs, runs=1):
    seconds = []
    for _ in range(runs):
        _cold()
        start = time.perf_counter()
        scores, bounds = fn(output, exemplar, **kwargs)
        seconds.append(time.perf_counter() - start)
    failed = [name for name in NAMES if not scores[name] <= bounds[name]]
    margin = min(bounds[name] - scores[name] for name in NAMES if math.isfinite(bounds[name]))
    return {"scores": scores, "failed": failed, "margin": margin, "seconds": statistics.median(seconds),
            "runs": runs}


def calibration_cases():
    for name in CALIBRATION:
        ex = texture(name, 64)
        short = name.split("/")[-1].split(".")[0]
        yield f"{short} noise 96", metrics.noise_baseline(ex, 96, rng=1), ex, {}
        yield f"{short} mosaic 96", metrics.mosaic_baseline(ex, 96, rng=1), ex, {}
        yield f"{short} tiled 96", metrics.tiled_baseline(ex, 96), ex, {}
        yield f"{short} quilt 96", texsynth.quilt(ex, 96, rng=0), ex, {}


def test_cases():
    big = texture("skimage/gravel.png", 112)
    ex, other = big[:48, :48], big[56:, 56:]
    yield "gravel fresh crop 56", other, ex, {}
    yield "gravel noise 56", metrics.noise_baseline(ex, 56, rng=0), ex, {}
    yield "gravel tiled 64", metrics.tiled_baseline(ex, 64), ex, {}
    grey = np.random.default_rng(0).random((20, 20))
    yield "random20 noise 24 p4", metrics.noise_baseline(grey, 24, rng=0), grey, {"patch_size": 4}
    yield "random20 itself p4 bounds 0", grey, grey, {"patch_size": 4, "max_energy": 0, "max_completeness": 0,
                                                       "max_spectrum": 0, "max_copy": np.inf}
    rand24 = np.random.default_rng(0).random((24, 24))
    yield "random24 rot90 p4", np.rot90(rand24), rand24, {"patch_size": 4}


def timing_cases():
    water = data.load("water")
    for ex_size in (128, 256):
        ex = np.ascontiguousarray(water[:ex_size, :ex_size])
        for out_size in (128, 256):
            tag = f"water{ex_size} -> {out_size}"
            runs = 3 if out_size == 256 else 1
            yield f"{tag} quilt", texsynth.quilt(ex, out_size, rng=0), ex, {}, runs
            if out_size == ex_size:
                yield f"{tag} exemplar itself", ex, ex, {}, 1
            yield f"{tag} noise", metrics.noise_baseline(ex, out_size, rng=1), ex, {}, 1
            yield f"{tag} tiled", metrics.tiled_baseline(ex, out_size), ex, {}, 1
            crop = np.ascontiguousarray(water[-out_size:, -out_size:])
            yield f"{tag} blurred crop", ndimage.gaussian_filter(crop, (2, 2, 0)), ex, {}, 1
            pasted = metrics.noise_baseline(ex, out_size, rng=2)
            side = min(int(ex_size * 0.75), out_size)  # 0.56 of the exemplar's area, or all the output
            pasted[:side, :side] = ex[:side, :side]
            yield f"{tag} {side**2 / ex_size**2:.2f} pasted in noise", pasted, ex, {}, 1


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("groups", nargs="*", default=["calib", "tests", "timing"])
    parser.add_argument("--no-reference", action="store_true", help="skip the full computation")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f}; OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n")
    print("| case | verdict full | verdict fast | failed full | failed fast | margin full | margin fast "
          "| score diff: energy, completeness, spectrum, copy | s full | s fast |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    groups = {"calib": calibration_cases, "tests": test_cases, "timing": timing_cases}
    same = True
    for group in args.groups:
        for case in groups[group]():
            label, output, exemplar, kwargs = case[:4]
            runs = case[4] if len(case) > 4 else 1
            new = judge(new_verdict, output, exemplar, kwargs, runs)
            if args.no_reference:
                ref = None
            else:
                ref = judge(reference_verdict, output, exemplar, kwargs)
            cells = [label]
            for r in (ref, new):
                cells.append("-" if r is None else ("fail" if r["failed"] else "pass"))
            for r in (ref, new):
                cells.append("-" if r is None else (", ".join(r["failed"]) or "-"))
            for r in (ref, new):
                cells.append("-" if r is None else f"{r['margin']:+.3f}")
            if ref is None:
                cells.append("-")
            else:
                diffs = {n: abs(ref["scores"][n] - new["scores"][n]) for n in NAMES
                         if math.isfinite(ref["scores"][n]) or math.isfinite(new["scores"][n])}
                cells.append(" ".join(f"{ABBREV[n]} {d:.3f}" for n, d in diffs.items()))
                same &= ref["failed"] == new["failed"]
            cells.append("-" if ref is None else f"{ref['seconds']:.2f}")
            cells.append(f"{new['seconds']:.2f}" + (f" (median of {runs})" if runs > 1 else ""))
            print("| " + " | ".join(cells) + " |", flush=True)
    if not args.no_reference:
        print("\nsame verdicts (the same failed checks) on every case:", same)


if __name__ == "__main__":
    main()
