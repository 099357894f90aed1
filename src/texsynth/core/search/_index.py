"""Nearest-neighbour search over patch vectors: one interface, several backends.

Every neighbourhood-matching algorithm of texsynth (Wei-Levoy pixel synthesis,
Kwatra texture optimization, Ruiters interpolation, the copy-detection
metrics) asks the same question: *which exemplar neighbourhood is closest to
this one?*  This module answers it once.

>>> rng = np.random.default_rng(0)
>>> vectors = rng.random((200, 12))
>>> index = PatchIndex(vectors, method="exact")
>>> idx, d2 = index.query(vectors[:3] + 0.001, k=2)
>>> idx[:, 0].tolist()
[0, 1, 2]

Distances are (weighted) squared Euclidean distances

.. math::  d(q, v) = \\sum_d w_d (q_d - v_d)^2,

implemented by scaling both sides by :math:`\\sqrt{w}` once, so every backend
works on plain Euclidean vectors. Whatever the backend, the returned distances
are the exact full-dimension distances of the returned candidates, sorted
ascending, ties broken by the lowest vector index.

Backends
--------
``"exact"``
    Brute force by chunked BLAS, :math:`\\|q\\|^2 - 2 q\\cdot v + \\|v\\|^2`,
    memory-bounded by ``memory_budget``; candidates within the rounding error
    of the k-th best are re-scored by direct differences, so the answer is the
    true k nearest with deterministic tie-breaking.
``"kdtree"``
    PCA to a few dimensions (from the scatter matrix up to 256-D, by
    randomized subspace iteration on a subsample above, so 3072-D patches
    cost well under a second), :class:`scipy.spatial.cKDTree` for a short
    list of candidates, re-ranked by exact distance (the approximate search of
    Kwatra et al. 2005, Section 3, and Wei & Levoy 2000, Section 4.2).
``"tsvq"``
    Tree-structured vector quantization: hierarchical k-means, greedy
    (or beam) descent, exact search in the leaf (Wei & Levoy 2000, Section 4).
``"auto"``
    ``"exact"`` for small problems, ``"kdtree"`` otherwise (see
    :class:`PatchIndex`).

References
----------
.. [1] L.-Y. Wei and M. Levoy, "Fast texture synthesis using tree-structured
   vector quantization", SIGGRAPH 2000, pp. 479-488.
   :doi:`10.1145/344779.345009`
.. [2] V. Kwatra, I. Essa, A. Bobick and N. Kwatra, "Texture optimization for
   example-based synthesis", ACM TOG 24(3), 2005, pp. 795-802.
   :doi:`10.1145/1073204.1073263`
"""

from __future__ import annotations

import numbers

import numpy as np

from .._validate import as_rng, check_positive_float, check_positive_int

__all__ = ["PatchIndex", "nearest", "METHODS"]

#: Valid values of ``method``.
METHODS = ("auto", "exact", "kdtree", "tsvq")

# "auto" picks "exact" up to N vectors and "kdtree" above, N depending on the
# dimension: the measured crossover of build + query time
# (benchmarks/bench_nearest.py --crossover, M = N / 2 queries) is N ~ 2000 for
# 27-D and ~5000 for 147-D patches (brute force costs N * D per query, the PCA
# kd-tree little more in high D); interpolated linearly between, clamped outside.
_AUTO_CROSSOVER_DIMS = (27, 147)
_AUTO_CROSSOVER_N = (2_000, 5_000)


def _auto_method(n, dim):
    """``"exact"`` below the measured crossover size for this dimension, else ``"kdtree"``."""
    return "exact" if n <= np.interp(dim, _AUTO_CROSSOVER_DIMS, _AUTO_CROSSOVER_N) else "kdtree"

