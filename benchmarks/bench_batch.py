"""Batch synthesis on Dask (issue 21): 100 patchworks 512^2 from 256^2 exemplars, 1 vs 2 local workers.

Run: python benchmarks/bench_batch.py [--items 100] [--threads]   (needs pip install texsynth[dask])

Targets: 2 local workers >= 1.7x faster than 1; overhead per item <= 50 ms. The exemplars are
256x256 crops of benchmarks/photos (cycled to make --items items, each with its own seed index).
The overhead per item is (the 1-worker batch's wall time - the same items run in a plain loop in
this process with one BLAS/OpenMP thread, as a Dask worker runs them: load, synthesise, save) /
items; it holds scheduling, transfer and the summary. The loop with every thread is shown too.
The clusters get the settings of the one texsynth.batch starts (texsynth._batch.WORKER_CONFIG).
The cluster's start-up is timed apart (it is paid once per batch). Dask's own overhead is also
given apart: the 1-worker wall time minus the time the items took inside the worker.
"""

import argparse
import json
import tempfile
import time
from pathlib import Path

import dask

import texsynth
from texsynth._batch import WORKER_CONFIG, _plan, _rows, run_item
from texsynth.io import load_image, save_image

PHOTOS = Path(__file__).resolve().parent / "photos"


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--items", type=int, default=100)
    parser.add_argument("--threads", action="store_true", help="thread workers instead of processes")
    args = parser.parse_args()
    from distributed import Client, LocalCluster

    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        (tmp / "in").mkdir()
        photos = sorted(PHOTOS.glob("*.png"))
        n_files = min(len(photos), args.items)
        for p in photos[:n_files]:
            image = load_image(p)
            save_image(tmp / "in" / p.name, image[:256, :256, :3] if image.ndim == 3 else image[:256, :256])
        rows = [{"exemplar": f"in/{photos[i % n_files].name}", "method": "patchwork", "seed": i // n_files}
                for i in range(args.items)]
        manifest = tmp / "manifest.json"
        manifest.write_text(json.dumps(rows))
        items = _plan(_rows(manifest, ["patchwork"], None, 1, (512, 512)), tmp / "loop")
        (tmp / "loop").mkdir()
        start = time.perf_counter()
        for item in items:
            run_item(item, str(tmp / "loop"))
        loop = time.perf_counter() - start
        print(f"{len(items)} items, plain loop: {loop:.2f} s ({1000 * loop / len(items):.0f} ms per item)")
        # the same loop with one BLAS/OpenMP thread, as a Dask worker runs its items: the like-for-like
        # reference for the batch's overhead
        from threadpoolctl import threadpool_limits

        start = time.perf_counter()
        with threadpool_limits(1):
            for item in items:
                run_item(item, str(tmp / "loop"))
        loop1 = time.perf_counter() - start
        print(f"plain loop, one thread: {loop1:.2f} s ({1000 * loop1 / len(items):.0f} ms per item)")
        walls, work = {}, {}
        for n in (1, 2):
            start = time.perf_counter()
            with dask.config.set(WORKER_CONFIG), LocalCluster(n_workers=n, threads_per_worker=1,
                                                              processes=not args.threads,
                                                              dashboard_address=":0") as cluster, \
                    Client(cluster) as client:
                client.wait_for_workers(n)
                startup = time.perf_counter() - start
                result = texsynth.batch(manifest, tmp / f"out{n}", size=512, client=client, progress=False)
            assert result.count("done") == len(items) and not result.failed, result.failed
            walls[n] = result.seconds
            work[n] = sum(i["seconds"] for i in result.items)
            print(f"{n} worker(s) ({'threads' if args.threads else 'processes'}): batch {result.seconds:.2f} s "
                  f"for {len(result.items)} items, cluster start-up {startup:.2f} s")
        print(f"speed-up 2 vs 1 workers: {walls[1] / walls[2]:.2f}x (target >= 1.7x)")
        print(f"overhead per item (1 worker vs the one-thread plain loop): {1000 * (walls[1] - loop1) / len(items):.1f} "
              f"ms (target <= 50 ms); against the plain loop with every thread: "
              f"{1000 * (walls[1] - loop) / len(items):.1f} ms")
        print(f"dask's own overhead per item (1 worker: wall - the items' own time on the worker): "
              f"{1000 * (walls[1] - work[1]) / len(items):.1f} ms; items' time on the worker "
              f"{1000 * work[1] / len(items):.0f} ms each (Dask limits each worker to 1 BLAS/OpenMP thread)")


if __name__ == "__main__":
    main()
