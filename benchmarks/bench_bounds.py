"""PatchMatch's distance bounds: how many candidates they rule out, what they save, and that they change nothing.

``optimize_texture`` with its defaults, a colour photograph of
``benchmarks/photos`` (256² -> 1024² by default), once without bounds and once
for each number of principal components given (``_BOUND_COMPONENTS`` of
``texsynth.core.search._patchmatch``), then with the default components and
each number of sampled patches given (``_BOUND_SAMPLES``, the sample the
components are estimated from), then with each smallest patch dimension given
(``_BOUND_MIN_DIM``: patches with fewer values are compared exactly), in one
process after a warm-up run. For
each run: the wall time, the share of candidates that still needed an exact
distance, by patch dimension (8 / 16 / 32 / 64 px colour patches: 192, 768,
3072 and 12288 values), and a digest of the output, which must be the same for every
run (the bounds change the work, never the field).

Usage::

    python benchmarks/bench_bounds.py [--photo bricks_2] [--side 256] [--size 1024] [--components 8 16 32 64]
                                      [--samples 256 512 1024] [--min-dims 256 128]
"""

from __future__ import annotations

import argparse
import collections
import hashlib
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from bench_kwatra_production import load  # noqa: E402


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--photo", default="bricks_2")
    parser.add_argument("--side", type=int, default=256)
    parser.add_argument("--size", type=int, default=1024)
    parser.add_argument("--components", type=int, nargs="+", default=[8, 16, 32, 64])
    parser.add_argument("--samples", type=int, nargs="*", default=[])
    parser.add_argument("--min-dims", type=int, nargs="*", default=[])
    args = parser.parse_args()

    import texsynth
    import texsynth.core.search._patchmatch as pm

    seen = collections.defaultdict(lambda: [0, 0])
    may_beat = pm._Bound.may_beat

    def counted(self, q, ids, worst):
        out = may_beat(self, q, ids, worst)
        s = seen[self.kernels.shape[0]]
        s[0] += out.size
        s[1] += int(out.sum())
        return out

    pm._Bound.may_beat = counted
    exemplar = load(args.photo, args.side)
    texsynth.optimize_texture(exemplar[:64, :64], 96, rng=0)  # warm-up: imports, caches
    default, samples, min_dim = pm._BOUND_COMPONENTS, pm._BOUND_SAMPLES, pm._BOUND_MIN_DIM
    print(f"{args.photo} {args.side}² -> {args.size}², defaults, rng=0")
    print(f"{'components':>10}  {'samples':>7}  {'min dim':>7}  {'time':>7}  {'exact share by patch dimension':<40}  digest")
    runs = ([(m, samples, min_dim) for m in [0, *args.components]] + [(default, n, min_dim) for n in args.samples]
            + [(default, samples, d) for d in args.min_dims])
    for m, n_samples, dim in runs:
        seen.clear()
        pm._BOUND_CACHE.clear()
        pm._BOUND_MIN_DIM = 10**9 if m == 0 else dim
        pm._BOUND_COMPONENTS = m or default
        pm._BOUND_SAMPLES = n_samples
        start = time.perf_counter()
        out = texsynth.optimize_texture(exemplar, args.size, rng=0)
        took = time.perf_counter() - start
        shares = "  ".join(f"{d}: {k / n:.3f}" for d, (n, k) in sorted(seen.items())) or "no bounds"
        digest = hashlib.sha1(out.tobytes()).hexdigest()[:16]
        print(f"{m or '-':>10}  {n_samples if m else '-':>7}  {dim if m else '-':>7}  {took:6.1f}s  {shares:<40}  {digest}")


if __name__ == "__main__":
    main()
