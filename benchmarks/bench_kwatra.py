"""Speed and memory of texture optimization (Kwatra et al. 2005), side by side.

Run: python benchmarks/bench_kwatra.py [--methods auto,before,exact,kdtree,tsvq] [--seed 0]
                                             [--repeats 1] [--no-bidirectional] [--no-gradient]
                                             [--no-frames]

Prints one table: 128x128 colour exemplar -> 256x256 output with the
defaults (3 levels, 32/16/8, w/4 grid, r = 0.8, at most 5 iterations per
stage) for each nearest-neighbour backend: wall time (untraced), process CPU
time (less sensitive than wall time to other jobs on a shared machine), time
per level, share in nearest-neighbour search, index queries made (fraction of
"every neighbourhood in every M-step"), peak memory (tracemalloc, a second
one-iteration run), the final texture energy (texsynth.metrics.texture_energy,
exact), its cost and the speed-up against the exact backend. ``before`` is
``auto`` with the M-step of the previous release, kept here for the side-by-side
comparison: every neighbourhood searched again in every M-step, 16 kd-tree
candidates with eps = 1 (``_RESEARCH_TOLERANCE = 0``, and the index's
``"default"`` search profile in place of the M-step's ``"stage"``).
With ``--repeats N`` the methods are run N times, interleaved, and the
median is printed. Then the options that meet the issue's completeness and
copy bounds (``completeness_weight=1, copy_limit=0.2``): time and texture
energy against the defaults, completeness and largest verbatim copy of both.
Then the gradient energy (``gradient_weight=10``, the
paper's μ, non-tileable output: CG iterations and the largest relative
residual reached), and flow-guided 256x256 frames (4 frames after a given
first one, rotation 0.05 rad per frame: seconds of the first, which builds
the sequence's indexes, and mean of the next ones; texture energy of the last
frame; flicker = mean absolute change against the warped previous frame).
Reference: the paper's MATLAB code took 7-10 min for a 256x256 texture and
20-60 s per flow-guided frame (2.4 GHz dual processor, 2005). Targets here:
<= 10 s, < 1 GiB, <= 2 s per frame.
"""

import argparse
import contextlib
import os
import platform
import resource
import time
import tracemalloc
from pathlib import Path

import numpy as np

from texsynth.core import flows
from texsynth.core.em import _estep, _patches  # where the M-step's index and the gradient solve are looked up
from texsynth.optimization import _kwatra as opt
from texsynth.io import load_image
from texsynth.metrics import completeness, texture_energy, verbatim_copy
from texsynth.optimization import Schedule, Search, Terms, animate_texture, optimize_texture

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def load():
    return "%.1f %.1f %.1f" % os.getloadavg()


@contextlib.contextmanager
def previous_m_step():
    """The M-step of the previous release: full re-search, PatchIndex's default kd-tree options (the
    search profile "default" where the M-step asks for "stage")."""
    index = _patches.PatchIndex

    def default_index(*args, profile="default", **kwargs):
        return index(*args, profile="default" if profile == "stage" else profile, **kwargs)

    saved = opt._RESEARCH_TOLERANCE
    opt._RESEARCH_TOLERANCE, _patches.PatchIndex = 0.0, default_index
    try:
        yield
    finally:
        opt._RESEARCH_TOLERANCE, _patches.PatchIndex = saved, index


