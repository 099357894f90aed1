"""Tiling and blending: time and peak memory of an 8192x8192 colour output (target: at most 3 s).

Run: python benchmarks/bench_tiling_blending.py [--repeat 3] [--size 8192]

Every case runs in its own process, so that its peak resident memory (``VmHWM`` after resetting
it, minus the resident memory just before the call) is its own. Side by side in the same run, the reference is
``numpy.tile`` of the exemplar to the same size and dtype: the cheapest way to fill that many
pixels from an exemplar (and the one that repeats). Cases: jcjohnson/bread.png (99x108 colour) as
float32 (float32 output) and as loaded (float64 output, as the conventions give for 8-bit files),
skimage/gravel.png (512x512 grey). A point evaluation of 10^6 scattered pixels shows the cost
per point of ``tile_and_blend_at``.
"""

import argparse
import json
import os
import subprocess
import sys
import textwrap

CASE = textwrap.dedent("""
    import json, time
    import numpy as np
    from pathlib import Path
    import texsynth
    from texsynth.io import load_image
    textures = Path({textures!r})
    ex = load_image(textures / {name!r})
    ex = (ex[..., :3] if ex.ndim == 3 else ex).astype({dtype!r})
    size, kind, repeat = {size}, {kind!r}, {repeat}
    texsynth.tile_and_blend(ex, 64, rng=0)  # imports and threads
    def run(seed):
        if kind == "tile_and_blend":
            return texsynth.tile_and_blend(ex, size, rng=seed)
        if kind == "numpy.tile":
            reps = (-(-size // ex.shape[0]), -(-size // ex.shape[1])) + (1,) * (ex.ndim - 2)
            return np.tile(ex, reps)[:size, :size]
        points = np.random.default_rng(seed).integers(-10**9, 10**9, (2, size))
        return texsynth.tile_and_blend_at(ex, points[0], points[1], rng=seed)
    def status(key):
        with open("/proc/self/status") as f:
            return next(int(line.split()[1]) for line in f if line.startswith(key))
    with open("/proc/self/clear_refs", "w") as f:  # reset the high-water mark (ru_maxrss survives exec)
        f.write("5")
    before = status("VmRSS:")
    best, cpu = float("inf"), float("inf")
    for seed in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = run(seed)
        best, cpu = min(best, time.perf_counter() - t), min(cpu, time.process_time() - c)
        nbytes = out.nbytes
        del out
    peak = (status("VmHWM:") - before) / 1024
    print(json.dumps({{"wall": best, "cpu": cpu, "peak": peak, "output": nbytes / 2**20}}))
    """)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3)
    parser.add_argument("--size", type=int, default=8192)
    args = parser.parse_args()
    textures = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "textures")
    cases = [("jcjohnson/bread.png", "float32", "tile_and_blend", args.size),
             ("jcjohnson/bread.png", "float32", "numpy.tile", args.size),
             ("jcjohnson/bread.png", "float64", "tile_and_blend", args.size),
             ("jcjohnson/bread.png", "float64", "numpy.tile", args.size),
             ("skimage/gravel.png", "float32", "tile_and_blend", args.size),
             ("skimage/gravel.png", "float32", "numpy.tile", args.size),
             ("jcjohnson/bread.png", "float32", "tile_and_blend_at", 10**6)]
    print(f"{args.size}x{args.size} outputs (tile_and_blend_at: 10^6 random points within +-10^9); best of "
          f"{args.repeat}; CPU time of all threads; peak RSS growth of the process")
    print(f"{'method':<18} {'exemplar':<22} {'dtype':<8} {'wall [s]':>9} {'CPU [s]':>8} {'peak [MiB]':>11} "
          f"{'output [MiB]':>13}")
    for name, dtype, kind, size in cases:
        code = CASE.format(textures=textures, name=name, dtype=dtype, size=size, kind=kind, repeat=args.repeat)
        proc = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
        if proc.returncode:
            print(kind, name, "failed:", proc.stderr[-400:])
            continue
        r = json.loads(proc.stdout.strip().splitlines()[-1])
        print(f"{kind:<18} {name:<22} {dtype:<8} {r['wall']:9.3f} {r['cpu']:8.3f} {r['peak']:11.0f} "
              f"{r['output']:13.0f}")


if __name__ == "__main__":
    main()