_DEFAULT_MEMORY_BUDGET = 256 * 2**20
# preferred size of one brute-force distance block (bytes), and fewest query rows
_CACHE_BLOCK = 16 * 2**20
_GEMM_ROWS = 256
# TSVQ defaults of Kwatra et al. 2005, Sec. 3: k-means with k = 4 per node,
# leaves below 1 % of the vectors (but at least this many)
_TSVQ_BRANCHING = 4
_TSVQ_MIN_LEAF = 16
# Lloyd iterations per tree node of the TSVQ build
_LLOYD_ITERATIONS = 5


# --------------------------------------------------------------------------- #
# validation helpers
# --------------------------------------------------------------------------- #
def _as_vectors(array, name):
    """2-D finite real array -> float32 (kept) or float64, C-contiguous."""
    arr = np.asarray(array)
    if arr.dtype == object or not (
        np.issubdtype(arr.dtype, np.number) or arr.dtype == np.bool_
    ) or np.issubdtype(arr.dtype, np.complexfloating):
        raise TypeError(
            f"{name} has dtype {arr.dtype}; pass a real numeric array (float, int or bool)"
        )
    if arr.ndim != 2:
        hint = f" (a single vector: {name}.reshape(1, -1))" if arr.ndim == 1 else ""
        raise ValueError(
            f"{name} must be a 2-D array (number of vectors, dimension), got shape {arr.shape}{hint}"
        )
    if arr.size == 0:
        raise ValueError(f"{name} is empty (shape {arr.shape}); pass at least one vector of dimension >= 1")
    dtype = np.float32 if arr.dtype == np.float32 else np.float64
    arr = np.ascontiguousarray(arr, dtype=dtype)
    if not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values; replace them (e.g. np.nan_to_num) first")
    return arr


def _as_weights(weights, dim):
    w = np.asarray(weights, dtype=np.float64)
    if w.ndim != 1 or w.shape[0] != dim:
        raise ValueError(
            f"weights must be a 1-D array of length {dim} (one per vector dimension), "
            f"got shape {w.shape}; flatten a patch mask with mask.ravel()"
        )
    if not np.all(np.isfinite(w)):
        raise ValueError("weights contains NaN or infinite values; pass finite non-negative weights")
    if np.any(w < 0):
        raise ValueError(f"weights must be non-negative, got minimum {w.min():.4g}")
    if not np.any(w > 0):
        raise ValueError("weights are all zero, so every distance would be 0; give at least one dimension a positive weight")
    return w


def _optional_int(value, name, minimum=1):
    return None if value is None else check_positive_int(value, name, minimum)


# --------------------------------------------------------------------------- #
# shared pieces of every backend
# --------------------------------------------------------------------------- #
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