def run(ex, label, seed, terms=Terms()):
    method = "auto" if label == "before" else label
    ctx = previous_m_step() if label == "before" else contextlib.nullcontext()
    with ctx:
        l0 = os.getloadavg()[0]
        t0, c0 = time.perf_counter(), time.process_time()
        out, info = optimize_texture(ex, 256, search=Search(method=method), terms=terms, rng=seed, return_info=True)
        seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
    return dict(out=out, info=info, seconds=seconds, cpu=cpu, load=l0)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--methods", default="auto,before,exact,kdtree,tsvq")
    parser.add_argument("--texture", default="rohitrango/t4.png")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--no-gradient", action="store_true")
    parser.add_argument("--no-bidirectional", action="store_true")
    parser.add_argument("--no-frames", action="store_true")
    args = parser.parse_args()
    ex = load_image(TEXTURES / args.texture)[..., :3][:128, :128]
    methods = args.methods.split(",")
    print(f"# texture optimization benchmark: {args.texture} {ex.shape} -> 256x256; "
          f"python {platform.python_version()}, {platform.machine()}, {os.cpu_count()} cores, load {load()}")
    runs = {m: [] for m in methods}
    for _ in range(args.repeats):  # interleaved, so every method sees the same load
        for m in methods:
            runs[m].append(run(ex, m, args.seed))
    print(f"{'method':8s} {'wall s':>7s} {'cpu s':>6s} {'lvl2 s':>7s} {'lvl1 s':>7s} {'lvl0 s':>7s} {'NN %':>5s} "
          f"{'queries':>7s} {'peak MiB':>9s} {'energy':>8s} {'vs exact':>8s} {'speed-up':>8s} {'iters':>6s} {'load':>5s}")
    rows = []
    for m in methods:
        best = sorted(runs[m], key=lambda r: r["seconds"])[len(runs[m]) // 2]  # median run
        # timed without tracemalloc (it slows allocation-heavy code); peak memory in a second run
        ctx = previous_m_step() if m == "before" else contextlib.nullcontext()
        with ctx:
            tracemalloc.start()
            optimize_texture(ex, 256, search=Search(method="auto" if m == "before" else m), rng=args.seed,
                             schedule=Schedule(max_iterations=1))
            peak = tracemalloc.get_traced_memory()[1] / 2**20
            tracemalloc.stop()
        rows.append((m, best, peak, texture_energy(best["out"], ex)))
    # energy cost and speed-up of each backend against exact search (same seed, same schedule)
    ref = {m: (b["seconds"], e) for m, b, _, e in rows}.get("exact", (rows[0][1]["seconds"], rows[0][3]))
    for m, b, peak, energy in rows:
        info = b["info"]
        lv = info.level_seconds
        queries = sum(s.searches for s in info.stages)
        queries /= max(1, sum(s.neighborhoods * s.m_steps for s in info.stages))
        print(f"{m:8s} {b['seconds']:7.1f} {b['cpu']:6.1f} {lv.get(2, 0):7.1f} {lv.get(1, 0):7.1f} {lv.get(0, 0):7.1f} "
              f"{100 * info.nn_share:5.0f} {queries:7.2f} {peak:9.0f} {energy:8.5f} {energy / ref[1]:8.3f} "
              f"{ref[0] / b['seconds']:8.2f} {sum(s.iterations for s in info.stages):6d} {b['load']:5.1f}")
    if len(methods) > 1 and args.repeats > 1:
        print("all runs (wall s):", {m: [round(r["seconds"], 1) for r in runs[m]] for m in methods})
    if not args.no_bidirectional:
        # the options that meet the completeness and copy bounds, against the defaults
        b = run(ex, "auto", args.seed, terms=Terms(completeness_weight=1.0, copy_limit=0.2))
        base = next((r for r in rows if r[0] == "auto"), rows[0])
        lv = b["info"].level_seconds
        e = texture_energy(b["out"], ex)
        print(f"{'auto completeness_weight=1, copy_limit=0.2':10s} wall {b['seconds']:.1f} s "
              f"({b['seconds'] / base[1]['seconds']:.2f}x {base[0]}), levels "
              f"{lv.get(2, 0):.1f}/{lv.get(1, 0):.1f}/{lv.get(0, 0):.1f} s, NN {100 * b['info'].nn_share:.0f} %, "
              f"energy {e:.5f} ({e / base[3]:.2f}x); completeness {completeness(b['out'], ex):.5f} "
              f"(defaults {completeness(base[1]['out'], ex):.5f}), largest copy {verbatim_copy(b['out'], ex):.2f} "
              f"(defaults {verbatim_copy(base[1]['out'], ex):.2f}) (load {b['load']:.1f})")
    if not args.no_gradient:
        # μ = 10 (the paper's value), non-tileable: CG on the Poisson-like E-step
        stats = []
        solve = _estep.solve_gradient_system

        def spy(*a, **kw):
            st = {}
            x = solve(*a, stats=st, **kw)
            stats.append(st)
            return x

        _estep.solve_gradient_system = spy
        try:
            g = run(ex, "auto", args.seed, terms=Terms(gradient_weight=10.0))
        finally:
            _estep.solve_gradient_system = solve
        lv = g["info"].level_seconds
        its = [s["iterations"] for s in stats]
        print(f"{'auto mu=10':10s} wall {g['seconds']:.1f} s, cpu {g['cpu']:.1f} s, levels "
              f"{lv.get(2, 0):.1f}/{lv.get(1, 0):.1f}/{lv.get(0, 0):.1f} s, NN {100 * g['info'].nn_share:.0f} %, "
              f"energy {texture_energy(g['out'], ex):.5f}; {len(stats)} CG solves, iterations median {np.median(its):.0f} "
              f"max {max(its)}, largest relative residual {max(s['residual'] for s in stats):.1e} (load {g['load']:.1f})")
    if not args.no_frames:
        # flow-guided 256x256 frames (frame 1 given: only the constrained re-synthesis is timed);
        # the first timed frame includes the one-off index builds of the sequence
        first = optimize_texture(ex, 256, schedule=Schedule(neighborhood_sizes=(8,), levels=1, max_iterations=1), rng=0)
        rot = flows.rotation((256, 256), 0.05)
        print(f"{'flow frames 256x256':24s} {'first s':>8s} {'next s':>7s} {'energy':>8s} {'flicker':>8s}  (load {load()})")
        for m in methods:
            if m == "before":
                continue
            video, ainfo = animate_texture(ex, rot, n_frames=5, first_frame=first, search=Search(method=m), rng=0,
                                           return_info=True)
            flicker = np.mean([np.mean(np.abs(video[i + 1] - flows.warp(video[i], rot, mode="nearest", spline_order=3)))
                               for i in range(len(video) - 1)])
            print(f"{m:24s} {ainfo.frame_seconds[0]:8.2f} {ainfo.frame_seconds[1:].mean():7.2f} "
                  f"{texture_energy(video[-1], ex):8.5f} {flicker:8.4f}")
    print(f"max RSS {resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024:.0f} MiB; load at the end {load()}")
    print("paper (MATLAB, 2005): 7-10 min per 256x256 texture, 20-60 s per flow-guided frame")


if __name__ == "__main__":
    main()
