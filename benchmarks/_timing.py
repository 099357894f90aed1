"""Wall-time measurement shared by the benchmarks.

:func:`best_of` (the shortest of several runs) serves ``bench_noise.py`` and ``bench_patterns.py``;
:func:`timed_stages` (one run, with the stages it reports) ``bench_vertex_synthesis.py`` and ``bench_lapped.py``;
:func:`best_of_seeds` (wall and CPU time, seed by seed) ``bench_random_phase.py`` and ``bench_doretto.py``.
"""

import time


def best_of(fn, repeat):
    """The shortest wall time in seconds of ``repeat`` calls of ``fn()``, after one warm-up call."""
    fn()  # warm-up (imports, first-touch page faults)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        fn()
        times.append(time.perf_counter() - t0)
    return min(times)


def timed_stages(fn):
    """One call of ``fn()``, which returns ``(result, info)`` with ``info.stage_seconds``.

    Returns ``(result, info, seconds, stages)``: the wall time of the call and its stages as text,
    ``"field 0.1, paste 1.4, bake 0.8"``.
    """
    start = time.perf_counter()
    result, info = fn()
    seconds = time.perf_counter() - start
    return result, info, seconds, ", ".join(f"{k} {v:.1f}" for k, v in info.stage_seconds.items())


def best_of_seeds(func, repeat):
    """``(wall, cpu, out)``: the shortest wall and CPU times in seconds of ``func(seed)`` for seeds
    ``0 .. repeat - 1``, and the last call's result."""
    best, cpu, out = float("inf"), float("inf"), None
    for seed in range(repeat):
        t, c = time.perf_counter(), time.process_time()
        out = func(seed)
        best, cpu = min(best, time.perf_counter() - t), min(cpu, time.process_time() - c)
    return best, cpu, out
