"""What "the same seed gives the same output" means, checked as docs/conventions.md states it.

On one machine and one set of library versions, a seed gives the same bits in another process,
with another number of threads and with another number of Dask workers. One method per family
runs in two fresh processes, one limited to a single thread (``OMP_NUM_THREADS=1``, which also
caps BLAS and texsynth's own threads) and one with every core; both digests are computed in
this run and compared. Across CPUs the outputs are equally good samples that may differ in
their bits (numpy and OpenBLAS pick other SIMD kernels), so no digest is ever written down here.
"""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

import texsynth
from texsynth import data

# one small call (or a tuple of calls) per family
CALLS = {
    "pixel": "texsynth.synthesize_pixels(ex[:32, :32], 40, neighborhood=texsynth.Neighborhood(levels=2), rng=3)",
    "patch": "texsynth.quilt(ex, 72, rng=3), texsynth.patchwork(ex, 72, rng=3)",
    "optimization": "texsynth.optimize_texture(ex[:48, :48], 64, schedule=texsynth.optimization.Schedule("
                    "max_iterations=2), rng=3)",
    "statistical": "texsynth.heeger_bergen(ex, 64, iterations=2, rng=3)",
    "procedural": "texsynth.procedural.marble((48, 48), rng=3),"
                  " texsynth.procedural.reaction_diffusion((32, 32), steps=200, rng=3)",
    "surface": "texsynth.synthesize_surface(texsynth.surface.sphere(162), ex, n_vertices=642,"
               " rng=3).colors",
}

SCRIPT = """
import hashlib, json
import numpy as np
import texsynth, texsynth.procedural, texsynth.surface
from texsynth import data
ex = data.load("bread")[:64, :64]
digests = {}
for family, call in json.loads(CALLS).items():
    outs = eval(call)
    digest = hashlib.sha256()
    for out in outs if isinstance(outs, tuple) else (outs,):
        digest.update(repr((out.shape, out.dtype.str)).encode() + np.ascontiguousarray(out).tobytes())
    digests[family] = digest.hexdigest()
print(json.dumps(digests))
"""


def _run(threads):
    env = {k: v for k, v in os.environ.items() if not k.endswith("_NUM_THREADS")}
    if threads is not None:
        env.update(OMP_NUM_THREADS=str(threads), OPENBLAS_NUM_THREADS=str(threads), MKL_NUM_THREADS=str(threads))
    script = f"CALLS = {json.dumps(json.dumps(CALLS))}\n" + SCRIPT
    done = subprocess.run([sys.executable, "-c", script], env=env, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stderr[-2000:]
    return json.loads(done.stdout.strip().splitlines()[-1])


@pytest.fixture(scope="module")
def digests():
    """The digests of every family's call in a one-thread process and in an all-cores process."""
    return _run(1), _run(None)


@pytest.mark.parametrize("family", list(CALLS))
def test_same_seed_same_bits_in_another_process_with_other_thread_counts(digests, family):
    one_thread, all_cores = digests
    assert one_thread[family] == all_cores[family]


def test_the_calls_cover_every_family():
    assert set(CALLS) == {"pixel", "patch", "optimization", "statistical", "procedural", "surface"}


def test_same_seed_same_bits_with_other_dask_worker_counts():
    dask = pytest.importorskip("dask")
    ex = data.load("bread")[:64, :64]
    lazy = texsynth.patchwork(ex, (96, 80), rng=3, chunks=32)
    outs = []
    for workers in (1, 2):
        with dask.config.set(scheduler="threads", num_workers=workers):
            outs.append(np.asarray(lazy.compute()))
    assert np.array_equal(outs[0], outs[1])
    assert np.array_equal(outs[0], texsynth.patchwork(ex, (96, 80), rng=3))  # and the in-memory result
