"""The registry of search backends, the rules of ``method="auto"`` and the named tuning profiles.

A backend is a class with ``build(vectors, *, memory_budget, rng, **options)``
(a classmethod returning an object with ``query(queries, k) -> (indices,
sq_distances)``) registered under a name with the tuning options it accepts.
A new backend is one module that calls :func:`register`, imported by
``texsynth.core.search``.

Profiles name the settings that the algorithms' own measurements chose: the
rule that resolves ``method="auto"`` and each backend's tuning. They live here,
so every algorithm asks for a profile by name and the choices stay in one place.
"""

from __future__ import annotations

import contextlib
import contextvars
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

__all__ = ["register", "BACKENDS", "Profile", "PROFILES", "resolve", "use", "methods", "option_names"]


@dataclass(frozen=True)
class Backend:
    """A registered backend: its builder and the tuning options it accepts."""

    name: str
    build: Callable
    options: tuple = ()
    summary: str = ""


BACKENDS: dict[str, Backend] = {}


def register(name, build, *, options=(), summary=""):
    """Register a backend under ``name`` (``build`` as described in the module notes)."""
    BACKENDS[name] = Backend(name, build, tuple(options), summary)


def methods():
    """Valid values of ``method``: ``"auto"`` and every registered backend."""
    return ("auto",) + tuple(BACKENDS)


def option_names():
    """Every tuning option some backend accepts."""
    return sorted({o for b in BACKENDS.values() for o in b.options})


# --------------------------------------------------------------------------- rules of "auto"
# Default rule: "exact" up to N vectors and "kdtree" above, N depending on the
# dimension: the measured crossover of build + query time
# (benchmarks/bench_nearest.py --crossover, M = N / 2 queries) is N ~ 2000 for
# 27-D and ~5000 for 147-D patches (brute force costs N * D per query, the PCA
# kd-tree little more in high D); interpolated linearly between, clamped outside.
_AUTO_CROSSOVER_DIMS = (27, 147)
_AUTO_CROSSOVER_N = (2_000, 5_000)


def _by_crossover(n, dim, queries):
    return "exact" if n <= np.interp(dim, _AUTO_CROSSOVER_DIMS, _AUTO_CROSSOVER_N) else "kdtree"


# Order-independent Wei-Levoy passes and solids: exact brute force while the
# (query, candidate) pairs of one pass stay below this, kd-tree above.
_AUTO_EXACT_PAIRS = 2e8


def _by_pairs(n, dim, queries):
    return "exact" if queries is None or n * queries <= _AUTO_EXACT_PAIRS else "kdtree"


# Ruiters' correspondences: exact up to this many neighbourhoods of the other texture.
# Measured for 784 queries into the 12544 neighbourhoods (17 x 17 x 4) of a 128 px
# texture: exact 0.55-0.6 s, kd-tree 0.9-1.2 s (build + query) with recall@1 0.27-0.91.
# The default rule assumes about N / 2 queries; here there are at most max_neighborhoods.
_CORRESPONDENCE_EXACT_MAX = 20_000


def _by_size(n, dim, queries):
    return "exact" if n <= _CORRESPONDENCE_EXACT_MAX else "kdtree"


def _always_exact(n, dim, queries):
    return "exact"


@dataclass(frozen=True)
class Profile:
    """A named search setting: the rule of ``method="auto"`` and each backend's tuning.

    Attributes
    ----------
    name, summary : str
    auto : callable
        ``auto(n, dim, queries) -> method`` for ``n`` indexed vectors of
        dimension ``dim`` and about ``queries`` queries (None if unknown).
    options : dict
        ``{backend: {option: value}}``, applied under the user's own options.
    """

    name: str
    summary: str
    auto: Callable = _by_crossover
    options: dict = field(default_factory=dict)


