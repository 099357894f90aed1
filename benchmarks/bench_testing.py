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
  the quilting of 256² is timed three times (the median is printed);
- ``structure`` (not run by default): the regime the structure checks are made
  in, the 25 photographs of ``benchmarks/calibrate_structure.py`` (128 px
  exemplars, outputs of 256): the tiled exemplar, a mosaic, noise and a mosaic
  turned by 45 degrees (seed 1), and image quilting, graph cuts and texture
  optimization at their defaults (seed 0). Run it with ``--no-reference`` (the
  full computation takes minutes per case at this size);
- ``crops`` (not run by default; no assertion, a study): why three structure
  checks are made only from 128 px exemplars and at twice their size. For 41
  photographs (``benchmarks/photos`` and ten of ``../shared/textures``), a crop
  of 48-128 px from the top left is the exemplar and a crop of 1-2.5 times its
  size from the bottom right, another part of the same photograph, stands for a
  perfect synthesis; each structure check's rule is applied at every size, and
  the table counts the crops and the noise baselines (seed 0) it fails.

    python benchmarks/bench_testing.py                 # calib, tests, timing: 20-45 min, nearly all the reference's
    python benchmarks/bench_testing.py calib tests     # some groups
    python benchmarks/bench_testing.py --no-reference  # the new side only
    python benchmarks/bench_testing.py structure --no-reference --cache /tmp/structure   # about 10 min
    python benchmarks/bench_testing.py crops                                          # about 2 min

At the end: the cases whose verdict the structure checks change (the verdict of
the four patch checks alone against the verdict with all eight).

