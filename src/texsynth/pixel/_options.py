"""The option checks the pixel methods share (Wei-Levoy, Wei's mixtures and solids, texton synthesis): the
synthesis orders, the neighbourhood sizes and levels, the output's size and memory, and the search options."""

from __future__ import annotations

import math

import numpy as np

from ..core._validate import MAX_ITERATIONS, check_choice, check_group, check_memory, check_positive_int
from ..core.search import Search, check_candidates, check_method

#: Visiting orders: Wei & Levoy 2000 (scanline) and 2002 (order-independent).
ORDERS = ("scanline", "independent")


def default_parent_size(size):
    """Parent neighbourhood: about half the size, odd (5x5 -> 3x3, 9x9 -> 5x5), as in Wei & Levoy 2000, Fig. 5."""
    return tuple(max(1, (s // 2) | 1) for s in size)


def check_levels(levels):
    return check_positive_int(levels, "levels")


def check_fits(image, size, name, size_name):
    h, w = image.shape[:2]
    if size[0] > h or size[1] > w:
        raise ValueError(
            f"{size_name} {size} is larger than {name} ({h}x{w}); pass a smaller {size_name} or a larger {name}"
        )


def check_output_levels(sources, shape, out_pyr, levels):
    """The toroidal output's coarsest level must hold every neighbourhood (this level's and the parent's)."""
    coarse = out_pyr[-1].shape[:-1]
    for src in sources:
        plane = tuple(n for a, n in enumerate(coarse) if a != src.axis) if src.axis is not None else coarse
        need = src.size if levels == 1 else tuple(max(a, b) for a, b in zip(src.size, src.parent_size))
        if plane[0] < need[0] or plane[1] < need[1]:
            raise ValueError(
                f"the output size {tuple(shape)} is only {plane[0]}x{plane[1]} at the coarsest of levels={levels}, "
                f"smaller than the neighborhood {need[0]}x{need[1]} of {src.name}; pass a larger size, "
                f"fewer levels or a smaller neighborhood"
            )


def check_output_memory(sources, shape, channels, dtype, order):
    """Refuse an output whose arrays cannot fit: its pyramid, and in independent order every pixel's
    neighbourhood vector for every source at once (scanline order holds one row of them)."""
    n = float(math.prod(shape))  # Python ints: numpy's int64 product of a huge size wraps negative
    item = np.dtype(dtype).itemsize
    need = 3 * n * channels * item  # noise, the output pyramid, one pass's new values
    if order != "scanline":
        for src in sources:
            dim = (src.size[0] * src.size[1] + src.parent_size[0] * src.parent_size[1]) * channels
            need += 2 * n * (dim + channels) * item  # the query vectors and a temporary of the search
    check_memory(need, tuple(shape))


def check_order_method(order, method, passes, max_iterations=1):
    check_choice(order, "order", ORDERS)
    check_method(method)
    check_positive_int(passes, "passes", maximum=MAX_ITERATIONS)
    check_positive_int(max_iterations, "max_iterations", maximum=MAX_ITERATIONS)


def search_options(search, candidates="all"):
    """``(method, candidates, k)`` of a :class:`~texsynth.core.search.Search` (``"auto"`` candidates: the
    given default; ``"auto"`` k: 1, Ashikhmin's search)."""
    search = check_group(search, Search, "search")
    return search.method, search.resolved_candidates(candidates), search.resolved_k(1)


def check_candidate_options(candidates, k, order, tileable):
    """``k`` checked, and ``candidates`` with the options it works with; a ValueError naming the fix."""
    check_candidates(candidates)
    k = check_positive_int(k, "k")
    if candidates == "k-coherent" and order != "scanline":
        raise ValueError("candidates='k-coherent' is implemented in order='scanline' only; pass order='scanline' "
                         "or candidates='all'")
    if tileable and candidates == "k-coherent":
        raise ValueError("tileable=True is not implemented with candidates='k-coherent'; pass candidates='all' "
                         "(or order='independent', which tiles)")
    return k
