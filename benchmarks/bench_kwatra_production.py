"""Production sizes: texture optimization against the resynthesizer engine, side by side in one run.

Issue 16's targets, each run in a fresh Python process (so its peak resident
memory is its own), one after another:

- ``optimize_texture`` with its defaults, colour photographs of
  ``benchmarks/photos``: 128² -> 256², 256² -> 1024², 512² -> 2048²;
- the same with ``preset="paper"`` at 256² -> 1024² (the settings that were the
  defaults before), and the resynthesizer engine (Harrison's C engine, PyPI
  ``resynthesizer``, GPL-3.0: a peer, not a dependency) filling the same output
  from the same photograph as GIMP's "Uncrop" does: the photograph in the top-left
  corner of an output-sized canvas, every other pixel marked for synthesis;
- one flow-guided frame of ``animate_texture`` at 256² (the third frame: the
  first builds what later frames reuse).

Usage::

    pip install -e .[bench]
    python benchmarks/bench_kwatra_production.py [--quick] [--photo bricks_2]

Prints one line per run (wall time, peak RSS) and a table; ``--quick`` leaves out
the 2048² runs and the paper preset at 1024².
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

PHOTOS = Path(__file__).resolve().parent / "photos"
OUTPUT = Path(__file__).resolve().parent / "output"


def load(photo, side):
    import numpy as np
    from texsynth.io import load_image

    img = load_image(PHOTOS / f"{photo}.png")
    img = img[..., :3] if img.ndim == 3 else np.repeat(img[..., None], 3, -1)
    return np.ascontiguousarray(img[:side, :side]).astype(np.float32)


def resynthesize(exemplar, size):
    """Harrison's engine filling an output-sized canvas beside the exemplar (GIMP's Uncrop)."""
    import numpy as np
    from PIL import Image
    import resynthesizer

    canvas = np.zeros((size, size, 3), np.uint8)
    h, w = exemplar.shape[:2]
    canvas[:h, :w] = np.round(exemplar * 255).astype(np.uint8)
    mask = np.full((size, size), 255, np.uint8)
    mask[:h, :w] = 0  # the exemplar is the source; every other pixel is synthesised
    params = resynthesizer.getDefaultParams()
    params.isMakeSeamlesslyTileableHorizontally = 0
    params.isMakeSeamlesslyTileableVertically = 0
    out = resynthesizer.resynthesize(Image.fromarray(canvas), Image.fromarray(mask), params)
    return np.asarray(out, dtype=np.float32) / 255.0


def run_one(kind, photo, side, size):
    """Body of one child process: run, save the PNG, print a JSON line with time and peak memory."""
    import resource

    import numpy as np

    import texsynth
    from texsynth.core import flows
    from texsynth.io import save_image

    exemplar = load(photo, side)
    start = time.perf_counter()
    if kind == "defaults":
        out = texsynth.optimize_texture(exemplar, size, rng=0)
    elif kind == "paper":
        out = texsynth.optimize_texture(exemplar, size, preset="paper", rng=0)
    elif kind == "resynthesizer":
        out = resynthesize(exemplar, size)
    elif kind == "frame":
        frames, info = texsynth.animate_texture(exemplar, flows.rotation((size, size), 0.05), n_frames=4, rng=0,
                                                return_info=True)
        out = frames[-1]
    else:
        raise ValueError(kind)
    seconds = time.perf_counter() - start
    if kind == "frame":
        seconds = float(info.frame_seconds[-1])
    OUTPUT.mkdir(exist_ok=True)
    save_image(OUTPUT / f"production_{kind}_{photo}_{side}_{size}.png", np.clip(out, 0, 1), overwrite=True)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20  # kB -> GiB
    print(json.dumps(dict(kind=kind, photo=photo, side=side, size=size, seconds=seconds, peak_gib=peak)))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--photo", default="bricks_2")
    parser.add_argument("--one", nargs=4, metavar=("KIND", "PHOTO", "SIDE", "SIZE"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        kind, photo, side, size = args.one
        run_one(kind, photo, int(side), int(size))
        return
    runs = [("defaults", 128, 256), ("resynthesizer", 128, 256),
            ("defaults", 256, 1024), ("resynthesizer", 256, 1024)]
    if not args.quick:
        runs += [("paper", 256, 1024), ("defaults", 512, 2048), ("resynthesizer", 512, 2048)]
    runs += [("frame", 256, 256)]
    print(f"# {platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {os.getloadavg()[0]:.1f}, "
          f"photo {args.photo}", flush=True)
    results = []
    for kind, side, size in runs:
        proc = subprocess.run([sys.executable, __file__, "--one", kind, args.photo, str(side), str(size)],
                              capture_output=True, text=True)
        if proc.returncode:
            print(f"{kind} {side}->{size} failed:\n{proc.stderr[-2000:]}", flush=True)
            continue
        row = json.loads(proc.stdout.strip().splitlines()[-1])
        results.append(row)
        print(f"{kind:14s} {side:4d}² -> {size:4d}²  {row['seconds']:7.1f} s  peak {row['peak_gib']:.2f} GiB  "
              f"(load {os.getloadavg()[0]:.1f})", flush=True)
    print("\n| run | wall | peak RSS |\n|---|---|---|")
    for r in results:
        print(f"| {r['kind']} {r['side']}² → {r['size']}² | {r['seconds']:.1f} s | {r['peak_gib']:.2f} GiB |")


if __name__ == "__main__":
    main()