``margin`` is ``min(bound - score)`` over the four patch checks: positive passes
by that much, negative fails by that much (scores are 0 for the tiled exemplar and
1 for noise; the copy is a fraction of the exemplar's area). The structure checks
(issue 38) are the same computation on both sides (whole images, no sampling):
both verdicts include them, and the ``structure`` column gives the output's
orientation (the noise's), induced lattice, lattice kept and element integrity
(the noise's), "-" where a check was skipped.
"""

import argparse
import math
import os
import statistics
import sys
import time
from pathlib import Path

import numpy as np
from scipy import ndimage

import texsynth
from texsynth import data, metrics
from texsynth.metrics import _patches  # the baselines' caches
from texsynth.io import load_image
from texsynth import testing
from texsynth.core._validate import as_image
from texsynth.testing import TextureAssertionError, assert_texture_like, relative_scores

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"
CALIBRATION = ["embark/1.jpg", "skimage/gravel.png", "lcv/metal.pgm", "jcjohnson/bread.png", "rohitrango/t1.png",
               "skimage/brick.png", "lcv/reptil_skin.pgm", "rohitrango/t8.png", "lcv/text.pgm", "rohitrango/t16.png",
               "lcv/nuts.pgm"]
NAMES = ("energy", "completeness", "spectrum", "verbatim_copy")
ABBREV = {"energy": "E", "completeness": "C", "spectrum": "S", "verbatim_copy": "V"}
DEFAULT_BOUNDS = {"energy": 0.5, "completeness": 0.5, "spectrum": 0.6, "verbatim_copy": 0.5,
                  "orientation": metrics.ORIENTATION_THRESHOLD, "induced_lattice": metrics.INDUCED_LATTICE_THRESHOLD,
                  "lattice_kept": metrics.LATTICE_KEPT_THRESHOLD,
                  "element_integrity": metrics.ELEMENT_INTEGRITY_THRESHOLD}


def texture(name, size):
    image = load_image(TEXTURES / name)
    if image.ndim == 3 and image.shape[-1] == 4:
        image = image[..., :3]
    return np.ascontiguousarray(image[:size, :size])


def _cold():
    for cache in (_patches._BASELINE_METRICS, _patches._VERDICT_BASELINES, testing._STRUCTURE_BASELINES):
        cache.clear()


def _bounds(given):
    return {name: given.get(testing._BOUND_NAMES[name], default) for name, default in DEFAULT_BOUNDS.items()}


def reference_verdict(output, exemplar, *, patch_size=8, rng=0, **bounds):
    """The full computation: texture_report (every metric, every baseline, default grids) and the bounds, and
    the structure checks (the assertion's own: they are not sampled)."""
    bounds = _bounds(bounds)
    scores = relative_scores(metrics.texture_report(output, exemplar, patch_size=patch_size, rng=rng))
    failed = [name for name in NAMES if not scores[name] <= bounds[name]]
    values, reference, _, structure_failed = testing._structure(as_image(output), as_image(exemplar), bounds,
                                                                rng, None)
    return scores, bounds, failed + structure_failed, (values, reference)


def new_verdict(output, exemplar, *, patch_size=8, rng=0, **bounds):
    try:
        report = assert_texture_like(output, exemplar, patch_size=patch_size, rng=rng, **bounds)
    except TextureAssertionError as error:
        report = error.report
    return relative_scores(report), _bounds(bounds), report.failed, (report.values, report.reference)


def _structure_cell(values, reference):
    def f(value, digits):
        return "-" if value is None else f"{value:.{digits}f}"

    noise = reference["noise"]
    return (f"O {f(values['orientation'], 1)} ({f(noise.get('orientation'), 1)}) I {f(values['induced_lattice'], 2)} "
            f"K {f(values['lattice_kept'], 2)} E {f(values['element_integrity'], 2)} "
            f"({f(noise.get('element_integrity'), 2)})")


def judge(fn, output, exemplar, kwargs, runs=1):
    seconds = []
    for _ in range(runs):
        _cold()
        start = time.perf_counter()
        scores, bounds, failed, structure = fn(output, exemplar, **kwargs)
        seconds.append(time.perf_counter() - start)
    margin = min(bounds[name] - scores[name] for name in NAMES if math.isfinite(bounds[name]))
    return {"scores": scores, "failed": failed, "margin": margin, "seconds": statistics.median(seconds),
            "runs": runs, "structure": _structure_cell(*structure)}


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


def structure_cases(cache=None):
    sys.path.insert(0, str(Path(__file__).resolve().parent))
    import calibrate_structure as cs

    for path, _, level in cs.TUNING + cs.HELD_OUT + cs.FRESH:
        ex = cs.exemplar(path, level)
        name = path.stem if path.parent.name == "photos" else f"{path.parent.name}/{path.stem}"
        key = name.replace("/", "_")
        for row in cs.ROWS:
            seed = 0 if row in cs.METHODS else 1  # the assertion's own noise is seed 0
            yield f"{name} {row} 256", cs.image_for(row, ex, seed, cache, key), ex, {}


def crop_study():
    """Per exemplar side and output factor: how often each structure check's rule fails another crop of the
    same photograph (should pass) and the noise baseline (should fail), where the check applies."""
    from skimage.exposure import match_histograms

    photos = [TEXTURES / name for name in ("embark/1.jpg", "skimage/gravel.png", "lcv/metal.pgm",
                                           "lcv/reptil_skin.pgm", "lcv/text.pgm", "lcv/nuts.pgm", "skimage/brick.png",
                                           "rohitrango/t1.png", "rohitrango/t8.png", "rohitrango/t2.png")]
    photos += sorted((Path(__file__).resolve().parent / "photos").glob("*.png"))
    counts = {}  # (side, factor) -> {check: [applies, crops failing, noise failing]}
    for path in photos:
        image = load_image(path)
        image = image[..., :3] if image.ndim == 3 and image.shape[-1] == 4 else image
        height, width = image.shape[:2]
        for side in (48, 64, 96, 128):
            ex = np.ascontiguousarray(image[:side, :side])
            vectors = len(metrics.lattice(ex).vectors)
            for factor in (1.0, 1.5, 2.0, 2.5):
                size = round(factor * side)
                if side + size > height or size > width:  # the crop must not overlap the exemplar
                    continue
                crop = np.ascontiguousarray(image[height - size:, width - size:])
                noise = metrics.noise_baseline(ex, size, rng=0)
                row = counts.setdefault((side, factor), {})
                o, on = metrics.orientation_distance(crop, ex), metrics.orientation_distance(noise, ex)
                orient, induced = metrics.ORIENTATION_THRESHOLD, metrics.INDUCED_LATTICE_THRESHOLD
                kept, whole = metrics.LATTICE_KEPT_THRESHOLD, metrics.ELEMENT_INTEGRITY_THRESHOLD
                checks = {"orientation": (True, o > orient and o > on / 2, on > orient),
                          "induced_lattice": (True, metrics.induced_lattice(crop, ex) > induced,
                                              metrics.induced_lattice(metrics.tiled_baseline(ex, size), ex) > induced)}
                try:
                    en = metrics.element_integrity(noise, ex)
                    checks["element_integrity"] = (en < whole, metrics.element_integrity(crop, ex) < whole, en < whole)
                    # the crop with the exemplar's histogram, as a synthesis has it: the mask is cut at the
                    # exemplar's threshold, and another part of a photograph is often brighter or darker
                    matched = np.clip(match_histograms(crop, ex, channel_axis=-1 if crop.ndim == 3 else None), 0, 1)
                    checks["matched"] = (en < whole, metrics.element_integrity(matched, ex) < whole, en < whole)
                except ValueError:  # no element in the exemplar
                    pass
                if vectors:
                    try:
                        checks["lattice_kept"] = (True, metrics.lattice_kept(crop, ex) < kept,
                                                  metrics.lattice_kept(noise, ex) < kept)
                    except ValueError:  # the output cannot show the vectors
                        pass
                for name, (applies, crop_fails, noise_fails) in checks.items():
                    cell = row.setdefault(name, [0, 0, 0])
                    if applies:
                        cell[0] += 1
                        cell[1] += crop_fails
                        cell[2] += noise_fails
    names = ("orientation", "induced_lattice", "lattice_kept", "element_integrity", "matched")
    print("other crops failing / noise failing (the tiled exemplar for the induced lattice) / applicable; "
          "matched: element_integrity of the crop with the exemplar's histogram\n")
    print("| exemplar | output | " + " | ".join(names) + " |")
    print("|---|---|" + "---|" * len(names))
    for (side, factor), row in sorted(counts.items()):
        cells = [f"{row[n][1]} / {row[n][2]} / {row[n][0]}" if n in row else "-" for n in names]
        print(f"| {side} px | {factor:g}x | " + " | ".join(cells) + " |")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("groups", nargs="*", default=["calib", "tests", "timing"],
                        help="calib, tests, timing (the default: all three), structure, crops")
    parser.add_argument("--no-reference", action="store_true", help="skip the full computation")
    parser.add_argument("--cache", type=Path, help="keep the structure group's syntheses in this folder")
    args = parser.parse_args()
    unknown = sorted(set(args.groups) - {"calib", "tests", "timing", "structure", "crops"})
    if unknown:
        parser.error(f"unknown groups {unknown}; choose from calib, tests, timing, structure, crops")
    if "crops" in args.groups:
        crop_study()
        args.groups.remove("crops")
        if not args.groups:
            return
    if args.cache is not None:
        args.cache.mkdir(parents=True, exist_ok=True)
    print(f"load average {os.getloadavg()[0]:.1f}; OMP_NUM_THREADS={os.environ.get('OMP_NUM_THREADS', 'unset')}; "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}\n")
    print("| case | verdict full | verdict fast | failed full | failed fast | margin full | margin fast "
          "| score diff: energy, completeness, spectrum, copy | structure | s full | s fast |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    groups = {"calib": calibration_cases, "tests": test_cases, "timing": timing_cases,
              "structure": lambda: structure_cases(args.cache)}
    same = True
    changed = []
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
            cells.append(new["structure"])
            cells.append("-" if ref is None else f"{ref['seconds']:.2f}")
            cells.append(f"{new['seconds']:.2f}" + (f" (median of {runs})" if runs > 1 else ""))
            print("| " + " | ".join(cells) + " |", flush=True)
            if any(name in NAMES for name in new["failed"]) != bool(new["failed"]):
                changed.append(f"{label} ({', '.join(new['failed'])})")
    if not args.no_reference:
        print("\nsame verdicts (the same failed checks) on every case:", same)
    print(f"\nverdicts the structure checks change (pass -> fail), {len(changed)}:", "; ".join(changed) or "none")


if __name__ == "__main__":
    main()
