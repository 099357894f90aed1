"""Exact search: brute force by chunked BLAS, memory-bounded, with an exact tie-stable re-ranking.

Distances are ``||q||^2 - 2 q.v + ||v||^2`` one block of queries at a time
(``memory_budget`` bounds a block); every candidate within the rounding error
of the k-th best is re-scored by direct differences, so the answer is the true
k nearest with ties broken by the lowest index.

Also here: :class:`SequentialExact`, exact search for queries whose vector
becomes known in parts (scanline synthesis), :class:`SubsetExact`, for queries
known on a few recurring subsets of their dimensions (a tileable scanline
synthesis's wrapped windows), and :func:`nearest_candidates`, the nearest of
each query's own candidate list.
"""

from __future__ import annotations

import numpy as np

from ._common import best_k_of_pairs, pair_sq_distances
from ._registry import register

__all__ = ["exact_chunk_rows", "SequentialExact", "SubsetExact", "nearest_candidates", "candidate_sq_distances"]

# preferred size of one brute-force distance block (bytes), and fewest query rows
_CACHE_BLOCK = 16 * 2**20
_GEMM_ROWS = 256
# candidate_sq_distances scores blocks of at most this many values (queries x candidates x dims) in one
# gather; above, a column at a time (the gather of every candidate at once would take M K D values)
_SMALL_CANDIDATE_VALUES = 2**16


def exact_chunk_rows(n, itemsize, memory_budget):
    """Rows of queries per brute-force block so the block fits ``memory_budget``.

    One block holds, per query row, ``n`` distances, a partitioned copy of them
    (``2 * itemsize`` bytes each) and a boolean candidate mask (1 byte), so
    ``rows = memory_budget // (n * (2 * itemsize + 1))``.

    Raises
    ------
    ValueError
        If not even one row fits.

    Examples
    --------
    >>> exact_chunk_rows(1000, 8, 2**20)
    61
    """
    per_row = n * (2 * itemsize + 1)
    rows = memory_budget // per_row
    if rows < 1:
        raise ValueError(
            f"memory_budget={memory_budget} bytes is smaller than one row of distances to "
            f"{n} vectors ({per_row} bytes); pass memory_budget >= {per_row}"
        )
    return int(rows)