def _pair_sq_distances(queries, vectors, rows, cols, memory_budget):
    """Exact ``||queries[rows] - vectors[cols]||^2`` by direct differences."""
    out = np.empty(rows.shape[0], dtype=vectors.dtype)
    # small blocks stay in cache (measured 5x faster than one large block)
    step = max(1, min(4096, memory_budget // (2 * vectors.shape[1] * vectors.itemsize)))
    for start in range(0, rows.shape[0], step):
        sl = slice(start, start + step)
        diff = queries[rows[sl]]
        diff -= vectors[cols[sl]]
        diff *= diff
        out[sl] = diff.sum(axis=1)
    return out


def _best_k_of_pairs(n_rows, rows, cols, d2, k):
    """Per row, the k pairs of smallest distance (ties: lowest column).

    Every row must have at least k pairs.
    """
    order = np.lexsort((cols, d2, rows))
    counts = np.bincount(rows, minlength=n_rows)
    starts = np.cumsum(counts) - counts
    take = order[(starts[:, None] + np.arange(k)[None, :]).ravel()]
    return cols[take].reshape(n_rows, k).astype(np.int64), d2[take].reshape(n_rows, k)


# --------------------------------------------------------------------------- #
# backends
# --------------------------------------------------------------------------- #
class _Exact:
    """Chunked BLAS brute force with an exact, tie-stable re-ranking."""

    name = "exact"

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
                kth = block.min(axis=1)
            else:
                kth = np.partition(block, k - 1, axis=1)[:, k - 1]
            # the rounding error of that expression is below (dim + 2) eps (||q||^2 + ||v||^2) / 2;
            # keep every vector that could be within it of the k-th best, re-score exactly
            tol = (dim + 2) * eps * (q_norms + max_norm)
            rows, cols = np.nonzero(block <= (kth + tol)[:, None])
            del block
            d2 = _pair_sq_distances(q, v, rows, cols, self.memory_budget)
            out_i[start : start + len(q)], out_d[start : start + len(q)] = _best_k_of_pairs(
                len(q), rows, cols, d2, k
            )
        return out_i, out_d


class _KDTree:
    """PCA projection + cKDTree candidates + exact re-ranking."""

    name = "kdtree"

    def __init__(self, vectors, n_components, leaf_size, candidates, eps, memory_budget, rng):
        from scipy.spatial import cKDTree

        self.eps = eps
        self.vectors = vectors
        self.memory_budget = memory_budget
        self.candidates = candidates
        n, dim = vectors.shape
        # PCA on a subsample (seeded) for large N
        sample = vectors
        rows = min(_PCA_SAMPLE, max(_PCA_MAX + _PCA_OVERSAMPLES, _PCA_SAMPLE_VALUES // dim))
        if n > rows:
            sample = vectors[np.sort(rng.choice(n, rows, replace=False))]
        self.mean = sample.mean(axis=0)
        s, vt, total = _pca(sample - self.mean, n_components or _PCA_MAX, rng)
        if n_components is None:
            n_components = _default_components(s, dim, total)
        self.n_components = int(min(n_components, vt.shape[0]))
        self.basis = np.ascontiguousarray(vt[: self.n_components].T)
        self.tree = cKDTree(self._project(vectors), leafsize=leaf_size, balanced_tree=False)

    def _project(self, x):
        return (x - self.mean) @ self.basis

    def query(self, queries, k):
        n = self.vectors.shape[0]
        kk = min(n, self.candidates if self.candidates is not None else max(2 * k, _KD_CANDIDATES))
        kk = max(kk, k)
        # (1 + eps)-approximate tree search (Arya et al. 1998) in the PCA space
        _, cand = self.tree.query(self._project(queries), k=kk, eps=self.eps)
        cand = np.asarray(cand, dtype=np.int64).reshape(queries.shape[0], kk)
        m = queries.shape[0]
        rows = np.repeat(np.arange(m), kk)
        cols = cand.ravel()
        d2 = _pair_sq_distances(queries, self.vectors, rows, cols, self.memory_budget)
        return _best_k_of_pairs(m, rows, cols, d2, k)


class _TSVQ:
    """Tree-structured vector quantization (Wei & Levoy 2000, Section 4).

    The tree is built by hierarchical k-means ("generalised Lloyd" on each
    node's vectors, ``branching`` codewords per node) until a node holds at
    most ``leaf_size`` vectors. Each node owns a contiguous range of the
    permutation ``self.order``, so a leaf's vectors are ``order[start:end]``.
    A query descends to the nearest child codeword level by level (keeping the
    ``beams`` best nodes per level; 1 is the greedy descent of the paper), then
    the vectors of the reached leaves are searched exactly.
    """

    name = "tsvq"

    def __init__(self, vectors, leaf_size, branching, beams, memory_budget, rng):
        self.vectors = vectors
        self.memory_budget = memory_budget
        self.beams = beams
        self.leaf_size = leaf_size
        self._exact = None
        self.sq_norms = np.einsum("ij,ij->i", vectors, vectors)
        n = vectors.shape[0]
        order = np.arange(n)
        centers, starts, ends, kids = [vectors.mean(axis=0)], [0], [n], [[]]
        stack = [0]
        while stack:  # one Python step per tree node, vectorised inside
            node = stack.pop()
            s, e = starts[node], ends[node]
            if e - s <= leaf_size:
                continue
            members = order[s:e]
            labels, codewords = _lloyd(vectors[members], branching, rng)
            counts = np.bincount(labels, minlength=len(codewords))
            if np.count_nonzero(counts) < 2:  # Lloyd collapsed: split evenly
                labels = np.arange(e - s) * branching // (e - s)
                counts = np.bincount(labels, minlength=len(codewords))
            perm = np.argsort(labels, kind="stable")
            order[s:e] = members[perm]
            bounds = s + np.concatenate(([0], np.cumsum(counts)))
            for c in np.flatnonzero(counts):
                kids[node].append(len(centers))
                stack.append(len(centers))
                centers.append(codewords[c])
                starts.append(int(bounds[c]))
                ends.append(int(bounds[c + 1]))
                kids.append([])
        self.order = order
        self.centers = np.asarray(centers, dtype=vectors.dtype)
        self.center_norms = np.einsum("ij,ij->i", self.centers, self.centers)
        self.starts = np.asarray(starts, dtype=np.int64)
        self.ends = np.asarray(ends, dtype=np.int64)
        width = max(1, max(len(c) for c in kids))
        self.children = np.full((len(centers), width), -1, dtype=np.int64)
        self.is_leaf = np.array([len(c) == 0 for c in kids])
        for node, c in enumerate(kids):
            # a leaf is its own only child, so descents of unequal depth line up
            self.children[node, : max(1, len(c))] = c if c else [node]
        self.depth = _tree_depth(kids)

    def _descend(self, queries, q_norms):
        """Leaf nodes reached by each query, shape (M, beams), -1 where none.

        Level by level, the (query, node) pairs of all queries are grouped by
        node and each group is scored against that node's child codewords with
        one matrix product; each query keeps its ``beams`` best children.
        """
        m = queries.shape[0]
        width = self.children.shape[1]
        beam = np.zeros((m, 1), dtype=np.int64)  # every query starts at the root
        for _ in range(self.depth):
            alive = beam >= 0
            if np.all(self.is_leaf[beam[alive]]):
                break
            nb = beam.shape[1]
            dist = np.full((m, nb * width), np.inf)
            cand = np.full((m, nb * width), -1, dtype=np.int64)
            flat = beam.ravel()
            pairs = np.flatnonzero(flat >= 0)
            pairs = pairs[np.argsort(flat[pairs], kind="stable")]
            nodes, first = np.unique(flat[pairs], return_index=True)
            for node, group in zip(nodes, np.split(pairs, first[1:])):
                kids = self.children[node]
                kids = kids[kids >= 0]
                qi, slot = np.divmod(group, nb)
                cols = slot[:, None] * width + np.arange(kids.shape[0])
                # ||q - c||^2 for the child codewords c of this node
                d = q_norms[qi, None] - 2.0 * (queries[qi] @ self.centers[kids].T) + self.center_norms[kids]
                dist[qi[:, None], cols] = d
                cand[qi[:, None], cols] = kids
            keep = min(self.beams, dist.shape[1])
            sel = np.argsort(dist, axis=1, kind="stable")[:, :keep]
            beam = np.take_along_axis(cand, sel, axis=1)
        return beam

    def query(self, queries, k):
        m = queries.shape[0]
        q_norms = np.einsum("ij,ij->i", queries, queries)
        leaves = self._descend(queries, q_norms)
        # exact search inside each reached leaf, grouped by leaf (one product each):
        # each (query, leaf) pair contributes its k best vectors as candidates
        flat = leaves.ravel()
        pairs = np.flatnonzero(flat >= 0)
        pairs = pairs[np.argsort(flat[pairs], kind="stable")]
        cand = np.full((pairs.shape[0], k), -1, dtype=np.int64)
        nodes, first = np.unique(flat[pairs], return_index=True)
        for j, (leaf, start) in enumerate(zip(nodes, first)):
            stop = first[j + 1] if j + 1 < len(first) else pairs.shape[0]
            qi = pairs[start:stop] // leaves.shape[1]
            members = self.order[self.starts[leaf] : self.ends[leaf]]
            # ||v||^2 - 2 q.v ranks the leaf's vectors like ||q - v||^2
            d = self.sq_norms[members][None, :] - 2.0 * (queries[qi] @ self.vectors[members].T)
            kk = min(k, members.shape[0])
            best = np.argpartition(d, kk - 1, axis=1)[:, :kk] if kk < members.shape[0] else np.arange(kk)[None, :]
            cand[start:stop, :kk] = members[best]
        rows = np.repeat(pairs // leaves.shape[1], k)
        cols = cand.ravel()
        ok = cols >= 0
        rows, cols = rows[ok], cols[ok]
        short = np.bincount(rows, minlength=m) < k  # reached leaves hold < k vectors
        keep = ~short[rows]
        rows, cols = rows[keep], cols[keep]
        d2 = _pair_sq_distances(queries, self.vectors, rows, cols, self.memory_budget)
        out_i = np.empty((m, k), dtype=np.int64)
        out_d = np.empty((m, k), dtype=self.vectors.dtype)
        full = np.flatnonzero(~short)
        remap = np.cumsum(~short) - 1  # row number among the non-short queries
        out_i[full], out_d[full] = _best_k_of_pairs(len(full), remap[rows], cols, d2, k)
        if np.any(short):
            if self._exact is None:
                self._exact = _Exact(self.vectors, self.memory_budget)
            out_i[short], out_d[short] = self._exact.query(queries[short], k)
        return out_i, out_d


def _tree_depth(kids):
    depth = np.zeros(len(kids), dtype=np.int64)
    for node, c in enumerate(kids):  # children always have larger ids than parents
        for child in c:
            depth[child] = depth[node] + 1
    return int(depth.max()) + 1


def _lloyd(x, n_clusters, rng, n_iter=_LLOYD_ITERATIONS):
    """k-means++ seeding then a few Lloyd iterations; returns (labels, codewords).

    If the vectors cannot be separated (all identical), they are split into
    ``n_clusters`` equal runs so the tree still shrinks.
    """
    n = x.shape[0]
    x_norms = np.einsum("ij,ij->i", x, x)
    # k-means++ seeding (Arthur & Vassilvitskii 2007)
    chosen = [int(rng.integers(n))]
    d2 = np.maximum(x_norms - 2.0 * x @ x[chosen[0]] + x_norms[chosen[0]], 0.0)
    for _ in range(1, n_clusters):
        total = d2.sum()
        if not total > 0:
            break
        i = int(np.searchsorted(np.cumsum(d2), rng.random() * total, side="right"))
        i = min(i, n - 1)
        chosen.append(i)
        d2 = np.minimum(d2, np.maximum(x_norms - 2.0 * x @ x[i] + x_norms[i], 0.0))
    centers = x[chosen].astype(x.dtype, copy=True)
    if centers.shape[0] < 2:  # identical vectors: split evenly, codewords all equal
        labels = np.arange(n) * n_clusters // n
        return labels, np.repeat(centers[:1], n_clusters, axis=0)
    for _ in range(n_iter):
        d = x_norms[:, None] - 2.0 * x @ centers.T + np.einsum("ij,ij->i", centers, centers)[None, :]
        labels = np.argmin(d, axis=1)
        counts = np.bincount(labels, minlength=centers.shape[0])
        onehot = np.zeros((centers.shape[0], n), dtype=x.dtype)
        onehot[labels, np.arange(n)] = 1.0
        sums = onehot @ x
        nonempty = counts > 0
        centers[nonempty] = sums[nonempty] / counts[nonempty, None]
    return labels, centers


# default kd-tree candidates re-ranked exactly (with k=1, recall@1 on real
# 147-D patches: 5 -> 0.89, 16 -> 0.98, 32 -> 0.99; see the benchmark)
_KD_CANDIDATES = 16
# default approximation factor of the kd-tree search: with eps = 1 the tree
# query is ~6x faster on 50000 grey 7x7 patches, recall@1 1.000 -> 0.988
_KD_EPS = 1.0
# PCA basis from at most this many vectors (SVD cost ~ sample * D^2).
_PCA_SAMPLE = 20_000
# PCA from the D x D scatter matrix up to this dimension, randomized above (see _pca)
_PCA_COVARIANCE_MAX_DIM = 256
_PCA_OVERSAMPLES = 10
_PCA_POWER_ITERATIONS = 1
# relative eigenvalue below which a Gram direction counts as empty (~10 float32 eps)
_GRAM_RTOL = 1e-6
# PCA sample at most this many values (rows x D): 1365 rows of 3072-D patches; measured
# on real 32x32 colour patches, 1 power iteration and 2^22 values keep kd-tree recall@1
# within 0.01 of 3 iterations on 2^24 values (0.90 vs 0.90) at a third of the build time
_PCA_SAMPLE_VALUES = 2**22
# default PCA dimension: enough for this fraction of the variance, within the bounds
_PCA_VARIANCE = 0.98
_PCA_MIN, _PCA_MAX = 8, 24


def _pca(centred, n_components, rng):
    """Leading singular values and right singular vectors of ``centred``, and its total variance.

    Up to ``_PCA_COVARIANCE_MAX_DIM`` dimensions: eigen-decomposition of the
    D x D scatter matrix (one GEMM, cost ~ n D^2, then D^3 for ``eigh``).
    Above it (large patches, e.g. 32 x 32 x 3 = 3072-D, where a full SVD of a
    9409-row sample took ~20-40 s on the 2-core VM): randomized subspace
    iteration for the ``n_components`` leading components (Halko, Martinsson
    & Tropp 2011, Algorithm 4.4: Gaussian test matrix with
    ``_PCA_OVERSAMPLES`` extra columns, ``_PCA_POWER_ITERATIONS`` QR-stabilised
    power iterations; cost ~ n D (n_components + oversamples) per pass,
    0.1-0.5 s). ``total`` is the sum of all squared singular values (the
    squared Frobenius norm), so the variance fraction of the leading
    components is known without computing the others.
    """
    n, dim = centred.shape
    total = float(np.einsum("ij,ij->", centred, centred, dtype=np.float64))
    rank = min(n, dim)
    if dim <= _PCA_COVARIANCE_MAX_DIM:
        scatter = (centred.T @ centred).astype(np.float64)
        ev, evec = np.linalg.eigh(scatter)  # ascending
        s = np.sqrt(np.maximum(ev[::-1][:rank], 0.0))
        return s, evec[:, ::-1][:, :rank].T, total
    k = min(n_components + _PCA_OVERSAMPLES, rank)
    basis = _orthonormal(centred @ rng.standard_normal((dim, k)).astype(centred.dtype))
    for _ in range(_PCA_POWER_ITERATIONS):
        basis = _orthonormal(centred @ _orthonormal(centred.T @ basis))
    # SVD of the small k x D projection B = Q^T X through its k x k Gram matrix
    b = basis.T @ centred
    ev, u = np.linalg.eigh((b @ b.T).astype(np.float64))
    ev, u = ev[::-1], u[:, ::-1]
    keep = ev > ev[0] * _GRAM_RTOL
    s = np.sqrt(ev[keep])
    vt = (u[:, keep].T @ b.astype(np.float64)) / s[:, None]
    return s[:n_components], vt[:n_components].astype(centred.dtype), total


def _orthonormal(y):
    """Orthonormal basis of the columns of a tall ``y`` through its small Gram matrix.

    Equivalent to the Q of a QR decomposition up to a rotation (all the
    randomized range finder needs); columns whose variance falls below
    ``_GRAM_RTOL`` of the largest are dropped. Chosen over ``numpy.linalg.qr``
    because LAPACK's threaded Householder QR of a 5461 x 34 float32 matrix
    took 0.4-0.7 s on the loaded 2-core VM (0.01-0.03 s idle), while the Gram
    route is one GEMM and a 34 x 34 eigen-decomposition.
    """
    ev, evec = np.linalg.eigh((y.T @ y).astype(np.float64))
    keep = ev > ev[-1] * _GRAM_RTOL
    return y @ (evec[:, keep] / np.sqrt(ev[keep])).astype(y.dtype)


def _default_components(singular_values, dim, total=None):
    """Fewest components explaining ``_PCA_VARIANCE`` of ``total`` (default: of the given values)."""
    var = np.asarray(singular_values, dtype=np.float64) ** 2
    if total is None:
        total = var.sum()
    if total <= 0:
        return 1
    m = int(np.searchsorted(np.cumsum(var) / total, _PCA_VARIANCE) + 1)
    return int(min(dim, max(min(_PCA_MIN, dim), min(m, _PCA_MAX))))


# --------------------------------------------------------------------------- #
# public interface
# --------------------------------------------------------------------------- #
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
    method : {"auto", "exact", "kdtree", "tsvq"}
        Search backend; see Notes.
    n_components : int, optional
        ``"kdtree"`` only: PCA dimension. Default: the fewest components that
        explain 98 % of the variance, kept within [8, 24] (and <= D). The
        PCA uses at most 20 000 vectors and 2**22 values (a seeded
        subsample): an exact eigen-decomposition of the scatter matrix up to
        D = 256, a randomized one (Halko et al. 2011, one power iteration)
        above, whose explained-variance fraction is taken against the exact
        total variance.
    leaf_size : int, optional
        ``"kdtree"``: cKDTree leaf size (default 16). ``"tsvq"``: largest leaf
        of the vector-quantization tree; default ``max(16, ceil(N / 100))``,
        the 1 % of Kwatra et al. [2]_, Section 3.
    branching : int, optional
        ``"tsvq"`` only: children (k-means clusters) per tree node; default 4
        as in Kwatra et al. [2]_, Section 3.
    candidates : int, optional
        ``"kdtree"`` only: candidates fetched from the tree and re-ranked
        exactly. Default ``max(2 k, 16)``.
    eps : float, optional
        ``"kdtree"`` only: approximation factor of the tree search (the
        ``eps`` of :meth:`scipy.spatial.cKDTree.query`: candidates are within
        ``1 + eps`` times the true k-th distance in the PCA space). Default
        1.0; 0 searches the tree exactly (slower in 20+ PCA dimensions).
    beams : int, optional
        ``"tsvq"`` only: nodes kept per tree level during the descent. The
        default 1 is the greedy descent of Wei & Levoy [1]_; 4 roughly
        doubles recall@1 for about twice the query time (see Notes).
    memory_budget : int
        Bytes allowed for one block of brute-force distances (and for the
        temporary differences of the exact re-ranking). Default 256 MiB.
    rng : None, int or numpy.random.Generator
        Seeds the PCA subsample and the k-means of the tree builds. Same seed,
        same index, same answers.

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
        wrong length, negative or all zero, an unknown ``method`` or a
        ``memory_budget`` smaller than one row of distances.

    Notes
    -----
    Approximate backends only choose the candidates: the returned distances
    are always recomputed exactly in full dimension, so they are never smaller
    than the true nearest distance, and the exact backend returns the true k
    nearest neighbours.

    Measured on real 7x7 patches (benchmarks/bench_nearest.py and
    tests/test_nearest.py; 5 000-50 000 indexed vectors of 49-D grey and
    147-D colour patches, queries from another image region; recall@1 =
    fraction of queries given their exact nearest neighbour, distance ratio =
    mean returned / exact squared distance):

    ========================  ===========  ===============
    backend                   recall@1     distance ratio
    ========================  ===========  ===============
    exact                     1            1
    kdtree (default)          0.94 - 1.0   1.000 - 1.003
    kdtree, eps=0             0.98 - 1.0   1.000 - 1.001
    tsvq (greedy, default)    0.30 - 0.69  1.06 - 1.35
    tsvq, beams=4             0.67 - 0.94  1.01 - 1.05
    random index (baseline)   ~1 / N       6.5 - 94
    ========================  ===========  ===============

    ``"auto"`` picks by size and dimension: ``"exact"`` when ``N`` is at most
    the measured crossover of build + query time with ``M = N / 2`` queries,
    2000 for ``D <= 27`` rising linearly to 5000 for ``D >= 147`` (2-core VM),
    and ``"kdtree"`` above; below the crossover the exact answer costs no more
    than the approximate one. For many calls with
    a handful of queries each (scanline synthesis), build once and pick the
    backend explicitly.

    TSVQ: each node's vectors are clustered by k-means (k-means++ seeding
    and 5 Lloyd iterations, the generalised Lloyd algorithm of Wei & Levoy
    [1]_, Section 4) into ``branching`` children, recursively, until a node
    holds at most ``leaf_size`` vectors; a query follows the nearest child
    codeword down to a leaf and searches the leaf exactly.

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

    def __init__(
        self,
        vectors,
        *,
        weights=None,
        method="auto",
        n_components=None,
        leaf_size=None,
        branching=None,
        candidates=None,
        beams=None,
        eps=None,
        memory_budget=_DEFAULT_MEMORY_BUDGET,
        rng=None,
    ):
        vectors = _as_vectors(vectors, "vectors")
        self.n, self.dim = vectors.shape
        if not isinstance(method, str) or method not in METHODS:
            raise ValueError(f"method must be one of {', '.join(map(repr, METHODS))}, got {method!r}")
        memory_budget = check_positive_int(memory_budget, "memory_budget")
        n_components = _optional_int(n_components, "n_components")
        leaf_size = _optional_int(leaf_size, "leaf_size")
        branching = _optional_int(branching, "branching", 2)
        candidates = _optional_int(candidates, "candidates")
        beams = _optional_int(beams, "beams")
        if eps is not None:
            eps = check_positive_float(eps, "eps", allow_zero=True)
        rng = as_rng(rng)

        self.weights = None
        self._keep = None
        if weights is not None:
            w = _as_weights(weights, self.dim)
            self.weights = w
            keep = np.flatnonzero(w > 0)
            if keep.shape[0] < self.dim:
                self._keep = keep
                vectors = vectors[:, keep]
                w = w[keep]
            self._sqrt_w = np.sqrt(w).astype(vectors.dtype)
            vectors = vectors * self._sqrt_w
        if n_components is not None and n_components > vectors.shape[1]:
            raise ValueError(
                f"n_components={n_components} exceeds the vector dimension "
                f"{vectors.shape[1]} (after dropping zero weights); pass n_components <= {vectors.shape[1]}"
            )

        if method == "auto":
            method = _auto_method(self.n, vectors.shape[1])
        self.method = method
        self.memory_budget = memory_budget
        if method == "exact":
            self._backend = _Exact(vectors, memory_budget)
        elif method == "kdtree":
            self._backend = _KDTree(
                vectors, n_components, leaf_size or 16, candidates,
                _KD_EPS if eps is None else eps, memory_budget, rng,
            )
        else:
            if leaf_size is None:  # Kwatra et al. 2005, Sec. 3: stop below 1 % of the vectors
                leaf_size = max(_TSVQ_MIN_LEAF, -(-self.n // 100))
            self._backend = _TSVQ(
                vectors, leaf_size, branching or _TSVQ_BRANCHING, beams or 1, memory_budget, rng
            )

    def __repr__(self):
        return f"PatchIndex(n={self.n}, dim={self.dim}, method={self.method!r})"

    def _prepare_queries(self, queries):
        q = _as_vectors(queries, "queries")
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
