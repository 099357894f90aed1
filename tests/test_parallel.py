"""core._parallel.parallel_for: every piece once, errors raised, no deadlock when nested."""

import threading
from concurrent.futures import ThreadPoolExecutor

import pytest

from texsynth.core._parallel import parallel_for


@pytest.mark.parametrize("threads", [1, 2, 4])
def test_every_piece_runs_once(threads):
    seen = []
    lock = threading.Lock()

    def piece(i):
        with lock:
            seen.append(i)

    parallel_for(piece, 37, threads)
    assert sorted(seen) == list(range(37))


def test_the_first_error_is_raised_after_the_started_pieces():
    done = []

    def piece(i):
        if i == 3:
            raise KeyError("piece 3")
        done.append(i)

    with pytest.raises(KeyError, match="piece 3"):
        parallel_for(piece, 50, 2)
    assert 3 not in done


def test_nested_calls_from_a_busy_pool_do_not_deadlock():
    # every worker of an outer pool calls parallel_for while the shared pool may be busy with the others'
    # helpers: the callers take the pieces themselves, and a helper that has not started is cancelled
    totals = []

    def outer(j):
        parts = [0] * 20
        parallel_for(lambda i: parts.__setitem__(i, i + j), 20, 4)
        return sum(parts)

    with ThreadPoolExecutor(max_workers=8) as pool:
        totals = list(pool.map(outer, range(16)))
    assert totals == [190 + 20 * j for j in range(16)]
