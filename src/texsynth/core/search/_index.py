"""The nearest-neighbour index: one interface over every registered backend."""

from __future__ import annotations

import numbers

import numpy as np

from .._validate import as_rng, check_positive_float, check_positive_int
from ._common import as_vectors, as_weights
from ._registry import BACKENDS, check_profile, option_names, resolve

__all__ = ["PatchIndex", "nearest"]

#: Bytes one block of brute-force distances may take unless a caller passes ``memory_budget``.
DEFAULT_MEMORY_BUDGET = 256 * 2**20


def _check_options(options):
    """Tuning options: known to some backend, integers >= 1 (``eps`` a float >= 0, ``branching`` >= 2)."""
    known = option_names()
    out = {}
    for name, value in options.items():
        if name not in known:
            raise TypeError(f"unknown search option {name!r}; the backends accept {', '.join(known)}")
        if value is None:
            continue
        if name == "eps":
            out[name] = check_positive_float(value, "eps", allow_zero=True)
        else:
            out[name] = check_positive_int(value, name, 2 if name == "branching" else 1)
    return out


class PatchIndex:
    """Nearest-neighbour index over (weighted) patch vectors.

    Parameters
    ----------
    vectors : array_like, shape (N, D)
        The searchable vectors, e.g. every exemplar neighbourhood flattened.
        float32 input is searched in float32, anything else in float64.
    weights : array_like, shape (D,), optional
        Non-negative per-dimension weights (Gaussian falloff, causal mask,
        channel weights); the distance is ``sum_d w_d (q_d - v_d)**2``.
        Dimensions of weight 0 are dropped before building the index.
    method : str
        ``"auto"`` or a registered backend: ``"exact"``, ``"kdtree"``,
        ``"tsvq"`` (see :data:`texsynth.core.search.METHODS`). ``"auto"``
        follows the ``profile``'s rule (or :func:`texsynth.core.search.use`).
    profile : str
        The named setting that decides ``"auto"`` and tunes the backends
        (:data:`texsynth.core.search.PROFILES`; default ``"default"``).
    queries : int, optional
        Expected number of queries, for profiles whose ``"auto"`` weighs it.
    memory_budget : int
        Bytes allowed for one block of brute-force distances (and for the
        temporary differences of the exact re-ranking). Default 256 MiB.
    rng : None, int or numpy.random.Generator
        Seeds the approximate backends' builds (PCA subsample, k-means).
        Same seed, same index, same answers.
    **options
        Tuning of the backend, over the profile's: ``n_components``,
        ``leaf_size``, ``n_candidates``, ``eps`` (kd-tree); ``leaf_size``,
        ``branching``, ``beams`` (TSVQ). Options of other backends are
        ignored, so one call can name the tuning of several.

    Attributes
    ----------
    n : int
        Number of indexed vectors.
    dim : int
        Their dimension ``D`` (before zero-weight dimensions are dropped).
    method : str
        The backend actually used (``"auto"`` is resolved).

    Raises
    ------
    ValueError, TypeError
        For vectors that are not a finite real 2-D array, weights of the
        wrong length, negative or all zero, an unknown ``method``,
        ``profile`` or option, or a ``memory_budget`` smaller than one row of
        distances.

    Notes
    -----
    Approximate backends only choose the candidates: the returned distances
    are always recomputed exactly in full dimension, so they are never smaller
    than the true nearest distance, and the exact backend returns the true k
    nearest neighbours. The recall of each backend against exact search is
    measured in ``benchmarks/bench_nearest.py`` (``docs/methods/search.md``).

    References
    ----------
    .. [1] L.-Y. Wei and M. Levoy, "Fast texture synthesis using
       tree-structured vector quantization", SIGGRAPH 2000.
       :doi:`10.1145/344779.345009`
    .. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization
       for example-based synthesis", SIGGRAPH 2005.
       :doi:`10.1145/1073204.1073263`

    Examples
    --------
    >>> v = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 2.0]])
    >>> index = PatchIndex(v)
    >>> index.method, index.n, index.dim
    ('exact', 3, 2)
    >>> idx, d2 = index.query([[0.9, 0.1]], k=2)
    >>> idx.tolist(), np.round(d2, 2).tolist()
    ([[1, 0]], [[0.02, 0.82]])
    >>> PatchIndex(v, weights=[1.0, 0.0]).query([[0.0, 2.0]])[0].tolist()
    [[0]]
    """

    def __init__(self, vectors, *, weights=None, method="auto", profile="default", queries=None,
                 memory_budget=DEFAULT_MEMORY_BUDGET, rng=None, **options):
        vectors = as_vectors(vectors, "vectors")
        self.n, self.dim = vectors.shape
        rule = check_profile(profile)
        memory_budget = check_positive_int(memory_budget, "memory_budget")
        options = _check_options(options)
        rng = as_rng(rng)

        self.weights = None
        self._keep = None
        if weights is not None:
            w = as_weights(weights, self.dim)
            self.weights = w
            keep = np.flatnonzero(w > 0)
            if keep.shape[0] < self.dim:
                self._keep = keep
                vectors = vectors[:, keep]
                w = w[keep]
            self._sqrt_w = np.sqrt(w).astype(vectors.dtype)
            vectors = vectors * self._sqrt_w

        self.method = resolve(method, self.n, vectors.shape[1], profile=profile, queries=queries)
        self.memory_budget = memory_budget
        backend = BACKENDS[self.method]
        tuning = {**rule.options.get(self.method, {}), **options}
        tuning = {k: v for k, v in tuning.items() if k in backend.options}
        self._backend = backend.build(vectors, memory_budget=memory_budget, rng=rng, **tuning)

    def __repr__(self):
        return f"PatchIndex(n={self.n}, dim={self.dim}, method={self.method!r})"

    def _prepare_queries(self, queries):
        q = as_vectors(queries, "queries")
        if q.shape[1] != self.dim:
            raise ValueError(
                f"queries have dimension {q.shape[1]} but the index holds vectors of "
                f"dimension {self.dim}; pass queries of shape (M, {self.dim})"
            )
        q = np.asarray(q, dtype=self._backend.vectors.dtype)
        if self._keep is not None:
            q = q[:, self._keep]
        if self.weights is not None:
            q = q * self._sqrt_w
        return np.ascontiguousarray(q)

    def query(self, queries, k=1):
        """The k nearest indexed vectors of each query.

        Parameters
        ----------
        queries : array_like, shape (M, D)
        k : int
            Neighbours per query, ``1 <= k <= n``.

        Returns
        -------
        indices : numpy.ndarray of int64, shape (M, k)
            Row indices into ``vectors``, nearest first (ties: lowest index).
        sq_distances : numpy.ndarray, shape (M, k)
            Their exact weighted squared distances, ascending.

        Raises
        ------
        ValueError, TypeError
            For queries of the wrong dimension or non-finite values, or
            ``k`` outside ``1..n``.
        """
        if not isinstance(k, numbers.Integral) or isinstance(k, bool):
            raise TypeError(f"k must be an integer >= 1, got {k!r}")
        if k < 1:
            raise ValueError(f"k must be >= 1, got {k}")
        if k > self.n:
            raise ValueError(f"k={k} but the index holds {self.n} vectors; pass k <= {self.n}")
        q = self._prepare_queries(queries)
        idx, d2 = self._backend.query(q, int(k))
        np.maximum(d2, 0.0, out=d2)
        return idx, d2


def nearest(vectors, queries, k=1, **kwargs):
    """One-shot search: ``PatchIndex(vectors, **kwargs).query(queries, k)``.

    Examples
    --------
    >>> idx, d2 = nearest([[0.0], [1.0], [3.0]], [[2.9], [0.4]])
    >>> idx.ravel().tolist()
    [2, 0]
    """
    return PatchIndex(vectors, **kwargs).query(queries, k)
