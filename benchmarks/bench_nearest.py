"""Benchmark of texsynth.core.search.PatchIndex against scikit-learn NearestNeighbors.

Real patches: every 7x7 colour neighbourhood (147-D) of a 230x230 crop of one
ink-in-water photograph (50 176 vectors) is indexed; the queries are the
7x7 neighbourhoods of a second photograph of the same set (~20 000 vectors).
A grey set (7x7 patches of gravel, 49-D) shows the effect of the dimension.

For every method: build time, query time, recall@1 (fraction of queries whose
returned index is the exact nearest neighbour, ties counted as hits when the
distance is equal) and the mean distance ratio (returned / exact nearest
squared distance, over queries with a non-zero exact distance).

Run with a single BLAS thread on a shared machine: an oversubscribed
multi-threaded OpenBLAS slows every GEMM (ours and scikit-learn's) by up to 10x.

scikit-learn's tree searches are exact but slow in 147-D; they are timed on the
first ``--tree-queries`` queries and the time is scaled to the full query set
(marked "*").

Usage::

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_nearest.py   # full run (a few minutes)
    python benchmarks/bench_nearest.py --quick    # smaller sets
    python benchmarks/bench_nearest.py --crossover  # exact vs kdtree vs N (for method="auto")
"""

from __future__ import annotations

import argparse
import platform
import time
from pathlib import Path

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view

from texsynth.io import load_image
from texsynth.core.search import PatchIndex

TEXTURES = Path(__file__).resolve().parents[2] / "shared" / "textures"


def patches(path, size, crop, step=1):
    img = load_image(TEXTURES / path)
    if img.ndim == 2:
        img = img[..., None]
    img = img[..., :3]
    (r0, r1), (c0, c1) = crop
    view = sliding_window_view(img[r0:r1, c0:c1], (size, size), axis=(0, 1))[::step, ::step]
    return np.ascontiguousarray(view.reshape(-1, size * size * img.shape[-1]))


def datasets(quick):
    s = 120 if quick else 230
    t = 80 if quick else 148
    return {
        "colour 7x7x3 (ink, embark/multiexample)": (
            patches("embark/multiexample/1.jpg", 7, ((0, s), (0, s))),
            patches("embark/multiexample/2.jpg", 7, ((100, 100 + t), (100, 100 + t))),
        ),
        "grey 7x7 (gravel, skimage)": (
            patches("skimage/gravel.png", 7, ((0, s), (0, s))),
            patches("skimage/gravel.png", 7, ((300, 300 + t), (300, 300 + t))),
        ),
    }


def timed(fn):
    t = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t


def score(idx, d2, exact_d):
    # equal distance (to float32 rounding) = a tied exact answer
    hit = d2[:, 0] <= exact_d[:, 0] * (1 + 1e-5) + 1e-9
    pos = exact_d[:, 0] > 0
    ratio = float(np.mean(d2[pos, 0] / exact_d[pos, 0])) if pos.any() else 1.0
    return float(hit.mean()), ratio


def run(quick, tree_queries):
    import scipy.spatial  # noqa: F401  (import time is not build time)
    from sklearn.neighbors import NearestNeighbors

    rows = []
    for name, (v, q) in datasets(quick).items():
        print(f"\n## {name}: index {v.shape[0]} x {v.shape[1]}, queries {q.shape[0]}")
        (ex_i, ex_d), t_ex = timed(lambda: PatchIndex(v, method="exact").query(q))
        ours = [
            ("texsynth exact", dict(method="exact")),
            ("texsynth exact float32", dict(method="exact", _f32=True)),
            ("texsynth kdtree (default)", dict(method="kdtree")),
            ("texsynth kdtree n_candidates=5", dict(method="kdtree", n_candidates=5)),
            ("texsynth kdtree n_candidates=32", dict(method="kdtree", n_candidates=32)),
            ("texsynth tsvq (greedy)", dict(method="tsvq")),
            ("texsynth tsvq beams=4", dict(method="tsvq", beams=4)),
            ("texsynth tsvq beams=16", dict(method="tsvq", beams=16)),
            ("texsynth auto", dict(method="auto")),
        ]
        for label, kw in ours:
            f32 = kw.pop("_f32", False)
            vv, qq = (v.astype(np.float32), q.astype(np.float32)) if f32 else (v, q)
            index, tb = timed(lambda: PatchIndex(vv, rng=0, **kw))
            (i, d), tq = timed(lambda: index.query(qq))
            rec, ratio = score(i, d.astype(np.float64), ex_d)
            rows.append((name, f"{label} [{index.method}]", tb, tq, 1e6 * tq / len(q), rec, ratio, ""))
            print_row(rows[-1])
        for algo in ("brute", "kd_tree", "ball_tree"):
            nq = len(q) if algo == "brute" else min(tree_queries, len(q))
            nn, tb = timed(lambda: NearestNeighbors(n_neighbors=1, algorithm=algo).fit(v))
            (d, i), tq = timed(lambda: nn.kneighbors(q[:nq]))
            d2 = ((q[:nq] - v[i[:, 0]]) ** 2).sum(1)[:, None]
            rec, ratio = score(i, d2, ex_d[:nq])
            scale = len(q) / nq
            rows.append((name, f"sklearn {algo}", tb, tq * scale, 1e6 * tq / nq, rec, ratio, "*" if scale > 1 else ""))
            print_row(rows[-1])
    return rows


def print_row(r):
    name, label, tb, tq, us, rec, ratio, mark = r
    print(f"| {label:<42} | {tb:8.2f} | {tq:9.2f}{mark:1} | {us:9.1f} | {rec:6.3f} | {ratio:6.3f} |", flush=True)


def crossover(repeats=3):
    """Build + query time of each backend against N (M = N / 2 queries), best of repeats."""
    import scipy.spatial  # noqa: F401

    rng = np.random.default_rng(0)
    for size in (3, 7):
        full_v = patches("embark/multiexample/1.jpg", size, ((0, 300), (0, 300)))
        full_q = patches("embark/multiexample/2.jpg", size, ((0, 300), (0, 300)))
        dim = full_v.shape[1]
        print(f"\n## build + query seconds, {size}x{size}x3 = {dim}-D, M = N/2 queries, k = 1 (best of {repeats})")
        print("| N | exact | kdtree | tsvq |")
        print("|---|---|---|---|")
        for n in (2000, 5000, 10000, 20000, 40000):
            v = full_v[rng.choice(len(full_v), n, replace=False)]
            q = full_q[rng.choice(len(full_q), n // 2, replace=False)]
            times = []
            for method in ("exact", "kdtree", "tsvq"):
                best = np.inf
                for _ in range(repeats):
                    _, t = timed(lambda: PatchIndex(v, method=method, rng=0).query(q))
                    best = min(best, t)
                times.append(best)
            print(f"| {n} | {times[0]:.3f} | {times[1]:.3f} | {times[2]:.3f} |", flush=True)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--crossover", action="store_true")
    parser.add_argument("--tree-queries", type=int, default=1000)
    args = parser.parse_args()
    print(f"machine: {platform.machine()}, {platform.python_version()}, numpy {np.__version__}")
    if args.crossover:
        crossover()
        return
    print("| method | build s | query s | us/query | recall@1 | dist ratio |")
    print("|---|---|---|---|---|---|")
    run(args.quick, args.tree_queries)


if __name__ == "__main__":
    main()
