"""Gigapixel outputs chunk by chunk (issue 21): turbulence 65536^2 colour-mapped and patchwork 32768^2
colour from a 512^2 photo, written to Zarr, with their peak memory; beside them, the same methods in
memory at 8192^2 (the reference: what chunking costs per pixel where the whole image fits).

Run: python benchmarks/bench_gigapixel.py [--scale 1] [--chunks 2048] [--out DIR] [--cases turbulence,...]
(needs pip install texsynth[dask]; --scale 0.25 runs a quarter of each side, for a quick look).

Targets: each gigapixel case <= 5 min and <= 2 GiB peak RSS on the 2-core machine. Every case runs
in a fresh subprocess and reports its own peak RSS (ru_maxrss). The Zarr stores are
written under --out (default a temporary folder, removed at the end) and their size on disk given.
"""

import argparse
import json
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

PHOTO = Path(__file__).resolve().parent / "photos" / "granite_1.png"

CASE = r"""
import json, resource, sys, time
import numpy as np
from texsynth.io import load_image, save_chunked
from texsynth.patch import patchwork
from texsynth.procedural import apply_colormap, turbulence
kind, side, chunks, out = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
start = time.perf_counter()
if kind == "turbulence":
    image = apply_colormap(turbulence(side, rng=0, dtype=np.float32, chunks=chunks or None) / 2)
else:
    image = patchwork(load_image(sys.argv[5]), side, rng=0, chunks=chunks or None)
if chunks:
    save_chunked(out, image)
else:
    checksum = float(np.asarray(image[::97, ::89]).sum())  # the image is made; this only touches it
print(json.dumps({"seconds": time.perf_counter() - start,
                  "peak": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20}))
"""


def run(kind, side, chunks, out):
    """Seconds and peak RSS (GiB, the child's own ru_maxrss) of one case in a fresh process."""
    proc = subprocess.run([sys.executable, "-c", CASE, kind, str(side), str(chunks), str(out), str(PHOTO)],
                          capture_output=True, text=True)
    if proc.returncode:
        raise SystemExit(proc.stderr)
    result = json.loads(proc.stdout.splitlines()[-1])
    return result["seconds"], result["peak"]


def disk(path):
    return sum(p.stat().st_size for p in Path(path).rglob("*") if p.is_file()) / 2**30


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--scale", type=float, default=1.0)
    parser.add_argument("--chunks", type=int, default=2048)
    parser.add_argument("--out", type=Path, default=None)
    parser.add_argument("--cases", default="reference,patchwork,turbulence",
                        help="comma-separated: reference (the in-memory runs), patchwork, turbulence")
    args = parser.parse_args()
    cases = args.cases.split(",")
    out = args.out or Path(tempfile.mkdtemp(prefix="gigapixel-"))
    out.mkdir(parents=True, exist_ok=True)
    print(f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, {PHOTO.name} 512^2 exemplar, chunks {args.chunks}")
    try:
        for kind, side in (("turbulence", 8192), ("patchwork", 8192)) if "reference" in cases else ():
            seconds, peak = run(kind, side, 0, out / "none")
            print(f"{kind:10s} {side}^2 in memory (reference): {seconds:7.1f} s, "
                  f"{1e3 * seconds / (side * side / 1e6):.1f} ms per Mpx, peak RSS {peak:.2f} GiB")
        for kind, side in (("patchwork", 32768), ("turbulence", 65536)):
            if kind not in cases:
                continue
            side = int(side * args.scale)
            store = out / f"{kind}_{side}.zarr"
            seconds, peak = run(kind, side, args.chunks, store)
            print(f"{kind:10s} {side}^2 to Zarr: {seconds:7.1f} s, {1e3 * seconds / (side * side / 1e6):.1f} ms per "
                  f"Mpx, peak RSS {peak:.2f} GiB, {disk(store):.2f} GiB on disk")
    finally:
        if args.out is None:
            shutil.rmtree(out, ignore_errors=True)


if __name__ == "__main__":
    main()
