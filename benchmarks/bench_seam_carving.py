"""Seam carving: speed against the issue's target, side by side with a reference implementation when installed.

Run: nice -n 10 python benchmarks/bench_seam_carving.py [--repeat 2]   (from the repository root)

Target (issue 17): remove 100 vertical seams from a 512 x 512 colour photograph in at most 2 s.

Reference in the same run: scikit-image removed ``transform.seam_carve`` in 0.19 (0.26 here), so it cannot be
compared. The PyPI package ``seam-carving`` (li-plus/seam-carving 1.1.0: backward and forward energy, compiled
with numba) is timed on the same inputs when it is installed; it is not on the development machine (it needs numba,
which is not installed there), and then the table says so.
"""

import argparse
import os
import time

import numpy as np


def best_of(fn, repeat):
    times, result = [], None
    for _ in range(repeat):
        started = time.perf_counter()
        result = fn()
        times.append(time.perf_counter() - started)
    return min(times), result


def reference():
    try:
        import seam_carving
    except ImportError:
        return None
    return seam_carving


def main(repeat):
    from skimage import data as skdata

    from texsynth.patch import carve_seams

    photo = skdata.astronaut()  # 512 x 512 colour photograph, uint8
    ref = reference()
    print(f"Seam carving on skimage's astronaut (512 x 512 colour), best of {repeat}; load {os.getloadavg()[0]:.1f}")
    if ref is None:
        print("  reference: none installed (scikit-image's seam_carve was removed in 0.19; "
              "`pip install seam-carving` (needs numba) adds li-plus/seam-carving to this table)")
    print(f"{'task':<62} {'carve_seams s':>14} {'seam-carving (PyPI) s':>22} {'target':>8}")

    def row(task, ours, theirs, target=""):
        ref_text = f"{theirs:22.2f}" if theirs is not None else f"{'-':>22}"
        print(f"{task:<62} {ours:14.2f} {ref_text} {target:>8}")

    cases = [
        ("100 vertical seams removed (backward energy)", (512, 412), "backward", "<= 2 s"),
        ("100 vertical seams removed (forward energy)", (512, 412), "forward", ""),
        ("100 horizontal seams removed (backward energy)", (412, 512), "backward", ""),
        ("128 vertical seams inserted (512 -> 640 wide)", (512, 640), "backward", ""),
    ]
    for task, size, energy, target in cases:
        t, _ = best_of(lambda size=size, energy=energy: carve_seams(photo, size, energy=energy), repeat)
        theirs = None
        if ref is not None:
            theirs, _ = best_of(lambda size=size, energy=energy: ref.resize(photo, (size[1], size[0]), energy_mode=energy,
                                                   order="width-first"), repeat)
        row(task, t, theirs, target)
    small = photo[::2, ::2]  # 256 x 256
    for order in ("optimal", "alternate"):
        t, (_, info) = best_of(lambda order=order: carve_seams(small, (236, 236), order=order, return_info=True),
                               repeat)
        theirs = None
        if ref is not None and order == "alternate":
            theirs, _ = best_of(lambda: ref.resize(small, (236, 236), order="width-first"), repeat)
        row(f"256 x 256 -> 236 x 236, order={order} (total E {info.costs.sum():.1f})", t, theirs)
    rocket = skdata.rocket()
    mask = np.zeros(rocket.shape[:2], bool)
    mask[110:300, 178:214] = True
    mask[300:427, 160:216] = True
    t, (_, info) = best_of(lambda: carve_seams(rocket, remove_mask=mask, return_info=True), repeat)
    theirs = None
    if ref is not None:
        theirs, _ = best_of(lambda: ref.remove_object(rocket, drop_mask=mask), repeat)
    row(f"object removal, rocket 427 x 640 ({info.n_removed[1]} seams, then restored)", t, theirs)
    _, (_, info) = best_of(lambda: carve_seams(photo, (512, 412), return_info=True), 1)
    print(f"  stages of the 100-seam removal: {', '.join(f'{k} {v:.2f} s' for k, v in info.stage_seconds.items())}")


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=2)
    main(parser.parse_args().repeat)
