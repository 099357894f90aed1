"""Tree-structured vector quantization (Wei & Levoy 2000, Section 4; Kwatra et al. 2005, Section 3).

The vectors are clustered by k-means into ``branching`` children per node,
recursively, until a node holds at most ``leaf_size`` vectors; a query follows
the nearest child codeword down to a leaf (keeping the ``beams`` best nodes per
level; 1 is the greedy descent of the paper) and searches the reached leaves
exactly.

Options: ``leaf_size`` (default ``max(16, ceil(N / 100))``, the 1 % of Kwatra
et al.), ``branching`` (default 4, as Kwatra et al.), ``beams`` (default 1).
"""

from __future__ import annotations

import numpy as np

from ._common import best_k_of_pairs, pair_sq_distances
from ._exact import Exact
from ._registry import register

# TSVQ defaults of Kwatra et al. 2005, Sec. 3: k-means with k = 4 per node,
# leaves below 1 % of the vectors (but at least this many)
_TSVQ_BRANCHING = 4
_TSVQ_MIN_LEAF = 16
# Lloyd iterations per tree node of the TSVQ build
_LLOYD_ITERATIONS = 5


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

    @classmethod
    def build(cls, vectors, *, memory_budget, rng, leaf_size=None, branching=None, beams=None):
        if leaf_size is None:  # Kwatra et al. 2005, Sec. 3: stop below 1 % of the vectors
            leaf_size = max(_TSVQ_MIN_LEAF, -(-vectors.shape[0] // 100))
        return cls(vectors, leaf_size, branching or _TSVQ_BRANCHING, beams or 1, memory_budget, rng)

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
            if np.count_nonzero(counts) < 2:
                # Lloyd collapsed (near-duplicate vectors, whose float32 distances tie): split
                # evenly into `branching` runs, each with its mean as codeword (k-means++ may
                # have seeded fewer than `branching` codewords)
                labels = np.arange(e - s) * branching // (e - s)
                counts = np.bincount(labels, minlength=branching)
                codewords = np.stack([vectors[members[labels == c]].mean(axis=0) for c in range(branching)])
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
        d2 = pair_sq_distances(queries, self.vectors, rows, cols, self.memory_budget)
        out_i = np.empty((m, k), dtype=np.int64)
        out_d = np.empty((m, k), dtype=self.vectors.dtype)
        full = np.flatnonzero(~short)
        remap = np.cumsum(~short) - 1  # row number among the non-short queries
        out_i[full], out_d[full] = best_k_of_pairs(len(full), remap[rows], cols, d2, k)
        if np.any(short):
            if self._exact is None:
                self._exact = Exact(self.vectors, self.memory_budget)
            out_i[short], out_d[short] = self._exact.query(queries[short], k)
        return out_i, out_d


def _tree_depth(kids):
    depth = np.zeros(len(kids), dtype=np.int64)
    for node, c in enumerate(kids):  # children always have larger ids than parents
        for child in c:
            depth[child] = depth[node] + 1
    return int(depth.max()) + 1


# Hand-written rather than scikit-learn's KMeans: benchmarks/bench_packages.py (50 176 colour 7x7
# neighbourhoods, the same run) builds the tree in 0.23 s with it against 0.35 s with KMeans
# (n_init=1, max_iter=5; recall@1 0.58 against our 0.56) and 0.44 s with MiniBatchKMeans (0.61).
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


register("tsvq", _TSVQ.build, options=("leaf_size", "branching", "beams"),
         summary="tree-structured vector quantization (hierarchical k-means)")