# Hand-written rather than scikit-learn's brute-force NearestNeighbors / pairwise_distances_argmin_min:
# benchmarks/bench_packages.py (50 176 x 147-D float32, 4 900 queries, the same run, equal thread
# counts) takes 1.19 s against 1.67 s for k = 1 on one thread (the scanline loops and the test
# workers run one) and the same 0.88 s on two; for k = 3 on two threads scikit-learn is faster
# (0.88 s against 1.18 s). scikit-learn ranks float32 input in float64; this backend ranks float32
# in float32 (the float64 truth differs for 0.04 % of queries, all within float32 rounding).
class Exact:
    """Chunked BLAS brute force with an exact, tie-stable re-ranking: the ``"exact"`` backend.

    Built by :class:`~texsynth.core.search.PatchIndex` (``method="exact"``);
    the TSVQ backend answers with it the queries whose leaves hold fewer than k vectors.
    """

    name = "exact"

    @classmethod
    def build(cls, vectors, *, memory_budget, rng):
        return cls(vectors, memory_budget)

    def __init__(self, vectors, memory_budget):
        self.vectors = vectors
        self.memory_budget = memory_budget
        self.sq_norms = np.einsum("ij,ij->i", vectors, vectors)
        rows = exact_chunk_rows(vectors.shape[0], vectors.itemsize, memory_budget)
        # blocks of ~16 MiB keep the passes after the GEMM in cache (measured:
        # 2.7x faster than 256 MiB blocks for N = 13000), but at least 256 query
        # rows so the GEMM reuses each vector it streams (N = 50000: 19-row
        # blocks 1.5x slower); memory_budget stays the upper bound
        per_row = vectors.shape[0] * (2 * vectors.itemsize + 1)
        self.rows = min(rows, max(_GEMM_ROWS, _CACHE_BLOCK // per_row))

    def query(self, queries, k):
        v = self.vectors
        n, dim = v.shape
        eps = np.finfo(v.dtype).eps
        max_norm = float(self.sq_norms.max())
        half_norms = 0.5 * self.sq_norms
        out_i = np.empty((queries.shape[0], k), dtype=np.int64)
        out_d = np.empty((queries.shape[0], k), dtype=v.dtype)
        for start in range(0, queries.shape[0], self.rows):
            q = queries[start : start + self.rows]
            q_norms = np.einsum("ij,ij->i", q, q)
            # ||q - v||^2 = ||q||^2 - 2 q.v + ||v||^2: per query row the ranking is
            # that of ||v||^2 / 2 - q.v, one GEMM and one pass per block
            block = q @ v.T
            np.subtract(half_norms[None, :], block, out=block)
            if k == 1:
                best = block.argmin(axis=1)
                kth = block[np.arange(len(q)), best]
            else:
                kth = np.partition(block, k - 1, axis=1)[:, k - 1]
            # the rounding error of that expression is below (dim + 2) eps (||q||^2 + ||v||^2) / 2;
            # keep every vector that could be within it of the k-th best, re-score exactly
            tol = (dim + 2) * eps * (q_norms + max_norm)
            near = block <= (kth + tol)[:, None]
            del block
            if k == 1:
                # most rows keep one vector, their argmin: only the others need the (slower) nonzero
                counts = np.count_nonzero(near, axis=1)
                alone, several = np.flatnonzero(counts == 1), np.flatnonzero(counts > 1)
                rows, cols = np.nonzero(near[several])
                rows, cols = np.concatenate([alone, several[rows]]), np.concatenate([best[alone], cols])
            else:
                rows, cols = np.nonzero(near)
            del near
            d2 = pair_sq_distances(q, v, rows, cols, self.memory_budget)
            out_i[start : start + len(q)], out_d[start : start + len(q)] = best_k_of_pairs(
                len(q), rows, cols, d2, k
            )
        return out_i, out_d


class SequentialExact:
    """Exact nearest neighbours of queries whose vectors become known in parts.

    Scanline synthesis (Wei & Levoy 2000) knows the first part of a pixel's
    neighbourhood (the rows above and the parent level) for a whole scanline
    at once, but the second part (the pixels left of it) only when the pixel
    is reached. :meth:`start` computes the first part's distances for a batch
    of queries with one matrix product; :meth:`distances` then adds the
    second part of one query, a small dot product. A further part (Wei's
    eq. 1 adds the pixel value) is ranked by :meth:`nearest_with`.

    Parameters
    ----------
    *parts : numpy.ndarray
        ``(N, D_i)`` arrays: the indexed vectors, split by columns into the
        parts in the order they become known.

    Examples
    --------
    >>> rng = np.random.default_rng(0)
    >>> first, second = rng.random((50, 6)), rng.random((50, 2))
    >>> index = SequentialExact(first, second)
    >>> q = np.concatenate([first[7], second[7]]) + 0.01
    >>> index.start(q[None, :6])
    >>> k, d2 = index.nearest(0, q[6:])
    >>> int(k), bool(np.isclose(d2, 8 * 0.01**2))
    (7, True)
    """

    def __init__(self, *parts):
        self.parts = [np.ascontiguousarray(p) for p in parts]
        self._t = [np.ascontiguousarray(p.T) for p in self.parts]
        self._sq = [np.einsum("nd,nd->n", p, p) for p in self.parts]
        self._base = None

    def __len__(self):
        return self.parts[0].shape[0]

    def start(self, queries):
        """Fix the first part for a batch of queries ``(M, D_0)`` (one matrix product)."""
        q = queries
        # ||q - e||^2 of the first part, plus ||e||^2 of the second (its -2 q.e + ||q||^2 come later)
        self._base = (np.einsum("wd,wd->w", q, q)[:, None] - 2.0 * (q @ self._t[0])) + (self._sq[0] + self._sq[1])

    def distances(self, j, query):
        """Squared distances of batch query ``j``, completed by its second part ``query``, to every vector."""
        return self._base[j] - 2.0 * (query @ self._t[1]) + query @ query

    def nearest(self, j, query):
        """The nearest vector to batch query ``j`` completed by ``query``: ``(index, squared distance)``
        (ties: the lowest index)."""
        d = self.distances(j, query)
        k = d.argmin()
        return k, d[k]

    def nearest_with(self, distances, part, query):
        """Index minimising ``distances + ||query - parts[part]||^2`` (ties: the lowest index)."""
        return int(((distances + self._sq[part]) - 2.0 * (query @ self._t[part])).argmin())


class SubsetExact:
    """Exact nearest neighbours of queries known on a subset of their dimensions, where few subsets recur.

    A pixel of a tileable scanline synthesis whose window wraps around the
    output knows only the window pixels synthesised before it (and the
    parent level): its query is known on a subset ``S`` of the dimensions,
    and the same few subsets recur along the wrap. The distance over ``S``,

    .. math:: \\|v_S - q_S\\|^2 = \\|v_S\\|^2 - 2 v \\cdot q_S + \\|q_S\\|^2,

    costs one matrix-vector product per query; ``||v_S||^2`` of every
    vector is computed once per subset and kept. (Weighted distances, or
    many different subsets in one batch: :class:`MaskedIndex`.)

    Parameters
    ----------
    vectors : numpy.ndarray
        ``(N, D)`` the indexed vectors.

    Examples
    --------
    >>> v = np.array([[0.0, 5.0], [1.0, 0.0], [3.0, 3.0]])
    >>> search = SubsetExact(v)
    >>> known = np.array([True, False])  # the second value of the query is unknown
    >>> k, d2 = search.nearest(np.array([0.9, 123.0]), known)
    >>> int(k), round(float(d2), 6)
    (1, 0.01)
    """

    def __init__(self, vectors):
        self.vectors = vectors
        self._squares = vectors**2
        self._norms = {}  # subset (as bytes) -> ||v_S||^2 of every vector

    def sq_distances(self, query, known):
        """``(N,)`` squared distances from ``query`` ``(D,)`` to every vector over the dimensions where the boolean
        ``known`` ``(D,)`` is True."""
        key = known.tobytes()
        norms = self._norms.get(key)
        if norms is None:
            norms = self._norms[key] = self._squares @ known
        q = query * known
        return norms - 2 * (self.vectors @ q) + q @ q

    def nearest(self, query, known):
        """The nearest vector over the ``known`` dimensions: ``(index, squared distance)`` (ties: the lowest
        index)."""
        d = self.sq_distances(query, known)
        k = int(d.argmin())
        return k, d[k]


def nearest_candidates(queries, pool, *, vectors=None, weights=None):
    """The nearest of each query's own candidates.

    Parameters
    ----------
    queries : numpy.ndarray
        ``(M, D)``.
    pool : numpy.ndarray
        Each query's own ``K`` candidates: ``(M, K)`` integer rows of
        ``vectors``, or ``(M, K, D)`` candidate vectors themselves.
    vectors : numpy.ndarray, optional
        ``(N, D)``, for integer candidates.
    weights : numpy.ndarray, optional
        ``(D,)`` per-dimension weights, or ``(M, D)`` one set per query
        (integer candidates only).

    Returns
    -------
    choice : numpy.ndarray of int
        ``(M,)`` position of the nearest candidate in each row (ties: the first).
    sq_distances : numpy.ndarray
        ``(M,)`` its weighted squared distance.

    Notes
    -----
    Integer candidates are scored by direct differences, one column at a
    time, each candidate once per row (a repeat scores ``inf``, so ties keep
    the first); candidate vectors (patches extracted on the fly, which nothing
    else stores) by ``||c||^2 - 2 c.q`` in one pass, ``||q||^2`` added to the
    winner only.

    Examples
    --------
    >>> v = np.array([[0.0], [1.0], [5.0]])
    >>> nearest_candidates(np.array([[4.0], [0.2]]), np.array([[0, 2], [2, 1]]), vectors=v)
    (array([1, 1]), array([1.  , 0.64]))
    """
    pool = np.asarray(pool)
    rows = np.arange(queries.shape[0])
    if pool.ndim == 3:
        c = pool if weights is None else pool * np.sqrt(weights)
        q = queries if weights is None else queries * np.sqrt(weights)
        score = np.einsum("nkd,nkd->nk", c, c) - 2 * np.einsum("nkd,nd->nk", c, q)
        choice = np.argmin(score, axis=1)
        return choice, score[rows, choice] + np.einsum("nd,nd->n", q, q)
    scores = candidate_sq_distances(queries, pool, vectors, weights)
    choice = np.argmin(scores, axis=1)
    return choice, scores[rows, choice]


def candidate_sq_distances(queries, pool, vectors, weights=None):
    """Weighted squared distances ``(M, K)`` from each query to each of its own candidates (rows of
    ``vectors``); a candidate repeated in its row is scored once, its repeats ``inf``.

    The scoring of :func:`nearest_candidates` (same arguments), for callers
    that weigh the distances with other terms before choosing (Wei's eq. 1 of
    a mixture).

    Examples
    --------
    >>> v = np.array([[0.0], [1.0], [5.0]])
    >>> candidate_sq_distances(np.array([[4.0]]), np.array([[0, 2, 0]]), v)
    array([[16.,  1., inf]])
    """
    pool = np.asarray(pool)
    dims = vectors.shape[1]
    w = np.ones(dims, vectors.dtype) if weights is None else weights
    spec = "ij,ij,ij->i" if w.ndim == 2 else "ij,ij,j->i"
    scores = np.full(pool.shape, np.inf, dtype=np.result_type(vectors, queries, w))
    rows = np.arange(queries.shape[0])
    if pool.size * dims <= _SMALL_CANDIDATE_VALUES:  # few queries (one at a time): all columns at once
        order = np.argsort(pool, axis=1, kind="stable")
        ranked = np.take_along_axis(pool, order, axis=1)
        first = np.ones(pool.shape, dtype=bool)
        np.put_along_axis(first, order[:, 1:], ranked[:, 1:] != ranked[:, :-1], axis=1)
        r, j = np.nonzero(first)
        d = vectors[pool[r, j]] - queries[r]
        scores[r, j] = np.einsum(spec, d, d, w if w.ndim == 1 else w[r])
        return scores
    for j in range(pool.shape[1]):
        # a candidate repeated in its row (coherent candidates often agree) is scored once
        r = rows if j == 0 else np.flatnonzero(np.all(pool[:, j, None] != pool[:, :j], axis=1))
        d = vectors[pool[r, j]] - queries[r]
        scores[r, j] = np.einsum(spec, d, d, w if w.ndim == 1 else w[r])
    return scores


register("exact", Exact.build, summary="brute force by chunked BLAS, memory-bounded, exact re-ranking")
