"""Running independent pieces of one computation on the machine's cores.

numpy's loops (fancy indexing, ufuncs, sorting) release the GIL, so threads
that each take their own part of an array speed up work that BLAS does not
already spread over the cores. Each piece writes its own part of the output,
so the result is the same, bit for bit, whatever the number of threads.
"""

from __future__ import annotations

import os
import threading
from concurrent.futures import ThreadPoolExecutor

__all__ = ["parallel_for"]

_POOL = []  # one pool for the process, started on first use
_POOL_LOCK = threading.Lock()


def _pool():
    with _POOL_LOCK:
        if not _POOL:
            _POOL.append(ThreadPoolExecutor(max_workers=max(1, (os.cpu_count() or 1) - 1),
                                            thread_name_prefix="texsynth"))
        return _POOL[0]


def parallel_for(fn, n, threads):
    """Call ``fn(i)`` for ``i in range(n)`` on up to ``threads`` threads; return when all are done.

    The calling thread takes pieces too, and a helper that has not started
    by the time the pieces run out is cancelled, so a call made from inside
    another pool's task never waits for a thread that cannot come (no
    deadlock). The first exception raised by ``fn`` is raised here, after
    every started piece has finished.

    Examples
    --------
    >>> out = [0] * 5
    >>> parallel_for(lambda i: out.__setitem__(i, i * i), 5, threads=2)
    >>> out
    [0, 1, 4, 9, 16]
    """
    helpers = min(threads, n) - 1
    if helpers <= 0:
        for i in range(n):
            fn(i)
        return
    pieces = iter(range(n))
    lock = threading.Lock()
    failed = []

    def work():
        while not failed:
            with lock:
                i = next(pieces, None)
            if i is None:
                return
            try:
                fn(i)
            except BaseException as exc:  # stop the others; re-raised by the caller
                failed.append(exc)
                return

    futures = [_pool().submit(work) for _ in range(helpers)]
    work()
    for future in futures:
        if not future.cancel():  # started: wait for its pieces
            future.result()
    if failed:
        raise failed[0]