PROFILES = {p.name: p for p in (
    Profile("default", "exact below the measured crossover size for the dimension, PCA kd-tree above"),
    # Kwatra stages: 16 candidates of a (1 + 2)-approximate search instead of (1 + 1): measured at
    # 128 -> 192 on 6 textures x 3 seeds, final texture energy -0.3 % (geometric mean; -4.9 % to +4.9 %)
    # at 0.78 of the CPU time. 8 candidates were faster still (0.66) but +1.3 % (up to +19 % on text).
    # Not with the gradient energy (its 3x longer vectors: eps = 2 costs +7 %): use "default" there.
    Profile("stage", "texture optimization's M-step: kd-tree with 16 candidates, eps = 2",
            options={"kdtree": {"n_candidates": 16, "eps": 2.0}}),
    # Animation frames also rank coherent candidates, so the tree only has to offer one fresh
    # candidate per neighbourhood: 4 re-ranked candidates and eps = 2 cost a third of the defaults.
    Profile("frame", "animation frames: kd-tree with 4 candidates, eps = 2",
            options={"kdtree": {"n_candidates": 4, "eps": 2.0}}),
    Profile("pixels", "order-independent pixel synthesis: exact while queries x vectors <= 2e8, kd-tree above",
            auto=_by_pairs),
    # Scanline synthesis: exact search one scanline at a time (SequentialExact) is the fastest.
    Profile("scanline", "scanline pixel synthesis: exact, one scanline at a time", auto=_always_exact),
    # Solids (bread, nuts, paving t13; 32^3 and 64^3): 4 re-ranked kd-tree candidates kept the slice
    # energy within +-5 % of 16 candidates and of exact search, 1.7x faster. Not for 2-D mixtures:
    # there 4 candidates raise the energy by 25-35 % (brick/gravel ramp).
    Profile("solid", "solid textures: as 'pixels', kd-tree with 4 candidates", auto=_by_pairs,
            options={"kdtree": {"n_candidates": 4}}),
    Profile("correspondence", "texture interpolation's correspondences: exact up to 20000 vectors, kd-tree above",
            auto=_by_size),
)}

#: The backend :func:`use` makes ``"auto"`` mean in this context (None: the profiles decide); read by
#: every resolver of ``"auto"`` (also ``resolve_field``).
forced_method = contextvars.ContextVar("texsynth_search_method", default=None)


@contextlib.contextmanager
def use(method):
    """Make ``method="auto"`` mean ``method`` in every algorithm, inside a ``with`` block.

    One switch for the backend of every search of every algorithm (for
    comparisons and benchmarks); an explicit ``method=`` still wins.

    Examples
    --------
    >>> from texsynth.core import search
    >>> with search.use("tsvq"):
    ...     search.resolve("auto", 100, 8)
    'tsvq'
    >>> search.resolve("auto", 100, 8)
    'exact'
    """
    check_method(method)
    token = forced_method.set(None if method == "auto" else method)
    try:
        yield
    finally:
        forced_method.reset(token)


def check_method(method, name="method"):
    """``method`` itself, or a ValueError listing the valid values."""
    if not isinstance(method, str) or method not in methods():
        raise ValueError(f"{name} must be one of {', '.join(map(repr, methods()))}, got {method!r}")
    return method


def check_profile(profile):
    if profile not in PROFILES:
        raise ValueError(f"profile must be one of {', '.join(map(repr, PROFILES))}, got {profile!r}")
    return PROFILES[profile]


def resolve(method, n, dim, *, profile="default", queries=None):
    """The backend that ``method`` means for ``n`` vectors of dimension ``dim``.

    Parameters
    ----------
    method : str
        ``"auto"`` or a backend name (returned as is).
    n, dim : int
        Indexed vectors and their dimension.
    profile : str
        Whose rule decides ``"auto"`` (see :data:`PROFILES`).
    queries : int, optional
        Expected number of queries, for rules that weigh it.

    Examples
    --------
    >>> resolve("auto", 1000, 27), resolve("auto", 100_000, 27), resolve("tsvq", 10, 2)
    ('exact', 'kdtree', 'tsvq')
    >>> resolve("auto", 10**6, 27, profile="scanline")
    'exact'
    """
    check_method(method)
    rule = check_profile(profile)
    if method != "auto":
        return method
    return forced_method.get() or rule.auto(n, dim, queries)

