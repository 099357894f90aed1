"""Test-suite set-up: one BLAS thread per worker, and ``np`` in every doctest.

The suite runs on 2 cores with two pytest-xdist workers; multi-threaded BLAS in
each worker oversubscribes the cores and made small matrix products 100x slower
under load (measured for texsynth.core.search, docs/methods/search.md), so each
worker uses one BLAS thread.
"""

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import numpy as np  # noqa: E402
import pytest  # noqa: E402


@pytest.fixture(autouse=True)
def _doctest_numpy(doctest_namespace):
    doctest_namespace["np"] = np
